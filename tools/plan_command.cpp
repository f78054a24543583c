// `acuity plan`: the foveation planner's maps for one display, pictures and per-frame savings.
//   acuity plan --display 2000x2000 --fov 100 --gaze 10,5 --png maps.png
//   acuity plan --gaze-track gaze.csv --fps 90 --csv saved.csv --png frame0.png
//   acuity plan --table        (the savings table of docs/foveation.md)
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "acuity/file.hpp"
#include "acuity/foveation_plan.hpp"
#include "acuity/sim/foveation_report.hpp"
#include "acuity/sim/tracks.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

using namespace acuity::sim;  // the planner's pictures and table, the gaze track reader

struct Options {
  std::string display = "2000x2000";
  double fov = 100;
  std::vector<double> gaze{0, 0};
  bool no_gaze = false;
  std::string gaze_track;
  double fps = 90;
  std::size_t frame = 0;
  std::uint32_t tile = 16;
  ThresholdModel model = ThresholdModel::Default;
  float quality = 1.0f, uncertainty = 1.0f, no_gaze_radius = 30.0f, fovea = 2.5f, head_speed = 0.0f;
  unsigned max_rate = 4;
  std::string png, csv;
  int panel = 700;
  bool table = false;
};

void run(const Options& o) {
  FoveationConfig config;
  config.model = o.model;
  config.quality = o.quality;
  config.gaze_uncertainty_deg = o.uncertainty;
  config.no_gaze_radius_deg = o.no_gaze_radius;
  config.foveal_radius_deg = o.fovea;
  config.max_rate = static_cast<std::uint8_t>(o.max_rate);
  if (o.table) {
    std::printf("%s", savings_table(config, o.tile).c_str());
    return;
  }
  unsigned w = 0, h = 0;
  char tail = 0;
  if (std::sscanf(o.display.c_str(), "%ux%u%c", &w, &h, &tail) != 2 || w == 0 || h == 0 || w > 16384 ||
      h > 16384)
    throw std::runtime_error("--display: WIDTHxHEIGHT in pixels, each 1 to 16384");
  Eye eye = display_eye(w, h, o.fov);
  eye.angular_velocity[1] = o.head_speed;
  auto planner = std::make_unique<FoveationPlanner>();
  if (init_foveation_planner(config, planner.get()) != FoveationStatus::Ok)
    throw std::runtime_error("invalid settings: quality > 0, radii >= 0, max rate 1, 2 or 4");

  // Gazes per frame: a track, or the one given.
  std::vector<Gaze> gazes;
  if (!o.gaze_track.empty()) {
    gazes = gazes_from_track(read_table(o.gaze_track), o.fps);
  } else {
    if (o.gaze.size() != 2) throw std::runtime_error("--gaze: YAW,PITCH in degrees");
    Gaze g = gaze_toward(o.gaze[0], o.gaze[1]);
    g.valid = !o.no_gaze;
    gazes.push_back(g);
  }
  if (o.frame >= gazes.size())
    throw std::runtime_error("--frame: the track has " + std::to_string(gazes.size()) + " frames");
  for (const std::string* output : {&o.png, &o.csv})  // never over the track, never a device
    if (!output->empty())
      io::check_output(*output,
                       o.gaze_track.empty() ? std::vector<std::string>{} : std::vector{o.gaze_track});

  const TrackPlan plan = plan_track(*planner, eye, gazes, o.tile, o.fps, o.frame);
  const PlanResult& shown = plan.shown;
  std::printf(
      "display %ux%u px, %.1f deg horizontal, tile %u px, model %s, q %.2f: %zu frame(s), mean shading work "
      "saved %.1f%%\n",
      w, h, o.fov, o.tile, to_string(o.model), double(o.quality), gazes.size(),
      100 * plan.total_saved / double(gazes.size()));
  std::printf("frame %zu: %s, saved %.1f%% (tiles %u x %u)\n", o.frame, to_string(shown.status),
              100 * shown.saved(), shown.maps.cols, shown.maps.rows);
  if (!o.csv.empty()) {
    io::write_file_atomically(o.csv, plan.csv);
    std::printf("wrote %s\n", o.csv.c_str());
  }
  if (!o.png.empty()) {
    char caption[256];
    std::snprintf(caption, sizeof caption,
                  "%ux%u PX, %.0f DEG, GAZE %s, TILE %u PX, MODEL %s, Q %.2f: SHADING WORK SAVED %.1f%%", w,
                  h, o.fov, shown.status == FoveationStatus::Ok ? "TRACKED" : "NONE (30 DEG DISC)", o.tile,
                  to_string(o.model), double(o.quality), 100 * shown.saved());
    write_png(o.png, draw_plan(eye, gazes[o.frame], shown, o.panel, caption));
    std::printf("wrote %s\n", o.png.c_str());
  }
}

}  // namespace

void add_plan_command(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand(
      "plan", "Foveation maps (shading rate, mip bias) for a display: pictures and savings");
  cmd->add_option("--display", o->display, "WIDTHxHEIGHT [px]")->capture_default_str();
  add_number(cmd, "--fov", o->fov, "Horizontal field of view [deg] (vertical from the aspect, square pixels)",
             1.0, 170.0);
  cmd->add_option("--gaze", o->gaze, "YAW,PITCH of the gaze from the view axis [deg], right and up positive")
      ->delimiter(',')
      ->expected(2)
      ->capture_default_str();
  cmd->add_flag("--no-gaze", o->no_gaze, "Plan without a usable gaze (the no-gaze disc)");
  cmd->add_option("--gaze-track", o->gaze_track,
                  "Gaze track, CSV or JSON: t,x,y,z[,confidence] in head space")
      ->check(CLI::ExistingFile);
  add_number(cmd, "--fps", o->fps, "Frame rate the track is resampled to", 1.0, 1000.0);
  cmd->add_option("--frame", o->frame, "The frame the picture shows")->capture_default_str();
  cmd->add_option("--tile", o->tile, "Tile size [px]")
      ->capture_default_str()
      ->check(CLI::IsMember({8u, 16u, 32u}));
  add_model_option(cmd, o->model, "Threshold model");
  add_number(cmd, "--quality", o->quality, "q: invisible when lost contrast <= q CT", 0.01f, 100.0f);
  add_number(cmd, "--uncertainty", o->uncertainty, "Gaze uncertainty [deg]", 0.0f, 90.0f);
  add_number(cmd, "--no-gaze-radius", o->no_gaze_radius, "No-gaze disc radius [deg]", 0.0f, 90.0f);
  add_number(cmd, "--fovea", o->fovea, "Full rate within this of the gaze [deg]", 0.0f, 90.0f);
  cmd->add_option("--max-rate", o->max_rate, "Coarsest pixels per shade: 1, 2 or 4")
      ->capture_default_str()
      ->check(CLI::IsMember({1u, 2u, 4u}));
  add_number(cmd, "--head-speed", o->head_speed, "Head yaw speed [deg/s]", -1000.0f, 1000.0f);
  cmd->add_option("--png", o->png, "Picture of the maps of --frame (PNG)");
  cmd->add_option("--csv", o->csv, "Shading work saved per frame (CSV)");
  add_number(cmd, "--panel", o->panel, "Width of each picture panel [px]", 200, 4000);
  cmd->add_flag("--table", o->table, "Print the savings table of docs/foveation.md (markdown) and stop");
  cmd->callback([o] { run(*o); });
}

}  // namespace acuity::tools
