#include "acuity/foveation_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "vectorize.hpp"

namespace acuity {
namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kDegD = 180.0 / kPi;
constexpr float kMaxBias = 16.0f;     // octaves; far beyond any texture's mip chain
constexpr float kBiasMargin = 1e-5f;  // float rounding of the tables: the bias never exceeds the exact one
constexpr float kSineScale = kFoveationSineSteps;

bool finite3(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// log2(x) for finite x > 0, rounded down to the table's mantissa step (at most 0.0057 low).
inline float floor_log2(float x, const float* mantissa_table) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const int exponent = static_cast<int>((bits >> 23) & 0xffu) - 127;
  return static_cast<float>(exponent) +
         mantissa_table[(bits >> (23 - kFoveationLog2Bits)) & ((1u << kFoveationLog2Bits) - 1)];
}

// v rotated by the inverse of unit quaternion q (x y z w).
void rotate_inverse(const float q[4], const float v[3], double out[3]) {
  const double x = -q[0], y = -q[1], z = -q[2], w = q[3];
  const double tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  out[0] = v[0] + w * tx + (y * tz - z * ty);
  out[1] = v[1] + w * ty + (z * tx - x * tz);
  out[2] = v[2] + w * tz + (x * ty - y * tx);
}

double angle_deg(const double a[3], const double b[3]) {  // both unit
  const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) *
         kDegD;
}

void normalize(double v[3]) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; ++k) v[k] /= n;
}

bool valid_tile(std::uint32_t t) { return t == 8 || t == 16 || t == 32; }

// The eye's projection: tangents of the frustum edges and focal lengths in pixels.
struct Projection {
  double tan_l, tan_r, tan_u, tan_d, fx, fy;
};

bool projection(const Eye& eye, Projection* p) {
  for (float a : eye.fov_deg)
    if (!(std::abs(a) < 89.9f)) return false;  // also rejects NaN
  p->tan_l = std::tan(eye.fov_deg[0] / kDegD);
  p->tan_r = std::tan(eye.fov_deg[1] / kDegD);
  p->tan_u = std::tan(eye.fov_deg[2] / kDegD);
  p->tan_d = std::tan(eye.fov_deg[3] / kDegD);
  if (!(p->tan_r > p->tan_l) || !(p->tan_u > p->tan_d) || eye.viewport[0] == 0 || eye.viewport[1] == 0)
    return false;
  p->fx = eye.viewport[0] / (p->tan_r - p->tan_l);
  p->fy = eye.viewport[1] / (p->tan_u - p->tan_d);
  return true;
}

// One column (or row) of tiles: its centre's tangent and its nearest and farthest squared tangents
// from the view axis.
struct Band {
  float centre, near2, far2;
  std::uint32_t extent;  // covered pixels
  float inv_sqrt;        // 1 / sqrt(1 + near2)
};
// Tile i of an axis of `pixels` pixels starting at tangent t0, f pixels per unit tangent; sign: +1
// when the tangent grows with the pixel index (x), -1 when it falls (y, row 0 at the top).
Band band(std::uint32_t i, std::uint32_t tile, std::uint32_t pixels, double t0, double f, double sign) {
  const double p0 = double(i) * tile, p1 = std::min<double>(double(i + 1) * tile, pixels);
  const double x0 = t0 + sign * p0 / f, x1 = t0 + sign * p1 / f;
  const double lo = std::min(x0, x1), hi = std::max(x0, x1);
  const double nearest = lo > 0 ? lo : (hi < 0 ? -hi : 0.0);
  const double farthest = std::max(std::abs(lo), std::abs(hi));
  return {static_cast<float>(0.5 * (x0 + x1)), static_cast<float>(nearest * nearest),
          static_cast<float>(farthest * farthest), static_cast<std::uint32_t>(p1 - p0),
          static_cast<float>(1.0 / std::sqrt(1.0 + nearest * nearest))};
}

// The columns, as arrays (the row loops read them).
struct Axis {
  float centre[kMaxFoveationTiles];
  float near2[kMaxFoveationTiles];
  float far2[kMaxFoveationTiles];
  std::uint32_t extent[kMaxFoveationTiles];
  float inv_sqrt[kMaxFoveationTiles];
};
void fill_axis(Axis* a, std::uint32_t n, std::uint32_t tile, std::uint32_t pixels, double t0, double f) {
  for (std::uint32_t i = 0; i < n; ++i) {
    const Band b = band(i, tile, pixels, t0, f, 1.0);
    a->centre[i] = b.centre;
    a->near2[i] = b.near2;
    a->far2[i] = b.far2;
    a->extent[i] = b.extent;
    a->inv_sqrt[i] = b.inv_sqrt;
  }
}

// The least over a tile of (1 + s + w) / sqrt(1 + w): s = the squared tangent along the axis the
// rate is for (its least value over the tile), w the other's, in [w_lo, w_hi]. Pixels per degree
// along x at tangents (u, v) are fx (1 + u^2 + v^2) / sqrt(1 + v^2) pi / 180; it grows with u^2 and,
// in w = v^2, falls until w = u^2 - 1 and grows after.
inline float ppd_factor(float s, float w_lo, float w_hi) {
  const float w = std::clamp(s - 1.0f, w_lo, w_hi);
  return (1.0f + s + w) / std::sqrt(1.0f + w);
}

// What every row's tiles read: per column and per frame.
struct RowTables {
  const float* ox_u;            // [cols] gaze x times the column's centre tangent
  const float* u2;              // [cols] the column's squared centre tangent
  const std::int32_t* step_of;  // sine bin -> 0 (full rate) or 1 + eccentricity step
  const float* need_of;         // [1 + steps]: 2 f, index 0 unreachable (1e30): rates 1, bias 0
  const float* log2_need_of;    // and its log2
  const float* mantissa;        // floor_log2()'s table
  const Axis* columns;
  float kx, ky;  // px per deg on the axis
  int max_rate;
};
// Per tile of a row: pixels per shade in x and y, and the mip bias.
struct Tiles {
  int* x;
  int* y;
  float* b;
};
// The tiles of the row at tangent v (num_v = O_y v - O_z, den_v = 1 + v^2; squared tangents
// v_near2..v_far2 over the row, v_inv_sqrt = 1 / sqrt(1 + v_near2)): each one's own rates and bias,
// before the outward minima, into `out`. Plain arithmetic, selects and table reads (gathers under
// AVX2), so the loops vectorise; the same bits in every clone.
ACUITY_SIMD_CLONES void own_tiles(const RowTables& t, std::uint32_t n, float num_v, float den_v,
                                  float v_near2, float v_far2, float v_inv_sqrt, Tiles out) {
  int *out_x = out.x, *out_y = out.y;
  float* out_b = out.b;
  const std::int32_t* step_of = t.step_of;
  const float *ox_u = t.ox_u, *u2 = t.u2, *need_of = t.need_of, *log2_need_of = t.log2_need_of,
              *mantissa = t.mantissa;
  const float *u_near2s = t.columns->near2, *u_far2s = t.columns->far2, *u_inv_sqrts = t.columns->inv_sqrt;
  const float kx = t.kx, ky = t.ky;
  const int max_rate = t.max_rate;
  // Squared sine of the angle from the origin to each tile centre: 1 - (O.P)^2 / |P|^2 with
  // P = (u, v, -1); 1 (90 deg, the table's end) at or beyond 90 deg. The table bin, one lower than
  // the float value gives (rounding never raises the eccentricity); s <= 1, so the bin is at most
  // kFoveationSineSteps - 1. A loop of its own: it vectorises without gathers.
  int bins[kMaxFoveationTiles];
  for (std::uint32_t c = 0; c < n; ++c) {
    const float dot = std::max(ox_u[c] + num_v, 0.0f);
    const float s = 1.0f - dot * dot / (den_v + u2[c]);
    bins[c] = std::max(static_cast<int>(s * kSineScale) - 1, 0);
  }
  ACUITY_NO_ALIAS
  for (std::uint32_t c = 0; c < n; ++c) {
    const int j = step_of[bins[c]];
    const float need = need_of[j];
    const float u_near2 = u_near2s[c];
    // ppd_factor(), with the usual case (the clamp at the near end) from the precomputed roots.
    const float sum = 1.0f + u_near2 + v_near2;
    const float hx = u_near2 - 1.0f <= v_near2 ? sum * v_inv_sqrt : ppd_factor(u_near2, v_near2, v_far2);
    const float hy =
        v_near2 - 1.0f <= u_near2 ? sum * u_inv_sqrts[c] : ppd_factor(v_near2, u_near2, u_far2s[c]);
    const float ppd_x = kx * hx, ppd_y = ky * hy;
    const int rx = 1 + int(ppd_x >= 2.0f * need) + 2 * int(ppd_x >= 4.0f * need);
    const int ry = 1 + int(ppd_y >= 2.0f * need) + 2 * int(ppd_y >= 4.0f * need);
    const float b = floor_log2(std::min(ppd_x, ppd_y), mantissa) - log2_need_of[j] - kBiasMargin;
    out_x[c] = std::min(rx, max_rate);
    out_y[c] = std::min(ry, max_rate);
    out_b[c] = std::max(0.0f, std::min(b, kMaxBias));
  }
}

// Tiles take the minimum of their values and their outer neighbours' in y (`outer`, and for the
// origin's row `other`; neutral at an edge).
ACUITY_SIMD_CLONES void fold_outer(std::uint32_t n, Tiles outer, Tiles other, Tiles tiles) {
  ACUITY_NO_ALIAS
  for (std::uint32_t c = 0; c < n; ++c) {
    tiles.x[c] = std::min(tiles.x[c], std::min(outer.x[c], other.x[c]));
    tiles.y[c] = std::min(tiles.y[c], std::min(outer.y[c], other.y[c]));
    tiles.b[c] = std::min(tiles.b[c], std::min(outer.b[c], other.b[c]));
  }
}

// Running minima along a row.
struct Running {
  int x = 4, y = 4;
  float b = kMaxBias;
};

// Tiles from, from + step, ... (count of them) each take the running minimum of their values (`own`)
// and the tiles' before them, into `out`.
void scan_row(Tiles own, Tiles out, std::uint32_t from, int step, std::uint32_t count, Running* m) {
  int x = m->x, y = m->y;
  float b = m->b;
  for (std::uint32_t i = 0, c = from; i < count; ++i, c += step) {
    x = out.x[c] = std::min(x, own.x[c]);
    y = out.y[c] = std::min(y, own.y[c]);
    b = out.b[c] = std::min(b, own.b[c]);
  }
  *m = {x, y, b};
}

// Writes a row's final values to the maps and returns its shading work in sixteenths of a pixel
// (16 / (rate_x rate_y) = 16 >> (log2 rate_x + log2 rate_y) per covered pixel, at most 2^20 a row):
// integers, so the sums are exact and need no chain of floating-point adds.
ACUITY_SIMD_CLONES std::uint32_t write_row(std::uint32_t n, Tiles tiles, const std::uint32_t* extent,
                                           std::uint8_t* rate, float* bias) {
  std::uint32_t work = 0;
  ACUITY_NO_ALIAS
  for (std::uint32_t c = 0; c < n; ++c) {
    const std::uint32_t x = tiles.x[c], y = tiles.y[c];  // 1, 2 or 4: log2 is x >> 1
    work += extent[c] * (16u >> ((x >> 1) + (y >> 1)));
  }
  ACUITY_NO_ALIAS
  for (std::uint32_t c = 0; c < n; ++c) {
    rate[2 * c] = static_cast<std::uint8_t>(tiles.x[c]);
    rate[2 * c + 1] = static_cast<std::uint8_t>(tiles.y[c]);
    bias[c] = tiles.b[c];
  }
  return work;
}

void fill_full(FoveationMaps* m, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    m->shading_rate[2 * i] = m->shading_rate[2 * i + 1] = 1;
    m->mip_bias[i] = 0.0f;
  }
  m->shaded = m->pixels;
}
}  // namespace

const char* to_string(FoveationStatus status) {
  switch (status) {
    case FoveationStatus::Ok:
      return "ok";
    case FoveationStatus::NoGaze:
      return "no-gaze";
    case FoveationStatus::InvalidEye:
      return "invalid-eye";
    case FoveationStatus::InvalidArgument:
      return "invalid-argument";
  }
  return "unknown";
}

FoveationConfig foveation_config(const SchedulerConfig& config) {
  FoveationConfig c;
  c.model = config.model;
  c.params = config.params;
  c.quality = config.quality;
  c.min_gaze_confidence = config.min_gaze_confidence;
  c.gaze_uncertainty_deg = config.gaze_uncertainty_deg;
  c.no_gaze_radius_deg = config.no_gaze_radius_deg;
  return c;
}

FoveationStatus init_foveation_planner(const FoveationConfig& config, FoveationPlanner* out) {
  if (!out) return FoveationStatus::InvalidArgument;
  out->ready = false;
  out->config = config;
  const bool ok = std::isfinite(config.quality) && config.quality > 0 &&
                  !std::isnan(config.min_gaze_confidence) && std::isfinite(config.gaze_uncertainty_deg) &&
                  config.gaze_uncertainty_deg >= 0 && std::isfinite(config.no_gaze_radius_deg) &&
                  config.no_gaze_radius_deg >= 0 && std::isfinite(config.foveal_radius_deg) &&
                  config.foveal_radius_deg >= 0 &&
                  (config.max_rate == 1 || config.max_rate == 2 || config.max_rate == 4) &&
                  std::isfinite(config.params.drift) && config.params.drift >= 0;
  if (!ok) return FoveationStatus::InvalidArgument;

  // Speeds from the drift floor to Daly's 80 deg/s pursuit cap, log-spaced.
  const double v0 = std::max(config.params.drift, 0.01), v1 = 80.0;
  for (int k = 0; k < kFoveationSpeeds; ++k)
    out->speed[k] = static_cast<float>(v0 * std::pow(v1 / v0, double(k) / (kFoveationSpeeds - 1)));

  // 2 f(e, v): the frequency whose threshold reaches 1/q, doubled (Nyquist). NaN (a model that
  // cannot answer) counts as everything visible. Bounded to [1e-3, 1e6] cycles/deg so logs stay finite.
  const double contrast = 1.0 / config.quality;
  for (int k = 0; k < kFoveationSpeeds; ++k)
    for (int j = 0; j < kFoveationEccSteps; ++j) {
      const double f = max_visible_frequency<double>(contrast, j * double(kFoveationEccStep), out->speed[k],
                                                     config.model, config.params);
      const double n = std::isnan(f) ? 1e6 : std::clamp(2.0 * f, 1e-3, 1e6);
      out->nyquist[k][j] = static_cast<float>(n);
    }
  // Conservative envelopes: never less visible nearer the gaze, nor at a slower speed (a row is
  // used for every speed from its own up to the next row's).
  for (int k = 0; k < kFoveationSpeeds; ++k)
    for (int j = kFoveationEccSteps - 2; j >= 0; --j)
      out->nyquist[k][j] = std::max(out->nyquist[k][j], out->nyquist[k][j + 1]);
  for (int k = kFoveationSpeeds - 2; k >= 0; --k)
    for (int j = 0; j < kFoveationEccSteps; ++j)
      out->nyquist[k][j] = std::max(out->nyquist[k][j], out->nyquist[k + 1][j]);
  for (int k = 0; k < kFoveationSpeeds; ++k)
    for (int j = 0; j < kFoveationEccSteps; ++j)
      out->log2_nyquist[k][j] = static_cast<float>(std::log2(double(out->nyquist[k][j])));

  // Squared sine s -> angle asin(sqrt(s)) in [0, 90] deg, at each bin's start.
  for (int i = 0; i < kFoveationSineSteps; ++i)
    out->sine_angle[i] = static_cast<float>(std::asin(std::sqrt(double(i) / kFoveationSineSteps)) * kDegD);
  for (int i = 0; i < (1 << kFoveationLog2Bits); ++i)
    out->log2_mantissa[i] = static_cast<float>(std::log2(1.0 + double(i) / (1 << kFoveationLog2Bits)));
  out->ready = true;
  return FoveationStatus::Ok;
}

bool foveation_map_size(const Eye& eye, std::uint32_t tile_px, std::uint32_t* cols, std::uint32_t* rows) {
  std::uint32_t c = 0, r = 0;
  bool ok = valid_tile(tile_px) && eye.viewport[0] > 0 && eye.viewport[1] > 0;
  if (ok) {
    c = static_cast<std::uint32_t>((std::uint64_t(eye.viewport[0]) + tile_px - 1) / tile_px);
    r = static_cast<std::uint32_t>((std::uint64_t(eye.viewport[1]) + tile_px - 1) / tile_px);
    ok = c <= kMaxFoveationTiles && r <= kMaxFoveationTiles;
  }
  if (!ok) c = r = 0;
  if (cols) *cols = c;
  if (rows) *rows = r;
  return ok;
}

namespace {
// The row of the planner's tables for the least retinal speed of the static world under head rotation
// anywhere in the view (written to maps->retinal_speed): image speed |w| sin(angle between the
// rotation axis and the direction) >= |w| sin(angle to the view's centre less the view's angular
// radius), then Daly's pursuit model.
int retinal_speed_row(const FoveationPlanner& planner, const Eye& eye, const Projection& pr,
                      FoveationMaps* maps) {
  const FoveationConfig& cfg = planner.config;
  const float* q = eye.orientation;
  int speed_row = 0;
  double image_speed = 0;
  if (cfg.head_rotation) {
    double w[3];
    rotate_inverse(q, eye.angular_velocity, w);
    const double speed = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (speed > 0) {
      const double axis[3] = {w[0] / speed, w[1] / speed, w[2] / speed};
      double centre[3] = {0.5 * (pr.tan_l + pr.tan_r), 0.5 * (pr.tan_u + pr.tan_d), -1};
      normalize(centre);
      double radius = 0;
      for (double tx : {pr.tan_l, pr.tan_r})
        for (double ty : {pr.tan_u, pr.tan_d}) {
          double corner[3] = {tx, ty, -1};
          normalize(corner);
          radius = std::max(radius, angle_deg(centre, corner));
        }
      const double a = angle_deg(axis, centre);
      const double off_axis = std::clamp(std::min(a, 180.0 - a) - radius, 0.0, 90.0);
      image_speed = speed * std::sin(off_axis / kDegD);
    }
  }
  const float retinal = daly_retinal_velocity(static_cast<float>(image_speed), cfg.params);
  maps->retinal_speed = retinal;
  for (int k = 1; k < kFoveationSpeeds; ++k)
    if (planner.speed[k] <= retinal) speed_row = k;
  return speed_row;
}

// This frame's cutoff per sine bin: index 0 is full rate (an unreachable Nyquist: rate 1, bias
// 0), else 1 + the eccentricity step at or below the bin's eccentricity. Built once per frame so
// each tile needs one table read instead of the angle arithmetic.
void cutoff_tables(const FoveationPlanner& planner, const float* nyq, const float* log2_nyq, float e_offset,
                   float* need_of, float* log2_need_of, std::int32_t* step_of) {
  const float fovea = planner.config.foveal_radius_deg;
  need_of[0] = 1e30f;
  log2_need_of[0] = 100.0f;
  for (int j = 0; j < kFoveationEccSteps; ++j) {
    need_of[j + 1] = nyq[j];
    log2_need_of[j + 1] = log2_nyq[j];
  }
  for (int i = 0; i < kFoveationSineSteps; ++i) {
    const float e = planner.sine_angle[i] - e_offset;
    step_of[i] = e <= fovea
                     ? 0
                     : 1 + std::min(static_cast<int>(e * (1.0f / kFoveationEccStep)), kFoveationEccSteps - 1);
  }
}
}  // namespace

namespace {
// Whether the eye is usable (its projection in *pr): a valid frustum and viewport, finite position
// and velocities, a unit orientation.
bool eye_usable(const Eye& eye, Projection* pr) {
  const float* q = eye.orientation;
  const float qn = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return projection(eye, pr) && std::isfinite(eye.position[0]) && std::isfinite(eye.position[1]) &&
         std::isfinite(eye.position[2]) && std::abs(qn - 1.0f) < 1e-3f && finite3(eye.angular_velocity) &&
         finite3(eye.velocity);
}

// The gaze direction O (eye space, unit) where the gaze is usable; else the view's axis. Returns
// whether it is usable.
bool gaze_direction(const FoveationConfig& cfg, const Gaze& gaze, double O[3]) {
  const float gl = std::sqrt(gaze.direction[0] * gaze.direction[0] + gaze.direction[1] * gaze.direction[1] +
                             gaze.direction[2] * gaze.direction[2]);
  const bool has_gaze =
      gaze.valid && gaze.confidence >= cfg.min_gaze_confidence && std::isfinite(gl) && gl > 0.5f;
  O[0] = 0;
  O[1] = 0;
  O[2] = -1;
  if (has_gaze) {
    for (int k = 0; k < 3; ++k) O[k] = gaze.direction[k];
    normalize(O);
  }
  return has_gaze;
}

// The origin in pixels of gaze direction O (a gaze at or behind 90 deg goes far out in its own
// direction).
void origin_px(const double O[3], const Projection& pr, float out[2]) {
  const double depth = std::max(-O[2], 1e-6);
  const double px = std::clamp((O[0] / depth - pr.tan_l) * pr.fx, -1e9, 1e9);
  const double py = std::clamp((pr.tan_u - O[1] / depth) * pr.fy, -1e9, 1e9);
  out[0] = static_cast<float>(px);
  out[1] = static_cast<float>(py);
}

// No planned neighbours yet: the neutral 4, 4, kMaxBias for the rows below and above the origin's.
void neutral_rows(std::uint32_t cols, int* below_x, int* below_y, float* below_b, int* above_x, int* above_y,
                  float* above_b) {
  std::fill(below_x, below_x + cols, 4);
  std::fill(below_y, below_y + cols, 4);
  std::fill(below_b, below_b + cols, kMaxBias);
  std::copy(below_x, below_x + cols, above_x);
  std::copy(below_y, below_y + cols, above_y);
  std::copy(below_b, below_b + cols, above_b);
}
}  // namespace

FoveationStatus plan_foveation(const FoveationPlanner& planner, const Eye& eye, const Gaze& gaze,
                               FoveationMaps* maps) {
  if (!maps) return FoveationStatus::InvalidArgument;
  std::uint32_t cols, rows;
  if (!foveation_map_size(eye, maps->tile_px, &cols, &rows) || !maps->shading_rate || !maps->mip_bias ||
      maps->capacity < std::uint64_t(cols) * rows)
    return FoveationStatus::InvalidArgument;
  const std::size_t n = std::size_t(cols) * rows;
  const std::uint32_t W = eye.viewport[0], H = eye.viewport[1], T = maps->tile_px;
  maps->cols = cols;
  maps->rows = rows;
  maps->pixels = double(W) * H;
  maps->origin_px[0] = static_cast<float>(0.5 * W);
  maps->origin_px[1] = static_cast<float>(0.5 * H);
  maps->retinal_speed = 0;
  if (!planner.ready) {
    fill_full(maps, n);
    return FoveationStatus::InvalidArgument;
  }
  const FoveationConfig& cfg = planner.config;

  Projection pr;
  if (!eye_usable(eye, &pr)) {
    fill_full(maps, n);
    return FoveationStatus::InvalidEye;
  }

  // Where the gaze may be: a direction O (eye space) and a slack S around it; the origin in pixels.
  double O[3];
  const bool has_gaze = gaze_direction(cfg, gaze, O);
  const float slack = has_gaze ? cfg.gaze_uncertainty_deg : cfg.no_gaze_radius_deg;

  origin_px(O, pr, maps->origin_px);

  const int speed_row = retinal_speed_row(planner, eye, pr, maps);
  const float* nyq = planner.nyquist[speed_row];
  const float* log2_nyq = planner.log2_nyquist[speed_row];

  // Angular radius of a tile about its centre: half its diagonal at the largest angle per pixel
  // (1 / f radians, on the axis).
  const float rho = static_cast<float>(T * std::numbers::sqrt2 / 2.0 / std::min(pr.fx, pr.fy) * kDegD);
  const float e_offset = rho + slack;
  const float kx = static_cast<float>(pr.fx / kDegD),
              ky = static_cast<float>(pr.fy / kDegD);  // px per deg on axis
  const int max_rate = cfg.max_rate;

  Axis cx;
  fill_axis(&cx, cols, T, W, pr.tan_l, pr.fx);
  const float ox = static_cast<float>(O[0]), oy = static_cast<float>(O[1]), oz = static_cast<float>(O[2]);

  // Per column: the gaze term of the cosine and the squared tangent at the centre.
  float ox_u[kMaxFoveationTiles], u2[kMaxFoveationTiles];
  for (std::uint32_t c = 0; c < cols; ++c) {
    ox_u[c] = ox * cx.centre[c];
    u2[c] = cx.centre[c] * cx.centre[c];
  }
  float need_of[kFoveationEccSteps + 1], log2_need_of[kFoveationEccSteps + 1];
  std::int32_t step_of[kFoveationSineSteps];  // 32-bit: a vector gather's index
  cutoff_tables(planner, nyq, log2_nyq, e_offset, need_of, log2_need_of, step_of);
  const RowTables tables{.ox_u = ox_u,
                         .u2 = u2,
                         .step_of = step_of,
                         .need_of = need_of,
                         .log2_need_of = log2_need_of,
                         .mantissa = planner.log2_mantissa,
                         .columns = &cx,
                         .kx = kx,
                         .ky = ky,
                         .max_rate = max_rate};
  // The final values of the last row planned below the origin's row and above it, as the next row's
  // outer neighbours; none yet (neutral: 4, 4, kMaxBias).
  int below_x[kMaxFoveationTiles], below_y[kMaxFoveationTiles], above_x[kMaxFoveationTiles],
      above_y[kMaxFoveationTiles];
  float below_b[kMaxFoveationTiles], above_b[kMaxFoveationTiles];
  neutral_rows(cols, below_x, below_y, below_b, above_x, above_y, above_b);
  const Tiles below{below_x, below_y, below_b}, above{above_x, above_y, above_b};
  int own_x[kMaxFoveationTiles], own_y[kMaxFoveationTiles];
  float own_b[kMaxFoveationTiles];
  const Tiles own{own_x, own_y, own_b};

  // Never finer, never less bias, farther out along a ray from the origin: a ray from the origin
  // crosses from a tile only into a neighbour away from the origin (in x, in y, or through the
  // shared corner). So tiles are computed from the edges inward, rows toward the origin's row and,
  // in a row, columns toward its column, and each takes the minimum of itself and its outer
  // neighbours, already final (the corner one comes through the x neighbour's own vertical step).
  // This only ever moves a tile toward full rate.
  const auto clamp_tile = [](float p, std::uint32_t tile, std::uint32_t count) {
    const double t = std::floor(double(p) / tile);
    return static_cast<std::uint32_t>(std::clamp(t, 0.0, double(count - 1)));
  };
  const std::uint32_t oc = clamp_tile(maps->origin_px[0], T, cols),
                      orow = clamp_tile(maps->origin_px[1], T, rows);
  std::uint64_t shaded16 = 0;  // shading work [1/16 px]

  // Row r, its outer neighbours' final values in `outer` (and `other`), left there replaced by its own.
  const auto plan_row = [&](std::uint32_t r, Tiles outer, Tiles other) {
    const Band row = band(r, T, H, pr.tan_u, pr.fy, -1.0);
    const float v = row.centre;
    own_tiles(tables, cols, oy * v - oz, 1.0f + v * v, row.near2, row.far2, row.inv_sqrt, own);
    fold_outer(cols, outer, other, own);
    Running right, left;  // toward the origin's column from each side
    scan_row(own, outer, cols - 1, -1, cols - 1 - oc, &right);
    scan_row(own, outer, 0, 1, oc, &left);
    Running both{std::min(right.x, left.x), std::min(right.y, left.y), std::min(right.b, left.b)};
    scan_row(own, outer, oc, 1, 1, &both);  // the origin's column: both sides
    shaded16 +=
        std::uint64_t(write_row(cols, outer, cx.extent, maps->shading_rate + 2 * std::size_t(r) * cols,
                                maps->mip_bias + std::size_t(r) * cols)) *
        row.extent;
  };
  for (std::uint32_t r = rows; r-- > orow + 1;) plan_row(r, below, below);  // below the origin, upward
  for (std::uint32_t r = 0; r < orow; ++r) plan_row(r, above, above);       // above it, downward
  plan_row(orow, below, above);                                             // the origin's row: both sides
  maps->shaded = double(shaded16) / 16.0;
  return has_gaze ? FoveationStatus::Ok : FoveationStatus::NoGaze;
}

FoveationLayers foveation_layers(const FoveationPlanner& planner, const Eye& eye, int n_layers) {
  FoveationLayers out;
  Projection pr;
  if (!planner.ready || !projection(eye, &pr)) {
    out.layers = guenter_layers(0, 0, 0, 0, 0, n_layers);  // the invalid result: n_layers 0, NaN fields
    out.omega0 = out.slope = out.layers.e_star;
    return out;
  }
  const FoveationConfig& cfg = planner.config;
  // The model's MAR 1 / f(e) [deg per cycle] with the gaze uncertainty and the foveal radius
  // (finest inside), at the drift speed; the line from its value at 0 stays at or below it.
  const auto model_mar = [&](double e) {
    const double m = e - cfg.gaze_uncertainty_deg;
    const int j = e <= cfg.gaze_uncertainty_deg + cfg.foveal_radius_deg
                      ? 0
                      : std::min(static_cast<int>(m / kFoveationEccStep), kFoveationEccSteps - 1);
    return 2.0 / planner.nyquist[0][j];
  };
  const bool wide = eye.viewport[0] >= eye.viewport[1];
  const double span = wide ? pr.tan_r - pr.tan_l : pr.tan_u - pr.tan_d;
  const double pixels = wide ? eye.viewport[0] : eye.viewport[1];
  const double aspect =
      wide ? double(eye.viewport[1]) / eye.viewport[0] : double(eye.viewport[0]) / eye.viewport[1];
  // Lines through (0, w0) for a few w0 at or below the model's foveal MAR, each with the steepest
  // slope that stays at or below the model out to 90 deg (the flat top the gaze uncertainty and the
  // fovea give would otherwise force slope 0); the one whose layers cost least.
  const double foveal = model_mar(0);
  bool first = true;
  for (double fraction : {1.0, 0.5, 0.25, 0.1, 0.05, 0.02}) {
    const double omega0 = foveal * fraction;
    double slope = 1e9;
    for (int i = 1; i <= 360; ++i) {
      const double e = 0.25 * i;
      slope = std::min(slope, (model_mar(e) - omega0) / e);
    }
    slope = std::max(0.0, slope);
    const GuenterLayers l = guenter_layers(span, 1.0, pixels, aspect, slope, n_layers, omega0, 1000);
    if (first || l.work < out.layers.work) {
      out.layers = l;
      out.omega0 = omega0;
      out.slope = slope;
      first = false;
    }
  }
  return out;
}

}  // namespace acuity
