// `acuity demo`: the whole system on its embedded default. Four real meshes (Debian's
// libcgal-demo) go through lodgen (cached), are laid out as a field of 64 objects like Guenter et
// al.'s test scene (a glTF with MSFT_lod levels, instanced), get profiles (cached), and the field is
// simulated: a fly-through with eye-tracked gaze, four rules, decisions judged by render-and-analyze.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "acuity/bake/chains.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

namespace fs = std::filesystem;
using sim::SimulationOptions;
constexpr double kPi = 3.14159265358979323846;

struct DemoOptions {
  std::string meshes = ACUITY_DEMO_MESHES, cache = ACUITY_DEMO_CACHE;
  SimulationOptions sim;
  std::uint32_t pixels = 256;
};

// lodgen's chain for one mesh, or the one an earlier run cached as <cache>/<name>.glb.
lodgen::LodObject chain_for(const std::string& name, const DemoOptions& o) {
  const fs::path glb = fs::path(o.cache) / (name + ".glb");
  lodgen::LodObject obj;
  obj.name = name;
  if (fs::exists(glb)) {
    obj.chain = bake::read_chain_file(glb.string()).chain;
    std::printf("  %-10s LOD chain cached in %s\n", name.c_str(), glb.string().c_str());
    return obj;
  }
  const auto t0 = std::chrono::steady_clock::now();
  bake::ChainRequest request;
  request.input = (fs::path(o.meshes) / (name + ".off")).string();
  request.chain.levels = 5;
  obj = std::move(bake::build_scene_chains(request).objects.at(0));
  lodgen::write_lod_gltf(glb.string(), {obj}, {});
  std::printf("  %-10s lodgen: %zu -> %zu triangles in %zu levels, %.1f s\n", name.c_str(),
              obj.chain.levels.front().mesh.triangle_count(), obj.chain.levels.back().mesh.triangle_count(),
              obj.chain.levels.size(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return obj;
}

// The field: 8 x 8 objects 3 m apart resting on the ground, each scaled to a 1.5 m bounding
// sphere, with a random turn about the vertical.
std::vector<lodgen::LodInstance> field(const std::vector<lodgen::LodObject>& objects, unsigned seed) {
  struct Bounds {
    double centre[3], scale;
  };  // bounding-box centre, scale to a 0.75 m radius
  std::vector<Bounds> bounds;
  for (const lodgen::LodObject& obj : objects) {
    const lodgen::Mesh& m = obj.chain.levels[0].mesh;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (std::size_t v = 0; v < m.vertex_count(); ++v)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], double(m.positions[3 * v + std::size_t(k)]));
        hi[k] = std::max(hi[k], double(m.positions[3 * v + std::size_t(k)]));
      }
    bounds.push_back({{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])},
                      0.75 / (0.5 * lodgen::diameter(m))});
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<lodgen::LodInstance> out;
  for (int i = 0; i < 64; ++i) {
    const Bounds& b = bounds[std::size_t(i % 4)];
    const double s = b.scale, yaw = unit(rng) * 2 * kPi, c = std::cos(yaw), sn = std::sin(yaw);
    const double target[3] = {(i % 8 - 3.5) * 3.0, 0.75,
                              -(4.0 + (i / 8) * 3.0)};  // where the box centre goes
    lodgen::LodInstance in;
    in.object = i % 4;
    in.name = objects[std::size_t(i % 4)].name + "_" + std::to_string(i);
    in.matrix = {s * c, 0, -s * sn, 0, 0, s, 0, 0, s * sn, 0, s * c, 0, 0, 0, 0, 1};
    const double rb[3] = {s * (c * b.centre[0] + sn * b.centre[2]), s * b.centre[1],
                          s * (-sn * b.centre[0] + c * b.centre[2])};
    for (int k = 0; k < 3; ++k) in.matrix[std::size_t(12 + k)] = target[k] - rb[k];
    out.push_back(in);
  }
  return out;
}

void run(const DemoOptions& o) {
  if (!fs::exists(fs::path(o.meshes) / "elephant.off"))
    throw std::runtime_error("demo meshes not found in " + o.meshes +
                             " (install libcgal-demo and build with tests)");
  fs::create_directories(o.cache);
  SimulationOptions so = o.sim;
  if (so.output.empty()) so.output = (fs::path(o.cache) / "simulate").string();
  const auto start = std::chrono::steady_clock::now();
  std::printf(
      "acuity demo: four real meshes, a field of 64 objects, an eye-tracked fly-through\n\nlodgen:\n");
  std::vector<lodgen::LodObject> objects;
  for (const char* name : {"elephant", "camel", "cow", "fandisk"}) objects.push_back(chain_for(name, o));
  const std::string scene_path = (fs::path(o.cache) / "field.glb").string();
  lodgen::write_lod_gltf(scene_path, objects, {}, {}, field(objects, o.sim.seed));
  std::printf("scene:\n  %s: 64 instances of 4 LOD chains (MSFT_lod)\nprofile:\n", scene_path.c_str());
  AssetOptions ao;
  ao.profiles = (fs::path(o.cache) / "profiles").string();
  ao.profile_pixels = o.pixels;
  const std::unique_ptr<SceneAssets> scene = load_scene_assets(scene_path, ao);
  std::printf("\nsimulate: %.0f s at %.0f Hz, fixations, saccades, pursuit of %u moving objects, blinks\n",
              o.sim.seconds, o.sim.fps, o.sim.movers);
  const RunResult result = run_simulation(*scene, so, true);
  std::printf("\nacuity demo finished in %.1f s.\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (result.example.object >= 0) {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    std::printf(
        "Why the object looked at in frame %zu got its level:\n  %s explain %s --profiles %s --seconds %g "
        "--seed %u --frame %zu --object %s\n",
        result.example.frame, ec ? "acuity" : self.string().c_str(), scene_path.c_str(), ao.profiles.c_str(),
        so.seconds, so.seed, result.example.frame,
        scene->instances[std::size_t(result.example.object)].name.c_str());
  }
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto o = std::make_shared<DemoOptions>();
  CLI::App* cmd =
      app.add_subcommand("demo", "The whole system on its embedded default scene (the README's main job)");
  cmd->add_option("--meshes", o->meshes, "Directory of libcgal-demo meshes")->capture_default_str();
  cmd->add_option("--cache", o->cache, "Where LOD chains and profiles are kept between runs")
      ->capture_default_str();
  cmd->add_option("-o,--output", o->sim.output,
                  "Directory for CSV, plots and frame images (default: CACHE/simulate)");
  cmd->add_option("--seconds", o->sim.seconds, "Length of the fly-through")
      ->capture_default_str()
      ->check(Finite)
      ->check(CLI::Range(0.1, 600.0));
  cmd->add_option("--seed", o->sim.seed, "Layout and gaze seed")->capture_default_str();
  cmd->add_option("--validate", o->sim.validate, "Decisions judged by render-and-analyze")
      ->capture_default_str();
  cmd->add_option("--res", o->pixels, "Snapshot pixels of the profiles")->capture_default_str();
  cmd->callback([o] { run(*o); });
}

}  // namespace acuity::tools
