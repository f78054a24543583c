#pragma once
// acuity/foveation_plan.hpp — the per-pixel side of foveation, from the same threshold model as the
// per-object scheduler: per eye and per frame, a variable-rate-shading image (pixels per shade in x
// and y: 1, 2 or 4), a texture mip-bias map, and Guenter et al. 2012 layers (foveation.hpp).
//
//   auto planner = std::make_unique<acuity::FoveationPlanner>();     // ~125 KB of tables
//   acuity::init_foveation_planner(acuity::foveation_config(scheduler_config), planner.get());
//   uint32_t cols, rows; acuity::foveation_map_size(eye, 16, &cols, &rows);
//   std::vector<uint8_t> rate(2 * cols * rows); std::vector<float> bias(cols * rows);
//   acuity::FoveationMaps maps{16, cols * rows, rate.data(), bias.data()};
//   each frame, each eye: acuity::plan_foveation(*planner, eye, gaze, &maps);   // allocation-free
//
// The rule, per tile (docs/foveation.md has the derivation and the numbers):
// - eccentricity e: the angle from the gaze to the tile, less the gaze uncertainty (without a usable
//   gaze: from the view centre, less the no-gaze radius), never more than the tile's nearest point's;
// - the highest visible frequency f(e, v): the frequency whose threshold contrast reaches 1/q in the
//   configured ThresholdModel (a full-contrast component lost there is at most q CT: invisible), at
//   the least retinal speed the head rotation gives anywhere in the view (Daly's pursuit model);
// - the display's pixels per degree at the tile, in x and in y separately (a flat panel's grow away
//   from the view centre), the least over the tile;
// - shading rate in x: the largest r in {1, 2, 4} with ppd_x / r >= 2 f (Nyquist), likewise in y;
//   mip bias: max(0, log2(min(ppd_x, ppd_y) / (2 f))), the octaves of blur the eye cannot see;
// - full rate and bias 0 where any point of the tile lies within foveal_radius_deg of where the gaze
//   may be (gaze uncertainty or the no-gaze disc);
// - then neither map is finer or smaller farther out along any ray from the gaze: tiles are taken from
//   the image edges inward and each takes the minimum of itself and its neighbours away from the gaze
//   (a ray from the gaze leaves a tile only into one of those), which only moves tiles toward full rate.
// Every approximation (tables, bounds) errs toward finer shading and smaller bias.
#include <cstdint>

#include "acuity/foveation.hpp"
#include "acuity/models.hpp"
#include "acuity/scheduler.hpp"

namespace acuity {

struct FoveationConfig {
  ThresholdModel model = ThresholdModel::Default;
  ModelParams params;
  float quality = 1.0f;               // q: a lost component is invisible at contrast <= q CT
  float min_gaze_confidence = 0.5f;   // below it (or invalid, or non-finite) there is no gaze
  float gaze_uncertainty_deg = 1.0f;  // tracker error: subtracted from every eccentricity [deg]
  float no_gaze_radius_deg = 30.0f;   // without gaze, the gaze may be anywhere this close to the view
                                      // centre: eccentricity is measured from that disc [deg]
  float foveal_radius_deg = 2.5f;     // full rate within this of where the gaze may be [deg]
  std::uint8_t max_rate = 4;          // coarsest pixels per shade allowed: 1, 2 or 4
  // Lower the cutoff by the retinal speed the head's rotation gives the static world. Off: the
  // vestibulo-ocular reflex turns the eyes against the head, so the world the eye fixates stays
  // still on the retina while the head turns. On only for content that turns with the head while
  // the eyes hold still in it (a coarser plan; not for a world-fixed scene).
  bool head_rotation = false;
};

// The scheduler's model, q and gaze handling, with the defaults above for the rest.
FoveationConfig foveation_config(const SchedulerConfig& config);

// Tables of the visible-frequency limit, built once per configuration (about 12k model
// evaluations, a few milliseconds); plan_foveation() then needs no model evaluation.
inline constexpr int kFoveationSpeeds = 16;     // retinal speeds, log-spaced from the drift floor to 80 deg/s
inline constexpr int kFoveationEccSteps = 721;  // eccentricity 0 .. 180 deg in steps of 0.25 deg
inline constexpr float kFoveationEccStep = 0.25f;
inline constexpr int kFoveationSineSteps = 4096;           // squared sine of the angle, 0 .. 1
inline constexpr int kFoveationLog2Bits = 8;               // mantissa bits of the log2 table
inline constexpr std::uint32_t kMaxFoveationTiles = 2048;  // per axis (16384 px at tile 8)

struct FoveationPlanner {
  FoveationConfig config;
  bool ready = false;                                             // init_foveation_planner succeeded
  float speed[kFoveationSpeeds] = {};                             // retinal speed of each row [deg/s]
  float nyquist[kFoveationSpeeds][kFoveationEccSteps] = {};       // 2 f(e, v) [cycles/deg]
  float log2_nyquist[kFoveationSpeeds][kFoveationEccSteps] = {};  // log2 of it
  float sine_angle[kFoveationSineSteps] = {};                     // angle [deg] at the start of each bin
  float log2_mantissa[1 << kFoveationLog2Bits] = {};              // log2(1 + i / 256)
};

enum class FoveationStatus : std::uint8_t {
  Ok = 0,               // planned around the gaze
  NoGaze = 1,           // no usable gaze: planned around the no-gaze disc at the view centre
  InvalidEye = 2,       // non-finite or degenerate eye (fov, viewport, orientation, rotation):
                        // full rate and bias 0 everywhere
  InvalidArgument = 3,  // planner not ready or bad config: full rate everywhere when the buffers
                        // are usable; bad tile size, null or too small buffers: nothing written
};
const char* to_string(FoveationStatus status);

// Validates the configuration and fills the tables. Returns Ok or InvalidArgument (quality not
// finite and > 0, radii not finite and >= 0, max_rate not 1, 2 or 4, min_gaze_confidence NaN).
FoveationStatus init_foveation_planner(const FoveationConfig& config, FoveationPlanner* out);

// The caller's buffers, and what plan_foveation() reports about them.
struct FoveationMaps {
  // In: tiles of tile_px x tile_px pixels (8, 16 or 32); buffers for `capacity` tiles.
  std::uint32_t tile_px = 16;
  std::uint32_t capacity = 0;
  std::uint8_t* shading_rate = nullptr;  // [rows][cols][2]: pixels per shade in x, then y
  float* mip_bias = nullptr;             // [rows][cols]: texture LOD bias >= 0 [octaves]
  // Out: row-major, row 0 at the top of the image, ceil(pixels / tile_px) tiles per axis (the last
  // row and column may be partial).
  std::uint32_t cols = 0, rows = 0;
  float origin_px[2] = {0, 0};  // where the maps are centred: the gaze (or view centre) in pixels,
                                // x right, y down from the top-left corner; may lie off the image
  float retinal_speed = 0;      // the retinal speed the cutoff was taken at [deg/s]
  double shaded = 0;            // shading work: sum over tiles of covered pixels / (rate_x rate_y)
  double pixels = 0;            // full-rate work: width x height
};

// Tiles per axis for this eye's viewport: ceil(pixels / tile_px). False (and 0) when the tile size
// is not 8, 16 or 32, the viewport is empty or the grid exceeds kMaxFoveationTiles per axis.
bool foveation_map_size(const Eye& eye, std::uint32_t tile_px, std::uint32_t* cols, std::uint32_t* rows);

// One eye, one frame. Writes cols x rows entries of both maps. Allocation-free (its scratch, sized for
// kMaxFoveationTiles columns, is about 165 KB of the calling thread's stack), deterministic: the
// same bits on every CPU. Thread-safe for distinct maps (the planner is only read).
FoveationStatus plan_foveation(const FoveationPlanner& planner, const Eye& eye, const Gaze& gaze,
                               FoveationMaps* maps);

// Guenter layers for this eye's display from the same model: a MAR line omega0 + slope e at or below
// the model's 1 / f(e) for e in [0, 90] deg (with the gaze uncertainty and the foveal radius, at the
// drift speed; omega0 tried at 1, 1/2, 1/4, 1/10, 1/20 and 1/50 of the model's foveal MAR, each with
// its steepest slope, the cheapest kept), then guenter_layers() on the eye's wider axis (distance 1,
// width the tangent span, a 1000-step grid). Allocates (the layer search, ~10 ms): call once per
// display and configuration; the layers are centred on FoveationMaps::origin_px each frame.
struct FoveationLayers {
  double omega0 = 0;  // [deg per cycle]
  double slope = 0;   // [deg per cycle per deg]
  GuenterLayers layers;
};
FoveationLayers foveation_layers(const FoveationPlanner& planner, const Eye& eye, int n_layers = 3);

}  // namespace acuity
