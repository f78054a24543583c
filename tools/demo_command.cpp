// `acuity demo`: the whole system on its embedded default (sim::build_demo assembles the field; this
// runs it and prints).
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "acuity/sim/demo.hpp"
#include "acuity/sim/sampled.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

struct DemoCommand {
  sim::DemoOptions demo;
  std::uint32_t sampled = 0;  // > 0: that many sampled decisions instead of the fly-through
  bool large_object = true;   // the fly-through's gaze over a large object: object rule vs cluster cut
};

void run(const DemoCommand& o, const std::string& program) {
  const auto start = std::chrono::steady_clock::now();
  sim::DemoOptions demo = o.demo;
  demo.own_view_profiles = o.sampled > 0;  // the sampled margins price the cell bounds with them
  const sim::DemoScene scene =
      sim::build_demo(demo, [](const std::string& text) { std::fputs(text.c_str(), stdout); });
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  if (o.sampled > 0) {
    sim::SampleOptions sampled;
    sampled.count = o.sampled;
    sampled.seed = o.demo.sim.seed;
    sampled.model = o.demo.sim.model;
    std::printf("\nsampled decisions: %u, judged by rendering each at its exact view\n", o.sampled);
    const sim::SampledRun run = sim::run_sampled(*scene.assets, sampled, scene.own_views.get());
    std::printf("the perceptual rule: %s\n",
                sim::perceptual_text(run.perceptual, scene.assets->assets[0].profile).c_str());
    std::printf("\n%s\nacuity demo finished in %.1f s.\n", sim::sampled_text(*scene.assets, run).c_str(),
                seconds());
    return;
  }
  const sim::SimulationOptions& so = scene.sim;
  std::printf("\nsimulate: %.0f s at %.0f Hz, fixations, saccades, pursuit of %u moving objects, blinks\n",
              so.seconds, so.fps, so.movers);
  sim::LargeObjectOptions large;
  large.profiles = scene.profiles;
  large.pixels = o.demo.pixels;  // --res, as the field's profiles (the cache's stamp names it)
  const RunResult result = run_simulation(*scene.assets, so, true, o.large_object ? &large : nullptr);
  std::printf("\nacuity demo finished in %.1f s.\n", seconds());
  if (result.example.object >= 0)
    std::printf(
        "Why the object looked at in frame %zu got its level:\n  %s explain %s --profiles %s --seconds %g "
        "--seed %u --frame %zu --object %s\n",
        result.example.frame, program.c_str(), scene.scene_path.c_str(), scene.profiles.c_str(), so.seconds,
        so.seed, result.example.frame,
        scene.assets->instances[std::size_t(result.example.object)].name.c_str());
}

}  // namespace

void add_demo_command(CLI::App& app, const std::string& program) {
  auto o = std::make_shared<DemoCommand>();
  sim::DemoOptions& d = o->demo;
  d.meshes = ACUITY_DEMO_MESHES;
  d.assimp_models = ACUITY_DEMO_ASSIMP_MODELS;
  d.webxr_profiles = ACUITY_DEMO_WEBXR_PROFILES;
  d.cache = ACUITY_DEMO_CACHE;
  CLI::App* cmd =
      app.add_subcommand("demo", "The whole system on its embedded default scene (the README's main job)");
  cmd->add_option("--meshes", d.meshes, "Directory of libcgal-demo meshes")->capture_default_str();
  cmd->add_option("--cache", d.cache,
                  "Where LOD chains and profiles are kept between runs (with --flat and no --cache: this "
                  "folder's name + '-flat')")
      ->capture_default_str();
  cmd->add_option("-o,--output", d.sim.output,
                  "Directory for CSV, plots and frame images (default: CACHE/simulate)");
  add_number(cmd, "--seconds", d.sim.seconds, "Length of the fly-through", 0.1, 600.0);
  cmd->add_option("--seed", d.sim.seed, "Layout and gaze seed")->capture_default_str();
  cmd->add_option("--validate", d.sim.validate, "Decisions judged by render-and-analyze")
      ->capture_default_str();
  cmd->add_option("--sampled", o->sampled,
                  "Instead of the fly-through, this many decisions sampled over size, eccentricity and "
                  "retinal speed (docs/demo.md), each judged")
      ->check(CLI::Range(1u, 100000u));
  add_model_option(cmd, d.sim.model);
  cmd->add_flag(
      "!--no-large-object", o->large_object,
      "Leave out the large object spanning the gaze (one demo mesh as a cluster hierarchy: the object "
      "rule against the cluster cut, judged)");
  cmd->add_flag("--flat", d.flat,
                "Flat-shaded chains and profiles (every edge a crease), as an engine drawing faceted "
                "meshes shows them, kept apart from the smooth ones");
  cmd->add_option("--res", d.pixels, "Snapshot pixels of the profiles")->capture_default_str();
  add_number(
      cmd, "--ratio", d.ratio,
      "Triangles of each level over the previous; the chains span 1/16 of the finest whatever the step "
      "(0.5: 5 levels, 0.707: 9); with no --cache, the cache folder's name + '-ratio-' + the ratio",
      0.3, 0.9);
  cmd->callback([o, cmd, program] {
    if (o->demo.flat && cmd->count("--cache") == 0) o->demo.cache += "-flat";  // never over the smooth cache
    if (o->demo.ratio != 0.5 && cmd->count("--cache") == 0) {  // nor over the halving chains' cache
      char suffix[32];
      std::snprintf(suffix, sizeof suffix, "-ratio-%g", o->demo.ratio);
      o->demo.cache += suffix;
    }
    run(*o, program);
  });
}

}  // namespace acuity::tools
