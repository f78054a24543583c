#pragma once
// The built-in generators of a run: a head path through the scene, objects moving on circles, and
// a gaze trace over them. Deterministic for a seed. Units as in acuity/scheduler.hpp: metres,
// degrees, seconds; the head looks along its local -Z with +Y up.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "acuity/lodgen/gltf.hpp"
#include "acuity/sim/scene.hpp"
#include "acuity/sim/tracks.hpp"

namespace acuity::sim {

// An object that moves on a horizontal circle (so gaze can pursue it).
struct Mover {
  std::uint32_t instance = 0;
  glm::dvec3 centre{0.0};
  double radius = 1, speed = 1, phase = 0;  // [m], [m/s], [rad]
  glm::dvec3 position(double t) const;
};

// The built-in generators. A fly-through walks the long horizontal axis of the scene's bounds at
// eye height 1.6 m with a slow yaw sway; the gaze fixates objects in view (200-450 ms), moves
// between them by saccades on the main sequence (21 ms + 2.2 ms/deg, cosine velocity profile),
// pursues movers (0.6-1.5 s) and blinks every 2-6 s (150 ms, confidence 0).
std::vector<HeadPose> flythrough(const SceneAssets& scene, double seconds, double fps);
std::vector<Mover> choose_movers(const SceneAssets& scene, std::uint32_t count, unsigned seed);
struct GeneratedGaze {
  std::vector<GazeSample> samples;
  std::vector<GazePhase> phases;
  std::vector<std::int32_t> targets;  // instance looked at, -1 none
};
GeneratedGaze generate_gaze(const SceneAssets& scene, const std::vector<HeadPose>& head,
                            const std::vector<Mover>& movers, double fps, unsigned seed);

// A mesh of the demo's field: its name (the asset's), its file, and whether it is third-party
// content (SimulationOptions::third_party: the summary reports its instances apart).
struct DemoMesh {
  std::string name, path;
  std::string package;  // what installs the file (scripts/bootstrap.sh deps installs each)
  bool third_party = false;
};
// The demo's meshes: elephant, camel, cow and fandisk (OFF in `cgal_meshes`: Debian's libcgal-demo),
// then three nobody here wrote: assimp's Wuson (`assimp_models`/OFF/Wuson.off: Debian's
// assimp-testmodels) and two controllers of npm @webxr-input-profiles/assets (`webxr_profiles`/
// generic-hand/left.glb and google-daydream/none.glb; installed by scripts/bootstrap.sh deps).
// Throws std::runtime_error naming the first missing file and what installs it.
std::vector<DemoMesh> demo_meshes(const std::string& cgal_meshes, const std::string& assimp_models,
                                  const std::string& webxr_profiles);

// The demo's field (after Guenter et al.'s test scene): 64 instances of `objects` (cycled, at
// least one) on an 8 x 8 grid 3 m apart, each scaled to a 1.5 m bounding sphere, resting on the
// ground (y = 0) 4 to 25 m ahead (-Z), with a random turn about +Y from `seed`.
std::vector<lodgen::LodInstance> demo_field(const std::vector<lodgen::LodObject>& objects, unsigned seed);

}  // namespace acuity::sim
