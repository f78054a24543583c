// `acuity demo`: the whole system on its embedded default. Seven real meshes (sim::demo_meshes) go
// through lodgen (cached), are laid out as a field of 64 objects like Guenter et al.'s test scene (a
// glTF with MSFT_lod levels, instanced), get profiles (cached), and the field is simulated: a
// fly-through with eye-tracked gaze, four rules, decisions judged by render-and-analyze.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "acuity/bake/chains.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "acuity/sim/generators.hpp"
#include "acuity/sim/sampled.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

namespace fs = std::filesystem;
using sim::SimulationOptions;

struct DemoOptions {
  std::string meshes = ACUITY_DEMO_MESHES, cache = ACUITY_DEMO_CACHE;
  SimulationOptions sim;
  std::uint32_t pixels = 256;
  std::uint32_t sampled = 0;  // > 0: that many sampled decisions instead of the fly-through
  bool flat = false;          // every level flat-shaded (every edge a crease), as a faceted engine draws
};

// lodgen's options for the demo's chains: 5 levels, creases at 45 degrees (or every edge, flat).
lodgen::ChainOptions chain_options(const DemoOptions& o) {
  lodgen::ChainOptions c;
  c.levels = 5;
  if (o.flat) c.decimate.crease_degrees = 0;
  return c;
}

// lodgen's chain of one demo mesh (5 levels), or the one an earlier run cached as <cache>/<name>.glb.
lodgen::LodObject chain_for(const sim::DemoMesh& mesh, const DemoOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path glb = fs::path(o.cache) / (mesh.name + ".glb");
  bool cached = false;
  lodgen::LodObject obj = bake::cached_chain(mesh.path, glb.string(), chain_options(o), &cached);
  obj.name = mesh.name;
  if (cached) {
    std::printf("  %-15s LOD chain cached in %s\n", mesh.name.c_str(), glb.string().c_str());
  } else {
    std::printf("  %-15s lodgen: %zu -> %zu triangles in %zu levels, %.1f s\n", mesh.name.c_str(),
                obj.chain.levels.front().mesh.triangle_count(), obj.chain.levels.back().mesh.triangle_count(),
                obj.chain.levels.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return obj;
}

void run(const DemoOptions& o) {
  const std::vector<sim::DemoMesh> meshes =
      sim::demo_meshes(o.meshes, ACUITY_DEMO_ASSIMP_MODELS, ACUITY_DEMO_WEBXR_PROFILES);
  std::vector<std::string> names;
  for (const sim::DemoMesh& m : meshes) names.push_back(m.name);
  const std::string settings = "profile pixels " + std::to_string(o.pixels) + (o.flat ? ", flat-shaded" : "");
  if (!bake::refresh_cache(o.cache, names, settings))
    std::printf("(%s: cached chains and profiles of another version or settings removed)\n", o.cache.c_str());
  SimulationOptions so = o.sim;
  if (so.output.empty()) so.output = (fs::path(o.cache) / "simulate").string();
  const auto start = std::chrono::steady_clock::now();
  std::printf(
      "acuity demo: seven real meshes%s, a field of 64 objects, an eye-tracked fly-through\n\nlodgen:\n",
      o.flat ? " flat-shaded" : "");
  std::vector<lodgen::LodObject> objects;
  for (const sim::DemoMesh& m : meshes) {
    objects.push_back(chain_for(m, o));
    if (m.third_party) so.third_party.push_back(m.name);
  }
  const std::string scene_path = (fs::path(o.cache) / "field.glb").string();
  lodgen::write_lod_gltf(scene_path, objects, {}, {}, sim::demo_field(objects, o.sim.seed));
  std::printf("scene:\n  %s: 64 instances of %zu LOD chains (MSFT_lod)\nprofile:\n", scene_path.c_str(),
              objects.size());
  AssetOptions ao;
  ao.profiles = (fs::path(o.cache) / "profiles").string();
  ao.profile_pixels = o.pixels;
  const std::unique_ptr<SceneAssets> scene = load_scene_assets(scene_path, ao);
  if (o.sampled > 0) {
    sim::SampleOptions sampled;
    sampled.count = o.sampled;
    sampled.seed = o.sim.seed;
    std::printf("\nsampled decisions: %u, judged by rendering each at its exact view\n", o.sampled);
    const sim::SampledRun run = sim::run_sampled(*scene, sampled);
    std::printf("\n%s\nacuity demo finished in %.1f s.\n", sim::sampled_text(*scene, run).c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return;
  }
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
  cmd->add_option("--cache", o->cache,
                  "Where LOD chains and profiles are kept between runs (with --flat and no --cache: this "
                  "folder's name + '-flat')")
      ->capture_default_str();
  cmd->add_option("-o,--output", o->sim.output,
                  "Directory for CSV, plots and frame images (default: CACHE/simulate)");
  add_number(cmd, "--seconds", o->sim.seconds, "Length of the fly-through", 0.1, 600.0);
  cmd->add_option("--seed", o->sim.seed, "Layout and gaze seed")->capture_default_str();
  cmd->add_option("--validate", o->sim.validate, "Decisions judged by render-and-analyze")
      ->capture_default_str();
  cmd->add_option("--sampled", o->sampled,
                  "Instead of the fly-through, this many decisions sampled over size, eccentricity and "
                  "retinal speed (docs/demo.md), each judged")
      ->check(CLI::Range(1u, 100000u));
  cmd->add_flag("--flat", o->flat,
                "Flat-shaded chains and profiles (every edge a crease), as an engine drawing faceted "
                "meshes shows them, kept apart from the smooth ones");
  cmd->add_option("--res", o->pixels, "Snapshot pixels of the profiles")->capture_default_str();
  cmd->callback([o, cmd] {
    if (o->flat && cmd->count("--cache") == 0) o->cache += "-flat";  // never over the smooth cache
    run(*o);
  });
}

}  // namespace acuity::tools
