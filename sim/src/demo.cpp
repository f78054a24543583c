#include "acuity/sim/demo.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>

#include "acuity/bake/chains.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "acuity/sim/generators.hpp"
#include "text.hpp"

namespace acuity::sim {
namespace {

namespace fs = std::filesystem;
// The folder, under <cache>/profiles, of the profiles that keep each view's own measurement.
constexpr const char* kOwnViews = "own-views";

// lodgen's options for the demo's chains: levels down to 1/16 of level 0 at o.ratio (5 at 0.5),
// creases at 45 degrees (or every edge, flat).
lodgen::ChainOptions chain_options(const DemoOptions& o) {
  lodgen::ChainOptions c;
  c.ratio = o.ratio;
  c.levels = 1 + static_cast<std::size_t>(std::lround(std::log(1.0 / 16) / std::log(o.ratio)));
  if (o.flat) c.decimate.crease_degrees = 0;
  return c;
}

// lodgen's chain of one demo mesh, or the one an earlier run cached as <cache>/<name>.glb.
lodgen::LodObject chain_for(const DemoMesh& mesh, const DemoOptions& o,
                            const std::function<void(const std::string&)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path glb = fs::path(o.cache) / (mesh.name + ".glb");
  bool cached = false;
  lodgen::LodObject obj = bake::cached_chain(mesh.path, glb.string(), chain_options(o), &cached);
  obj.name = mesh.name;
  std::string line;
  if (cached)
    appendf(&line, "  %-15s LOD chain cached in %s\n", mesh.name.c_str(), glb.string().c_str());
  else
    appendf(&line, "  %-15s lodgen: %zu -> %zu triangles in %zu levels, %.1f s\n", mesh.name.c_str(),
            obj.chain.levels.front().mesh.triangle_count(), obj.chain.levels.back().mesh.triangle_count(),
            obj.chain.levels.size(),
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  progress(line);
  return obj;
}

}  // namespace

DemoScene build_demo(const DemoOptions& o, const std::function<void(const std::string&)>& progress) {
  const std::vector<DemoMesh> meshes = demo_meshes(o.meshes, o.assimp_models, o.webxr_profiles);
  std::vector<std::string> names;
  for (const DemoMesh& m : meshes) {
    names.push_back(m.name);
    names.push_back(m.name + "-clusters");  // a large object's hierarchy profile (sim/large_object.hpp)
    names.push_back(std::string(kOwnViews) + "/" + m.name);  // its profile without cell bounds
  }
  if (!(o.ratio > 0.0 && o.ratio < 1.0))
    throw std::runtime_error("demo: the chain's ratio must lie in (0, 1)");
  const std::string settings = "profile pixels " + std::to_string(o.pixels) +
                               (o.flat ? ", flat-shaded" : "") +
                               (o.ratio != 0.5 ? ", ratio " + std::to_string(o.ratio) : "");
  if (!bake::refresh_cache(o.cache, names, settings))
    progress("(" + o.cache + ": cached chains and profiles of another version or settings removed)\n");
  DemoScene out;
  out.sim = o.sim;
  if (out.sim.output.empty()) out.sim.output = (fs::path(o.cache) / "simulate").string();
  progress(std::string("acuity demo: seven real meshes") + (o.flat ? " flat-shaded" : "") +
           ", a field of 64 objects, an eye-tracked fly-through\n\nlodgen:\n");
  std::vector<lodgen::LodObject> objects;
  for (const DemoMesh& m : meshes) {
    objects.push_back(chain_for(m, o, progress));
    if (m.third_party) out.sim.third_party.push_back(m.name);
  }
  out.scene_path = (fs::path(o.cache) / "field.glb").string();
  lodgen::write_lod_gltf(out.scene_path, objects, {}, {}, demo_field(objects, o.sim.seed));
  std::string scene;
  appendf(&scene, "scene:\n  %s: 64 instances of %zu LOD chains (MSFT_lod)\nprofile:\n",
          out.scene_path.c_str(), objects.size());
  progress(scene);
  bake::AssetOptions ao;
  ao.profiles = out.profiles = (fs::path(o.cache) / "profiles").string();
  ao.profile_pixels = o.pixels;
  out.assets = bake::load_scene_assets(out.scene_path, ao);
  if (o.own_view_profiles) {
    progress("profile, each view's own measurement (no cell bounds):\n");
    ao.profiles = (fs::path(out.profiles) / kOwnViews).string();
    ao.bound_cells = false;
    out.own_views = bake::load_scene_assets(out.scene_path, ao);
  }
  return out;
}

}  // namespace acuity::sim
