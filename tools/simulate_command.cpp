// `acuity simulate SCENE` and `acuity explain SCENE --frame F --object NAME`: a glTF scene along a
// head path with a gaze trace (given or generated), four rules per frame (acuity/sim/simulation.hpp).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "acuity/file.hpp"
#include "acuity/sim/run.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

using sim::Simulation;
using sim::SimulationOptions;

struct SimulateOptions {
  std::string scene;
  AssetOptions assets;
  SimulationOptions sim;
  bool plot_hint = true;
  std::size_t frame = 0;
  std::string object;
  std::string large_object;  // an asset drawn large as a cluster hierarchy; empty: none
};

// The plot script: next to the sources in a build tree, in share/acuity when installed.
std::string plot_script() {
  for (const char* p : {ACUITY_PLOT_SCRIPT_SOURCE, ACUITY_PLOT_SCRIPT_INSTALLED})
    if (std::filesystem::exists(p)) return p;
  return "plot_simulation.py";
}

// The options simulate and explain share.
void add_scene_options(CLI::App* cmd, SimulateOptions* o) {
  cmd->add_option("scene", o->scene,
                  "glTF/GLB scene (nodes with MSFT_lod levels, or plain meshes lodgen will chain)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--asset-root", o->assets.asset_root,
                  "Folder the glTF's uris may read from (default: the glTF's own folder)");
  cmd->add_option("--profiles", o->assets.profiles,
                  "Directory of <mesh>.acuity profiles: used when they match, else built and saved there");
  cmd->add_option("--res", o->assets.profile_pixels, "Snapshot pixels of profiles built here")
      ->capture_default_str();
  cmd->add_option("--head", o->sim.head_file,
                  "Head path, CSV or JSON: t,x,y,z,qx,qy,qz,qw (default: a fly-through)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--gaze", o->sim.gaze_file,
                  "Gaze trace, CSV or JSON: t,x,y,z[,confidence] in head space (default: generated)")
      ->check(CLI::ExistingFile);
  add_number(cmd, "--seconds", o->sim.seconds, "Length of the run", 0.01, 3600.0);
  add_number(cmd, "--fps", o->sim.fps, "Frame rate", 1.0, 1000.0);
  cmd->add_option("--seed", o->sim.seed, "Seed of the generators and of the judged sample")
      ->capture_default_str();
  cmd->add_option("--movers", o->sim.movers, "Objects moving on circles (pursuit targets)")
      ->capture_default_str();
  add_number(cmd, "--viewport", o->sim.viewport, "Pixels across each eye's square viewport", 16u, 16384u);
  add_number(cmd, "--fov", o->sim.fov_deg, "Each eye's field of view [deg]", 10.0f, 170.0f);
  cmd->add_option("--saccade-speed", o->sim.saccade_speed,
                  "Gaze speed above which a frame is a saccade [deg/s]")
      ->capture_default_str()
      ->check(Finite)
      ->check(CLI::NonNegativeNumber);
  add_evaluation_option(cmd, o->sim.evaluation,
                        "The perceptual rule's thresholds, conservative tables or the exact evaluation");
  add_model_option(cmd, o->sim.model);
}

void simulate(const SimulateOptions& o) {
  io::check_output_folder(o.sim.output);  // before any work
  io::check_output_folder(o.assets.profiles);
  std::printf("acuity simulate %s\nassets:\n", o.scene.c_str());
  const std::unique_ptr<SceneAssets> scene = load_scene_assets(o.scene, o.assets);
  sim::LargeObjectOptions large;
  large.asset = o.large_object;
  large.profiles = o.assets.profiles;
  large.pixels = o.assets.profile_pixels;
  if (!large.asset.empty()) sim::large_object_asset(*scene, large.asset, "--large-object");  // before the run
  run_simulation(*scene, o.sim, o.plot_hint, large.asset.empty() ? nullptr : &large);
}

void explain(const SimulateOptions& o) {
  AssetOptions quiet = o.assets;
  quiet.quiet = true;
  const std::unique_ptr<SceneAssets> scene = load_scene_assets(o.scene, quiet);
  std::fputs(sim::explain_frame(*scene, o.sim, o.frame, o.object).c_str(), stdout);
}

}  // namespace

RunResult run_simulation(const SceneAssets& scene, const SimulationOptions& options, bool plot_hint,
                         const sim::LargeObjectOptions* large) {
  const sim::Run run = sim::simulate(scene, options);
  const Simulation& sim = *run.simulation;
  std::printf(
      "\nsimulated %zu frames x %zu rule settings in %.1f s; judged %zu decisions by render-and-analyze in "
      "%.1f s\n",
      sim.frame_count(), sim.rules().size(), run.simulate_seconds, run.judged.size(), run.judge_seconds);
  std::printf(
      "the perceptual rule: %s\n",
      sim::perceptual_text(sim.rule("perceptual").scheduler->config(), scene.assets[0].profile).c_str());
  std::fputs(sim::summary_text(sim, run.results).c_str(), stdout);
  if (large) {
    // Its profile's line (made once, then cached) goes to stderr: it would land inside the summary,
    // which docs/demo.md holds verbatim, only on a first run.
    const sim::LargeObjectRun r =
        sim::run_large_object(sim, *large, [](const std::string& text) { std::fputs(text.c_str(), stderr); });
    std::fputs(sim::large_object_text(r, *large).c_str(), stdout);
  }
  if (!options.output.empty())
    std::fputs(
        sim::outputs_text(run.results, run.written, options.output, plot_hint ? plot_script() : "").c_str(),
        stdout);
  return {run.written, sim::example_decision(sim)};
}

void add_simulate_commands(CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Run a scene along a head path and gaze trace through four LOD rules (and ungated)");
  add_scene_options(cmd, o.get());
  cmd->add_option("-o,--output", o->sim.output, "Directory for CSV, JSON and frame images")
      ->capture_default_str();
  cmd->add_option("--validate", o->sim.validate,
                  "Decisions judged by rendering both levels at the exact view (0: none)")
      ->capture_default_str();
  cmd->add_option("--images", o->sim.images, "Frames rendered as PNG")->capture_default_str();
  cmd->add_flag("!--no-plots", o->plot_hint, "Do not print the command that plots the run");
  cmd->add_option("--large-object", o->large_object,
                  "Also draw this asset (a mesh name of the scene) large in front of a still head under the "
                  "run's gaze, as a cluster hierarchy of its finest level (lodgen --clusters; its profile "
                  "cached in --profiles as NAME-clusters.acuity), 40 and 20 deg across: triangles per frame "
                  "of the object rule against the cluster cut, both judged, as acuity demo does")
      ->needs("--profiles");
  cmd->callback([o] { simulate(*o); });

  auto e = std::make_shared<SimulateOptions>();
  CLI::App* ex = app.add_subcommand("explain", "Why one object got its level in one simulated frame");
  add_scene_options(ex, e.get());
  ex->add_option("--frame", e->frame, "Frame index")->required();
  ex->add_option("--object", e->object, "Node name or instance index")->required();
  ex->callback([e] { explain(*e); });
}

}  // namespace acuity::tools
