// `acuity models`: the thresholds and cutoff frequencies of every model over eccentricity and
// velocity, as tables a person can check against the papers.
#include <cstdio>
#include <string>

#include "acuity/foveation.hpp"
#include "acuity/models.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

constexpr double kEccentricities[] = {0, 2, 5, 10, 20, 40};  // [deg]
constexpr double kImageSpeeds[] = {0, 1, 3, 10, 30, 100};    // [deg/s]

void print_row_header(const char* corner) {
  std::printf("%-22s", corner);
  for (double e : kEccentricities) std::printf(" %8.0f", e);
  std::printf("\n");
}

void report(double contrast, ThresholdModel model, const std::string& fit_name) {
  ModelParams p;
  if (!parse_csf_fit(fit_name.c_str(), &p.fit))
    throw std::runtime_error("unknown CSF fit '" + fit_name + "' (daly1998, laird2006)");

  std::printf("acuity vision models (shared/reference/vision-models.md)\n\n");
  std::printf("Highest visible frequency [cpd] at contrast %.3g, model '%s', CSF fit '%s'.\n", contrast,
              to_string(model), fit_name.c_str());
  std::printf("Rows: image velocity [deg/s] -> Daly retinal velocity; columns: eccentricity [deg].\n");
  print_row_header("v_image (v_retinal)");
  for (double v : kImageSpeeds) {
    const double v_r = daly_retinal_velocity(v, p);
    std::printf("%6.0f (%8.3f)      ", v, v_r);
    for (double e : kEccentricities) std::printf(" %8.3f", max_visible_frequency(contrast, e, v_r, model, p));
    std::printf("\n");
  }

  std::printf("\nThreshold contrast of the same model at retinal velocity %.2f deg/s (drift).\n", p.drift);
  print_row_header("f [cpd] \\ e [deg]");
  for (double f : {0.5, 2.0, 4.0, 8.0, 16.0, 32.0}) {
    std::printf("%-22.1f", f);
    for (double e : kEccentricities) std::printf(" %8.3g", threshold(f, e, p.drift, model, p));
    std::printf("\n");
  }

  std::printf(
      "\nCutoffs at full contrast [cpd]: Geisler-Perry f_c(e); Reddy H(v) M(e) [unverified] at v = 0.\n");
  print_row_header("model \\ e [deg]");
  std::printf("%-22s", "geisler-perry");
  for (double e : kEccentricities) std::printf(" %8.3f", geisler_perry_cutoff(e, 1.0, p));
  std::printf("\n%-22s", "reddy");
  for (double e : kEccentricities) std::printf(" %8.3f", reddy_cutoff(0.0, e));
  std::printf("\n%-22s", "MAR acuity 1/w(e)");
  for (double e : kEccentricities) std::printf(" %8.3f", 1.0 / mar(e, 0.022, 1.0 / 48.0));
  std::printf("\n");

  const GuenterLayers g = guenter_layers(51, 59, 1920, 9.0 / 16.0, 0.022, 3);
  std::printf(
      "\nGuenter et al. 2012 display (W 51 cm, V 59 cm, D 1920, aspect 9/16, slope 0.022, 3 layers):\n");
  std::printf("  e* = %.1f deg, w* = %.4f deg; radii", g.e_star, g.omega_star);
  for (int i = 0; i < g.n_layers; ++i) std::printf(" %.2f", g.radius[i]);
  std::printf(" deg; sampling");
  for (int i = 0; i < g.n_layers; ++i) std::printf(" %.2f", g.sampling[i]);
  std::printf("; predicted speedup %.2fx\n", g.speedup);
}

}  // namespace

void print_models_report() { report(1.0, ThresholdModel::Default, "daly1998"); }

void add_models_report(CLI::App& app) {
  struct Options {
    double contrast = 1.0;
    ThresholdModel model = ThresholdModel::Default;
    std::string fit = "daly1998";
  };
  auto opts = std::make_shared<Options>();
  CLI::App* cmd =
      app.add_subcommand("models", "Print thresholds and cutoff frequencies over eccentricity and velocity");
  cmd->add_option("--contrast", opts->contrast, "Contrast for the highest-visible-frequency table")
      ->check(Finite)
      ->check(CLI::PositiveNumber);
  add_model_option(cmd, opts->model, "Threshold model");
  cmd->add_option("--fit", opts->fit, "daly1998 | laird2006");
  cmd->callback([opts] { report(opts->contrast, opts->model, opts->fit); });
}

}  // namespace acuity::tools
