#pragma once
// Subcommands of the acuity command. Each add_* registers its options and callback on the app.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "acuity/bake/library.hpp"
#include "acuity/bake/scene.hpp"
#include "acuity/sim/large_object.hpp"
#include "acuity/sim/simulation.hpp"

namespace acuity::tools {
using bake::AssetOptions;  // the scene bake the subcommands load scenes with
using bake::load_scene_assets;
using bake::SceneAssets;

// A finite number: CLI11's Range, PositiveNumber and NonNegativeNumber let NaN through (every
// comparison with NaN is false), so every floating-point option also checks this.
inline const CLI::Validator Finite(
    [](std::string& text) -> std::string {
      char* end = nullptr;
      const double x = std::strtod(text.c_str(), &end);
      if (end == text.c_str() || *end != '\0' || !std::isfinite(x))
        return "'" + text + "' is not a finite number";
      return {};
    },
    "FINITE");

// A numeric option with its default shown, finite and in [lo, hi].
template <typename T>
CLI::Option* add_number(CLI::App* cmd, const std::string& name, T& value, const std::string& help, double lo,
                        double hi) {
  return cmd->add_option(name, value, help)->capture_default_str()->check(Finite)->check(CLI::Range(lo, hi));
}
// The options `acuity lodgen` and `acuity bake` share: the chain (levels, ratio, max error, backend,
// border, creases, measurement budget, reference height) and the asset root.
void add_chain_options(CLI::App* cmd, bake::BakeOptions& options);
// The options `acuity profile` and `acuity bake` share: snapshot pixels, orientations, bands, the
// adaptive views' tolerance.
void add_profile_options(CLI::App* cmd, bake::BakeOptions& options);
// `--model NAME`: a threshold model, by the names parse_threshold_model reads; `what` begins the help.
void add_model_option(CLI::App* cmd, ThresholdModel& model,
                      const std::string& what = "The perceptual rule's threshold model");
// `--evaluation NAME`: tabulated or exact, by the names parse_evaluation reads.
void add_evaluation_option(CLI::App* cmd, Evaluation& evaluation, const std::string& what);

void add_models_report(CLI::App& app);  // `acuity models`
void print_models_report();             // the same tables with the defaults
// `acuity demo`: the README's main job. `program`: how the command was invoked (argv[0]), for the
// `explain` line it prints.
void add_demo_command(CLI::App& app, const std::string& program);
void add_profile_command(CLI::App& app);    // `acuity profile`
void add_inspect_command(CLI::App& app);    // `acuity inspect`
void add_lodgen_command(CLI::App& app);     // `acuity lodgen`
void add_simulate_commands(CLI::App& app);  // `acuity simulate` and `acuity explain`
void add_plan_command(CLI::App& app);       // `acuity plan`: foveation maps
void add_bake_command(CLI::App& app);       // `acuity bake`: a library of assets, cached

// What a run leaves: the files written, and a decision worth explaining.
struct RunResult {
  std::vector<std::string> written;
  sim::Decision example;
};
// Runs every frame, judges options.validate decisions, prints the summary (and, when large is given,
// the large object's block: sim::run_large_object over the run, its profile's line on stderr), writes
// the outputs into options.output (when set) and lists them, with the command that plots them when
// plot_hint.
RunResult run_simulation(const SceneAssets& scene, const sim::SimulationOptions& options, bool plot_hint,
                         const sim::LargeObjectOptions* large = nullptr);
}  // namespace acuity::tools
