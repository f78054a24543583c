#pragma once
// The foveation planner seen from the command line (`acuity plan`): a display and its field of view
// as an acuity::Eye, pictures of one eye's maps over a frame with a legend, the shading work saved
// per frame of a gaze track, and the savings table of docs/foveation.md.
#include <cstdint>
#include <string>
#include <vector>

#include "acuity/foveation_plan.hpp"
#include "acuity/sim/frame_image.hpp"
#include "acuity/sim/tracks.hpp"

namespace acuity::sim {

// A flat display of width x height pixels spanning hfov_deg horizontally, centred on the view axis,
// square pixels (the vertical field follows from the aspect). Throws on a degenerate display.
Eye display_eye(std::uint32_t width, std::uint32_t height, double hfov_deg);
// A gaze yaw_deg to the right and pitch_deg up from the view axis.
Gaze gaze_toward(double yaw_deg, double pitch_deg);

struct PlanResult {
  FoveationStatus status = FoveationStatus::InvalidArgument;
  std::vector<std::uint8_t> rate;  // rows x cols x 2
  std::vector<float> bias;         // rows x cols
  FoveationMaps maps;              // its pointers point into rate and bias
  double saved() const { return 1.0 - maps.shaded / maps.pixels; }
};
PlanResult plan_eye(const FoveationPlanner& planner, const Eye& eye, const Gaze& gaze, std::uint32_t tile_px);

// A gaze track (columns t,x,y,z[,confidence], head space) as one gaze per frame at `fps`, frames
// 0 to floor(last t x fps). Throws std::runtime_error naming the track past a million frames.
std::vector<Gaze> gazes_from_track(const Table& track, double fps);
// Gaze samples as the scheduler's gazes (direction, confidence; valid while confidence > 0), as the
// OSG kit's TrackGaze plays them.
std::vector<Gaze> gazes_from(const std::vector<GazeSample>& samples);

// The planner over every gaze: CSV text, one line per frame (frame,time_s,status,origin_x_px,
// origin_y_px,shaded_px,full_px,saved), the sum of the fractions saved, and frame `shown`'s plan.
struct TrackPlan {
  std::string csv;
  double total_saved = 0;
  PlanResult shown;
};
TrackPlan plan_track(const FoveationPlanner& planner, const Eye& eye, const std::vector<Gaze>& gazes,
                     std::uint32_t tile_px, double fps, std::size_t shown);

// Two panels side by side, each `panel_width` wide: the shading rate and the mip bias over a grey
// test frame, with rings every 10 deg around the gaze, the gaze cross, colour legends and a caption.
RgbImage draw_plan(const Eye& eye, const Gaze& gaze, const PlanResult& plan, int panel_width,
                   const std::string& caption);

// Markdown: shading work saved at 1920x1920 over 90 deg, 2000x2000 over 100 deg and 3840x2160 over
// 90 deg horizontal, gaze centred, 20 deg right and 10 deg up, and none; with the Guenter layers'
// pixel saving from the same model.
std::string savings_table(const FoveationConfig& config, std::uint32_t tile_px);

}  // namespace acuity::sim
