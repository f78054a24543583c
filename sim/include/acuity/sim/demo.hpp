#pragma once
// acuity/sim/demo.hpp — the assembly of `acuity demo`, the README's main job: the seven demo meshes
// (demo_meshes) go through lodgen (chains cached), are laid out as a field of 64 objects like
// Guenter et al.'s test scene (a glTF with MSFT_lod levels, instanced: demo_field), and get profiles
// (cached); what is left is the run, simulate() or run_sampled(), which the command calls.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "acuity/sim/scene.hpp"
#include "acuity/sim/simulation.hpp"

namespace acuity::sim {

struct DemoOptions {
  // Where the meshes are (demo_meshes): Debian's libcgal-demo OFF files, Debian's
  // assimp-testmodels, npm @webxr-input-profiles/assets' profiles folder.
  std::string meshes, assimp_models, webxr_profiles;
  // Where chains (<cache>/<name>.glb), profiles (<cache>/profiles, the large object's
  // <name>-clusters.acuity among them) and the field (<cache>/field.glb) are kept between runs, under
  // a stamp of the code and settings (bake::refresh_cache): a stamp that differs removes them all.
  std::string cache;
  std::uint32_t pixels = 256;  // snapshot pixels of the profiles
  bool flat = false;           // every level flat-shaded (every edge a crease), as a faceted engine draws
  // Triangles of each level over the previous, in (0, 1); the chain spans the same 1/16 of level 0's
  // triangles whatever the step (0.5: 5 levels; 0.707: 9), so that steps compare over one range.
  double ratio = 0.5;
  // Also profiles that store each view's own measurement, not the largest loss over its cell
  // (<cache>/profiles/own-views; `acuity demo --sampled` prices the cell bounds with them).
  bool own_view_profiles = false;
  SimulationOptions sim;  // the run; sim.seed also lays out the field
};

// The demo's field, ready to run.
struct DemoScene {
  std::string scene_path;  // <cache>/field.glb
  std::string profiles;    // <cache>/profiles
  // The run's options: DemoOptions::sim with the output folder defaulted to <cache>/simulate and
  // the third-party meshes listed (SimulationOptions::third_party).
  SimulationOptions sim;
  std::unique_ptr<SceneAssets> assets;
  std::unique_ptr<SceneAssets> own_views;  // with own_view_profiles: the same assets, views unbounded
};

// Builds (or finds in the cache) every chain, the field and the profiles. `progress` receives the
// text of each step as it is done (the cache's state, a line per chain, the field), for the command
// to print; load_scene_assets prints the profiles' lines itself. Throws std::runtime_error naming a
// missing mesh and what installs it, io::Error when the cache cannot be written.
DemoScene build_demo(const DemoOptions& options, const std::function<void(const std::string&)>& progress);

}  // namespace acuity::sim
