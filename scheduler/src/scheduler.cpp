// Per-frame LOD selection. See acuity/scheduler.hpp for the contract.
//
// The perceptual rule, per object and eye:
//   distance d, angular diameter D = 2 asin(r / d), eccentricity e from the gaze to the sphere,
//   image-plane angular velocity -> retinal velocity (Daly's pursuit or measured gaze), projected
//   onto each profile orientation t: v_t = |v_R . w_t| floored at the drift;
//   per band b: f = f_b / D [cpd]; ln CT(t, b) from the threshold model (bands above the display's
//   Nyquist frequency are invisible); level k's score = max_tb lost_k / (q CT).
// For the Default model, ln CT is split into per-orientation terms (one log10 and one log per
// orientation, once per frame for static objects) and per-band multiply-adds, using
//   ln S(f, v) = A(v) + 2 ln(2 pi c1 f) - b(v) f  above the peak f_p(v) = 2 / b(v), plateau below.
#include "acuity/scheduler.hpp"

#include "fast_math.hpp"
#include "vectorize.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>

namespace acuity {
namespace {

using detail::atan2_deg;
using detail::ln_positive;

// A hint to load a cache line that is read a pass later.
#if defined(__GNUC__) || defined(__clang__)
#define ACUITY_PREFETCH(p) __builtin_prefetch(p)
#define ACUITY_PREFETCH_L2(p) __builtin_prefetch(p, 0, 1)  // many lines: keep them out of L1
#else
#define ACUITY_PREFETCH(p) ((void)(p))
#define ACUITY_PREFETCH_L2(p) ((void)(p))
#endif

constexpr float kDeg = 180.0f / std::numbers::pi_v<float>;
constexpr float kRad = std::numbers::pi_v<float> / 180.0f;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Vec3 {
  float x, y, z;
};
[[gnu::always_inline]] inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
[[gnu::always_inline]] inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
[[gnu::always_inline]] inline Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
[[gnu::always_inline]] inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
[[gnu::always_inline]] inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
[[gnu::always_inline]] inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline bool finite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
inline Vec3 load(const float* p) { return {p[0], p[1], p[2]}; }

// Rotates v by the unit quaternion (x, y, z, w).
[[gnu::always_inline]] inline Vec3 rotate(float x, float y, float z, float w, Vec3 v) {
  const Vec3 u{x, y, z};
  const Vec3 t = 2.0f * cross(u, v);
  return v + w * t + cross(u, t);
}
[[gnu::always_inline]] inline Vec3 rotate(const float* q, Vec3 v) {
  return rotate(q[0], q[1], q[2], q[3], v);
}
// The coarsest level whose threshold distance / radius = x passes (thresholds of absent levels are
// +inf); NaN passes none.
[[gnu::always_inline]] inline std::uint8_t level_by_ratio(float x, const float* threshold,
                                                          std::uint32_t count) {
  std::uint8_t level = 0;
  for (std::uint32_t k = 1; k < count; ++k) level = x >= threshold[k] ? static_cast<std::uint8_t>(k) : level;
  return level;
}

// Angle between unit vectors [deg], accurate at small angles.
[[gnu::always_inline]] inline float angle_deg(Vec3 a, Vec3 b) {
  return atan2_deg(length(cross(a, b)), dot(a, b));
}
// The angular radius [deg] of a sphere of radius r at distance d from the eye (any finite value where
// the eye is inside it), as the frame loop computes it.
[[gnu::always_inline]] inline float angular_radius_deg(float d, float r) {
  const float sin_radius = d > r ? r / d : 0.5f;
  return atan2_deg(sin_radius, std::sqrt(1.0f - sin_radius * sin_radius));  // asin
}

// Per-orientation terms of the Default model's ln S at velocity v (already floored).
struct VelocityTerms {
  float a_term;     // A(v) = ln(prefactor v k(c2 v))
  float b;          // b(v) = 4 pi c1 (c2 v + 2) / 45.9  [per cpd]
  float peak;       // f_p = 2 / b  [cpd]
  float ln_s_peak;  // ln S at the peak
};

struct DalyConstants {
  float ln_prefactor, c1, c2, ln_2pi_c1, v_floor;
};

// The fit's constants (from models.cpp, the one place they are written) in the fast path's form.
DalyConstants daly_constants(const ModelParams& p) {
  const DalyFitConstants f = daly_fit_constants(p.fit);
  return {float(std::log(f.prefactor)), float(f.c1), float(f.c2),
          float(std::log(2 * std::numbers::pi * f.c1)), float(std::max(p.drift, f.v_floor))};
}

VelocityTerms velocity_terms(float v, const DalyConstants& c) {
  const float x = c.c2 * v;
  const float l = std::abs(std::log10(x / 3.0f));
  VelocityTerms t;
  t.a_term = c.ln_prefactor + std::log(v) + std::log(6.1f + 7.3f * l * l * l);
  t.b = 4.0f * std::numbers::pi_v<float> * c.c1 * (x + 2.0f) / 45.9f;
  t.peak = 2.0f / t.b;
  t.ln_s_peak = t.a_term + 2.0f * (c.ln_2pi_c1 + std::log(t.peak)) - 2.0f;
  return t;
}

// For moving objects, "faster never finer" needs a threshold that never falls as speed rises. The
// low-pass CSF rises with speed below its argmax u*(f) (< 2 deg/s; Kelly's surface is nearly flat
// there), so each component is evaluated at max(v, u*(f)): the velocity envelope. u* is tabulated
// over ln f once, each entry the largest argmax on its interval plus a step, so the envelope is
// monotone by construction wherever S(f, .) is unimodal (a test checks it on a fine grid).
constexpr int kEnvelopeSize = 192;
constexpr float kEnvelopeLnF0 = -4.6f, kEnvelopeLnF1 = 5.3f;  // 0.01 .. 200 cpd

double argmax_speed(double f, const ModelParams& p) {
  auto ln_s = [&](double ln_u) { return -log_threshold(f, 0.0, std::exp(ln_u), ThresholdModel::Default, p); };
  double lo = std::log(std::max(p.drift, 1e-3)), hi = std::log(20.0);
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  double a = hi - g * (hi - lo), b = lo + g * (hi - lo), sa = ln_s(a), sb = ln_s(b);
  for (int i = 0; i < 40; ++i) {  // golden section, one new evaluation a step; 0.618^40 ~ 4e-9
    if (sa < sb) {
      lo = a;
      a = b;
      sa = sb;
      b = lo + g * (hi - lo);
      sb = ln_s(b);
    } else {
      hi = b;
      b = a;
      sb = sa;
      a = hi - g * (hi - lo);
      sa = ln_s(a);
    }
  }
  return std::exp(0.5 * (lo + hi));
}

// max over t < T, b < B of lost[t B + b] - ct[t stride + b], with stride B (one threshold row per
// orientation) or 0 (one row for all). Eight independent accumulators keep the adds in flight.
inline float max_excess(const float* lost, const float* ct, std::uint32_t T, std::uint32_t B,
                        std::uint32_t stride) {
  float acc[8] = {-kInf, -kInf, -kInf, -kInf, -kInf, -kInf, -kInf, -kInf};
  for (std::uint32_t t = 0; t < T; ++t) {
    const float* l = lost + std::size_t(t) * B;
    const float* c = ct + std::size_t(t) * stride;
    std::uint32_t b = 0;
    for (; b + 8 <= B; b += 8)
      for (int j = 0; j < 8; ++j) acc[j] = std::max(acc[j], l[b + j] - c[b + j]);
    for (; b < B; ++b) acc[0] = std::max(acc[0], l[b] - c[b]);
  }
  float m = acc[0];
  for (int j = 1; j < 8; ++j) m = std::max(m, acc[j]);
  return m;
}

// ---- Tabulated path: grid and threshold curves ----------------------------------------------------
// Eccentricity nodes e_j = kTableMaxE (j / (n - 1))^2 (dense near the fovea), speed nodes
// s_i = floor 2^i; beyond the last node the last one (thresholds never fall with e or speed).
constexpr std::uint32_t kStillE = 24, kMovingE = 16, kMovingS = 13;
constexpr float kTableMaxE = 90.0f;
// A threshold curve: ln CT against u = ln f [cpd] on kCurveSamples points, made non-decreasing
// (a suffix minimum: a band-pass CSF counts as its low-pass envelope, which is conservative).
constexpr int kCurveSamples = 4096;
constexpr float kCurveU0 = -7.0f, kCurveU1 = 14.0f;
constexpr float kCurveStep = (kCurveU1 - kCurveU0) / float(kCurveSamples - 1);
constexpr float kNever = -1e30f;  // a table entry no size passes
// The moving tables' cells are checked at their centres only; this much more [ln deg] covers what
// the bilinear surface can still cut above the truth between centre and edges (measured: < 0.003).
constexpr float kBilinearMargin = 0.001f;
// Table sets per profile: [2 i + 0] score <= 1, [2 i + 1] score <= 1 - margin, at the i-th bias with
// tables (Scheduler::table_bias_); an object whose bias has none takes the exact path.
constexpr std::uint32_t kTableSets = 2 * (1 + kMaxTabulatedBiases);
constexpr std::uint8_t kExactBias = 255;
constexpr std::uint8_t kInvalidBias = 254;  // quality x bias not finite and > 0: invalid input
// Table sets per bias: score <= 1, and score <= 1 - margin where a margin is set.
inline int margin_sets(const SchedulerConfig& c) { return c.hysteresis_margin > 0 ? 2 : 1; }
// The biases with tables: 1, then each distinct finite entry > 0 of the configuration's. Returns the count.
std::uint32_t table_biases(const SchedulerConfig& c, float* out) {
  std::uint32_t n = 0;
  out[n++] = 1.0f;
  for (const float b : c.tabulated_biases)
    if (std::isfinite(b) && b > 0 && std::find(out, out + n, b) == out + n) out[n++] = b;
  return n;
}

// Table entries: ln deg in steps of 1/1024, rounded down (conservative), saturating at
// kLeastEntry and kMostEntry (about +-32 ln deg; e^32 deg: every size passes; e^-32: none does).
constexpr float kSizeSteps = 1024.0f;  // per ln deg (a power of two: scaling is exact)
constexpr std::int32_t kLeastEntry = -32768, kMostEntry = 32757;
inline std::int16_t encode_size(float ln_size) {
  const float x = std::clamp(std::floor(ln_size * kSizeSteps), float(kLeastEntry), float(kMostEntry));
  return static_cast<std::int16_t>(x);
}
[[gnu::always_inline]] inline float decode_size(std::int16_t q) { return float(q) * (1.0f / kSizeSteps); }
// An object's ln size [ln deg] in table steps, rounded up (NaN: -64 ln deg): it is at most an entry
// exactly where the size is at most that entry's decoded value. Every size at most kLeastEntry is at
// most every entry and every size above kMostEntry is above all, so the steps are clamped to
// [kLeastEntry, kMostEntry + 1] (the same comparisons; an int16). Branch-free, so a loop vectorises.
[[gnu::always_inline]] inline std::int32_t size_steps_above(float ln_size) {
  const float scaled = (ln_size > -64.0f ? std::min(ln_size, 64.0f) : -64.0f) * kSizeSteps;
  const auto truncated = static_cast<std::int32_t>(scaled);
  return std::clamp(truncated + (float(truncated) < scaled), kLeastEntry, kMostEntry + 1);
}
// Between two table entries (a cell's lower and upper node) at the upper one's weight w [ln deg].
[[gnu::always_inline]] inline float between(std::int16_t lower, std::int16_t upper, float w) {
  const float a = decode_size(lower);
  return a + w * (decode_size(upper) - a);
}

constexpr float e_node(std::uint32_t j, std::uint32_t n) {
  const float t = float(j) / float(n - 1);
  return kTableMaxE * t * t;
}
inline float still_e_node(std::uint32_t j) { return e_node(j, kStillE); }
inline float moving_e_node(std::uint32_t j) { return e_node(j, kMovingE); }

// A position on a grid axis: the cell's lower node and the weight of the upper one. The weight is
// linear in the physical quantity (eccentricity, speed), where the largest invisible ln size is
// concave (ln of an affine function of e or v for the CSF's exponential fall-off), so the
// interpolation stays below it; a sqrt or log weight would cut above it.
struct Cell {
  std::uint32_t j;
  float w;
};
// The cell of eccentricity e [deg] on an n-node axis. The nodes come from e_node(), not from a table,
// so a loop over objects vectorises without gathers.
template <std::uint32_t n>
[[gnu::always_inline]] inline Cell e_cell(float e) {
  const float r = std::sqrt(e * (1.0f / kTableMaxE));
  const float x = (r < 1.0f ? r : 1.0f) * float(n - 1);  // NaN: the last cell (no NaN reaches the cast)
  const std::uint32_t j = std::min(static_cast<std::uint32_t>(x), n - 2);
  const float lower = e_node(j, n), upper = e_node(j + 1, n);
  return {j, std::clamp((e - lower) * (1.0f / (upper - lower)), 0.0f, 1.0f)};
}
// Speed nodes floor 2^i: the cell from the float's exponent (exact at powers of two). The weight is
// linear in g(r) = (r - 1) / (r + 1) ~ ln(r) / 2, r = (v + v0) / (v_lo + v0), v0 = 2 / c2: the CSF's
// fall-off b(v) f grows with c2 v + 2, so the largest invisible ln size is nearly linear in ln(v + v0).
// Plain arithmetic (the node and 1 / g at the cell's top computed, not looked up): a loop over
// orientations vectorises.
[[gnu::always_inline]] inline void speed_cell(float v, float floor, float v0, std::uint32_t n,
                                              std::uint32_t* j, float* w) {
  const float r = v / floor;  // >= 1
  std::uint32_t bits;
  std::memcpy(&bits, &r, sizeof bits);
  const int octave = std::min(std::max(int((bits >> 23) & 255u) - 127, 0), int(n) - 2);
  const std::uint32_t power_bits = std::uint32_t(octave + 127) << 23;  // 2^octave
  float power;
  std::memcpy(&power, &power_bits, sizeof power);
  const float lo = floor * power;                    // the cell's lower node
  const float inv_g = (3.0f * lo + 2.0f * v0) / lo;  // 1 / g at the cell's top, 2 lo
  // g(r) = (r - 1) / (r + 1) with r = (v + v0) / (lo + v0) is (v - lo) / (v + lo + 2 v0).
  *j = static_cast<std::uint32_t>(octave);
  *w = std::clamp((v - lo) / (v + lo + 2.0f * v0) * inv_g, 0.0f, 1.0f);
}
// The speed at weight 1/2 of cell [lo, 2 lo].
inline float speed_midpoint(float lo, float v0) {
  const float half = 0.5f * ((2.0f * lo + v0) / (lo + v0) - 1.0f) / ((2.0f * lo + v0) / (lo + v0) + 1.0f);
  return (1.0f + half) / (1.0f - half) * (lo + v0) - v0;
}

// Where a decision stands: x [table steps, as size_steps_above()] in (lo, hi] and the eccentricity
// cell's upper weight w in [w_from, w_to] / kWeightSteps. Where there is no end, lo and hi start just
// past the entries (size_steps_above()'s range); a decision over the whole cell stands for every w.
constexpr float kWeightSteps = 32768.0f;  // a power of two: w * kWeightSteps is exact
struct Stand {
  static constexpr std::int32_t kNoLow = kLeastEntry - 1, kNoHigh = kMostEntry + 1;
  std::int32_t lo = kNoLow, hi = kNoHigh;
  std::uint16_t w_from = 0, w_to = 0xffff;
};
static_assert(Stand::kNoLow + 1 >= INT16_MIN && Stand::kNoHigh <= INT16_MAX, "lo + 1 and hi fit an int16");

// Where a decision made at an object's place in its cell stands. It compared x [ln deg] (x_step: in
// table steps) against lines between a cell's two entries at the weight w: x <= between(lower, upper,
// w) + offset, and `lines(f)` calls f(lower, upper, offset) for each. Half the least distance from x
// to a line goes to x, the rest to w: the box of w in which every line stays that far on its side of
// x. Then each line at the box's ends, computed as the decision computes it (between() is monotone in
// w, so its extremes are there), narrows (lo, hi], with a table step of room for rounding. Writes
// *out and returns true where x_step lies inside; else the decision stands nowhere around x.
template <class Lines>
bool stand_at_place(float x, std::int32_t x_step, float w, const Lines& lines, Stand* out) {
  float slack = kInf;
  lines([&](std::int16_t lower, std::int16_t upper, float offset) {
    slack = std::min(slack, std::abs(between(lower, upper, w) + offset - x));
  });
  const float half = 0.5f * slack;
  float w_lo = 0.0f, w_hi = 1.0f;
  lines([&](std::int16_t lower, std::int16_t upper, float offset) {
    const float a = decode_size(lower) + offset, d = decode_size(upper) - decode_size(lower);
    if (d == 0.0f) return;  // level: on its side at every w
    const bool passes = x <= between(lower, upper, w) + offset;
    const float near = ((passes ? x + half : x - half) - a) / d;  // the w where it comes that near
    if (passes == (d > 0.0f))
      w_lo = std::max(w_lo, near);
    else
      w_hi = std::min(w_hi, near);
  });
  const float from = std::ceil(w_lo * kWeightSteps), to = std::floor(w_hi * kWeightSteps);
  if (!(from <= w * kWeightSteps && w * kWeightSteps <= to)) return false;
  const float end0 = from / kWeightSteps, end1 = to / kWeightSteps;
  Stand s{Stand::kNoLow, Stand::kNoHigh, static_cast<std::uint16_t>(from), static_cast<std::uint16_t>(to)};
  lines([&](std::int16_t lower, std::int16_t upper, float offset) {
    const float b0 = between(lower, upper, end0) + offset, b1 = between(lower, upper, end1) + offset;
    if (x <= between(lower, upper, w) + offset)
      s.hi = std::min(s.hi, static_cast<std::int32_t>(std::floor(std::min(b0, b1) * kSizeSteps)) - 1);
    else
      s.lo = std::max(s.lo, static_cast<std::int32_t>(std::ceil(std::max(b0, b1) * kSizeSteps)) + 1);
  });
  if (!(s.lo < x_step && x_step <= s.hi)) return false;
  *out = s;
  return true;
}

}  // namespace

struct Scheduler::ProfileCache {
  Profile profile{};
  std::vector<float> ln_lost;       // [(K-1) V T B], -inf where nothing is lost
  std::vector<float> ln_lost_any;   // [(K-1) V B]: max over orientations (all a static object needs)
  std::vector<float> ln_band;       // [B] ln of the band centre [cpod]
  std::vector<float> cos_t, sin_t;  // [T] orientation unit vectors in the snapshot plane
  std::vector<float> view_right;    // [V][3] snapshot right = -direction x up, object space
  // Tabulated path: ln of the largest invisible angular diameter [ln deg] (see scheduler.hpp).
  // Levels are innermost, so one object's reads share cache lines.
  // still and slow [V][n][kStillE][K-1]: the n = 1..B lowest bands visible on the display, a still
  // object (the floor's terms) and one moving no faster than the floor (the velocity envelope) --
  // a bound for every moving object, since thresholds never fall with speed;
  // moving [V][T][kMovingS][kMovingE][K-1]: every band, one orientation at its own speed.
  // Entries: encode_size(), 1/1024 ln deg, rounded down.
  // The same bounds taken over every view at each eccentricity node, so that most objects are
  // decided before their view is looked up: any_view [B][kStillE][2 (K-1) + 1], per band count
  // and eccentricity node the least and the most over the views of the still table, then the least
  // over the views of the still and slow tables at the coarsest level (every object whose image
  // moves is bounded by one of them).
  struct Tables {
    std::vector<std::int16_t> still, slow, moving, any_view;
  };
  // [2 i]: score <= 1, [2 i + 1]: score <= 1 - margin (empty when the margin is 0), at bias
  // table_bias_[i] (kTableSets). One set's four side by side: an object reads one set.
  Tables sets[kTableSets];
};

// Everything that depends only on the configuration, computed once at creation.
struct Scheduler::Precomputed {
  DalyConstants daly{};
  VelocityTerms static_terms{};  // Default-model terms at the velocity floor
  float floor_velocity = 0;      // [deg/s]
  float ln_quality = 0, ln_margin = 0;
  // ln(q x bias): what an object of this bias is decided at, by the exact path and by its tables.
  float ln_quality_at(float bias) const { return ln_quality + (bias != 1.0f ? std::log(bias) : 0.0f); }
  float ecc_slope = 0;           // alpha / e2 [per cpd per deg]
  float distance_per_error = 0;  // Distance rule: distance_scale / tan(1 arcmin)
  float speed_offset = 1;        // tabulated path: v0 = 2 / c2 of the speed grid's weight [deg/s]
  // velocity_terms() tabulated over ln v, linear between nodes (error ~1e-5 in ln S).
  static constexpr int kTermsSize = 2048;
  static constexpr float kTermsLnV0 = -2.31f, kTermsLnV1 = 6.91f;  // 0.0993 .. 1000 deg/s
  VelocityTerms terms[kTermsSize] = {};
  VelocityTerms terms_at(float v) const {
    const float x = (std::log(v) - kTermsLnV0) * float(kTermsSize - 1) / (kTermsLnV1 - kTermsLnV0);
    if (!(x >= 0.0f && x < float(kTermsSize - 1))) return velocity_terms(v, daly);
    const int i = int(x);
    const float w = x - float(i);
    const VelocityTerms& p = terms[i];
    const VelocityTerms& q = terms[i + 1];
    VelocityTerms out;
    out.a_term = p.a_term + w * (q.a_term - p.a_term);
    out.b = p.b + w * (q.b - p.b);
    out.peak = 2.0f / out.b;
    out.ln_s_peak = p.ln_s_peak + w * (q.ln_s_peak - p.ln_s_peak);
    return out;
  }
  // The velocity envelope: u* bound for f in [f_j, f_j+1) [deg/s], and its largest value.
  float upper[kEnvelopeSize] = {};
  VelocityTerms upper_terms[kEnvelopeSize] = {};  // velocity_terms(upper[j])
  float largest = 0;
  int envelope_index(float ln_f) const {
    const float x = (ln_f - kEnvelopeLnF0) * float(kEnvelopeSize - 1) / (kEnvelopeLnF1 - kEnvelopeLnF0);
    if (!(x >= 0)) return 0;
    return x >= float(kEnvelopeSize - 1) ? kEnvelopeSize - 1 : int(x);
  }
  float speed_at(float ln_f) const { return upper[envelope_index(ln_f)]; }

  // The velocity terms a component at ln f [cpd] is evaluated with: its own, or for a moving one
  // slower than the envelope there, the envelope's.
  [[gnu::always_inline]] const VelocityTerms& band_terms(const VelocityTerms& own, float v, float ln_f,
                                                         bool moving) const {
    if (moving && v < largest) {
      const int j = envelope_index(ln_f);
      if (upper[j] > v) return upper_terms[j];
    }
    return own;
  }
  // ln CT of the Default model at frequency f = exp(ln_f) [cpd], eccentricity slope a [per cpd]:
  //   ln S(f, v) = A(v) + 2 ln(2 pi c1 f) - b(v) f above the peak f_p(v) = 2 / b(v), plateau below.
  [[gnu::always_inline]] float default_ln_ct(const VelocityTerms& vt, float ln_f, float f, float a) const {
    return f >= vt.peak ? -vt.a_term - 2.0f * (daly.ln_2pi_c1 + ln_f) + (vt.b + a) * f
                        : -vt.ln_s_peak + a * f;
  }
  // The Default model's terms of retinal speed v [deg/s], still or moving (for ln_ct()).
  VelocityTerms own_terms(float v, bool moving) const { return moving ? terms_at(v) : static_terms; }
  // One component's ln CT at ln f [cpd], eccentricity e [deg], retinal speed v [deg/s], still or moving,
  // ignoring the display: what the exact path computes per band, for the tables' curves. `own` is
  // own_terms(v, moving), computed once for the many frequencies of one speed.
  float ln_ct(const SchedulerConfig& c, float ln_f, float e, float v, bool moving,
              const VelocityTerms& own) const {
    const float f = std::exp(ln_f);
    if (c.model != ThresholdModel::Default)
      return log_threshold(f, e, moving ? v : floor_velocity, c.model, c.params);
    return default_ln_ct(band_terms(own, v, ln_f, moving), ln_f, f, ecc_slope * e);
  }
};

// The tabulated path's threshold curves on the table grid (config-dependent, profile-independent).
struct Scheduler::Curves {
  std::vector<float> still;   // [kStillE][kCurveSamples]: the floor's terms
  std::vector<float> slow;    // [kStillE][kCurveSamples]: moving at the floor (the velocity envelope)
  std::vector<float> moving;  // [kMovingS][kMovingE][kCurveSamples]
  std::vector<float> centre;  // [kMovingS - 1][kMovingE - 1][kCurveSamples]: each moving cell's midpoint
  std::vector<float> still_centre, slow_centre;  // [kStillE - 1][kCurveSamples]: each cell's midpoint
  // Reddy's cutoff H(v) M(e) is separable and kinked (0.825 deg/s, 5.79 deg; -ln H steep and convex
  // towards 118 deg/s), so a cell's midpoint does not show how far interpolation rises above the
  // truth. The largest invisible ln size is ln(band) - ln H(v) - ln M(e) whatever the profile, so how
  // far each node must come down for its cells to stay below it is known in advance, per axis
  // (Lift): [kStillE - 1] and [kMovingS - 1], [kMovingE - 1] (empty for the other models).
  struct Lift {
    float lower, upper;  // [ln deg] at the cell's lower and upper node
  };
  std::vector<Lift> still_lift, speed_lift, moving_e_lift;
  static float speed(std::uint32_t i, float floor) { return floor * std::ldexp(1.0f, int(i)); }
  static float centre_speed(std::uint32_t i, float floor, float v0) {
    return speed_midpoint(speed(i, floor), v0);
  }
  static float centre_e(std::uint32_t j) { return 0.5f * (moving_e_node(j) + moving_e_node(j + 1)); }
  static float still_centre_e(std::uint32_t j) { return 0.5f * (still_e_node(j) + still_e_node(j + 1)); }
  // The least the ends of a cell must come down (a at w = 0, b at w = 1, both >= 0, a + b least) for
  // the chord of f to stay at or below f over the cell, at 4096 weights w in [0, 1] mapped to the axis
  // by x(w): {0, 0} where f is concave.
  template <class F, class X>
  static Lift chord_lift(F f, X x) {
    constexpr int kSteps = 4096;
    const float f0 = f(x(0.0f)), f1 = f(x(1.0f));
    float rise[kSteps + 1];
    float most_a = 0;  // a with b = 0
    for (int i = 0; i <= kSteps; ++i) {
      const float w = float(i) / float(kSteps);
      rise[i] = f0 + w * (f1 - f0) - f(x(w));
      if (i < kSteps) most_a = std::max(most_a, rise[i] / (1.0f - w));
    }
    auto least_b = [&](float a) {  // the least b >= 0 that covers every sample given a
      float b = 0;
      for (int i = 1; i <= kSteps; ++i) {
        const float w = float(i) / float(kSteps);
        b = std::max(b, (rise[i] - a * (1.0f - w)) / w);
      }
      return b;
    };
    float lo = 0, hi = most_a;  // a + least_b(a) is convex in a: ternary search
    for (int it = 0; it < 60; ++it) {
      const float m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (m1 + least_b(m1) <= m2 + least_b(m2))
        hi = m2;
      else
        lo = m1;
    }
    return {hi, least_b(hi)};
  }
  // Reddy's lifts (see still_lift): per axis, -ln M(e) and -ln H(v) against the weights the frame
  // loop interpolates with (e_cell, speed_cell).
  void reddy_lifts(float floor, float v0) {
    auto ln_size_e = [](float e) { return -std::log(reddy_eccentricity(e)); };
    auto ln_size_v = [](float v) { return -std::log(reddy_velocity(v)); };
    auto e_axis = [](float lower, float upper) {
      return [=](float w) { return lower + w * (upper - lower); };
    };
    for (std::uint32_t j = 0; j + 1 < kStillE; ++j)
      still_lift.push_back(chord_lift(ln_size_e, e_axis(still_e_node(j), still_e_node(j + 1))));
    for (std::uint32_t j = 0; j + 1 < kMovingE; ++j)
      moving_e_lift.push_back(chord_lift(ln_size_e, e_axis(moving_e_node(j), moving_e_node(j + 1))));
    for (std::uint32_t i = 0; i + 1 < kMovingS; ++i) {
      const float lo = speed(i, floor), inv_g = (3.0f * lo + 2.0f * v0) / lo;
      // speed_cell()'s weight w = g inv_g, g = (v - lo) / (v + lo + 2 v0), solved for v.
      speed_lift.push_back(chord_lift(ln_size_v, [=](float w) {
        const float g = w / inv_g;
        return (lo + g * (lo + 2.0f * v0)) / (1.0f - g);
      }));
    }
  }
  // Samples ln CT over the curve's range and makes it non-decreasing from the top (suffix minimum).
  static void sample(const Precomputed& pre, const SchedulerConfig& c, float e, float v, bool moving,
                     float* out) {
    const VelocityTerms own = pre.own_terms(v, moving);
    for (int i = 0; i < kCurveSamples; ++i)
      out[i] = pre.ln_ct(c, kCurveU0 + kCurveStep * float(i), e, v, moving, own);
    for (int i = kCurveSamples - 2; i >= 0; --i) out[i] = std::min(out[i], out[i + 1]);
  }
  // ln of the largest angular diameter [ln deg] at which a component of band ln_band [ln cpod] with
  // ln lost contrast y (already divided by q) stays at or below threshold: ln_band - u*, u* the
  // smallest ln f above which the curve stays >= y. Bisection on the model itself refines the sampled
  // bracket; the upper end is kept, so the result errs small (conservative).
  // The same from the samples alone: ln_band - (the upper end of the sampled bracket), at most one
  // sample step below largest_size(). `bracket` receives the sample index of that upper end (-1: the
  // curve's ends decided, nothing to refine).
  // `hint` (a sample index, e.g. the bracket at the neighbouring grid node) starts a galloping search
  // there: the same bracket in a few steps where neighbouring nodes' answers lie close.
  static float sampled_size(const float* curve, float y, float ln_band, int* bracket,
                            int hint = kCurveSamples / 2) {
    *bracket = -1;
    if (!(y > curve[0])) return ln_band - kCurveU0;
    if (y > curve[kCurveSamples - 1]) return ln_band - kCurveU1;
    int lo = 0, hi = kCurveSamples - 1;  // curve[lo] < y <= curve[hi]
    hint = std::clamp(hint, 1, kCurveSamples - 1);
    if (curve[hint] >= y) {  // gallop down from the hint
      hi = hint;
      for (int step = 1; hi - step > 0; step *= 2) {
        if (curve[hi - step] < y) {
          lo = hi - step;
          break;
        }
        hi -= step;
      }
    } else {  // gallop up
      lo = hint;
      for (int step = 1; lo + step < kCurveSamples - 1; step *= 2) {
        if (curve[lo + step] >= y) {
          hi = lo + step;
          break;
        }
        lo += step;
      }
    }
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (curve[mid] >= y ? hi : lo) = mid;
    }
    *bracket = hi;
    return ln_band - (kCurveU0 + kCurveStep * float(hi));
  }
  static float refine(const Precomputed& pre, const SchedulerConfig& c, int bracket, float y, float ln_band,
                      float e, float v, bool moving) {
    float ulo = kCurveU0 + kCurveStep * float(bracket - 1), uhi = kCurveU0 + kCurveStep * float(bracket);
    const VelocityTerms own = pre.own_terms(v, moving);
    for (int i = 0; i < 6; ++i) {
      const float mid = 0.5f * (ulo + uhi);
      (pre.ln_ct(c, mid, e, v, moving, own) >= y ? uhi : ulo) = mid;
    }
    return ln_band - uhi;
  }
  static float largest_size(const Precomputed& pre, const SchedulerConfig& c, const float* curve, float y,
                            float ln_band, float e, float v, bool moving, int* hint) {
    int bracket;
    const float sampled = sampled_size(curve, y, ln_band, &bracket, *hint);
    if (bracket >= 0) *hint = bracket;
    return bracket < 0 ? sampled : refine(pre, c, bracket, y, ln_band, e, v, moving);
  }
  // min over bands of largest_size(): sampled for every band, refined only where it can be the minimum
  // (a refinement raises a value by less than one sample step). Same result, a fraction of the work.
  static float smallest_size(const Precomputed& pre, const SchedulerConfig& c, const float* curve,
                             const float* y, const float* ln_band, std::uint32_t bands, float e, float v,
                             bool moving, int* hint) {
    float sampled[kMaxBands];
    int bracket[kMaxBands];
    float least = -kNever;
    for (std::uint32_t b = 0; b < bands; ++b) {
      sampled[b] = sampled_size(curve, y[b], ln_band[b], &bracket[b], hint[b]);
      if (bracket[b] >= 0) hint[b] = bracket[b];
      least = std::min(least, sampled[b]);
    }
    float m = -kNever;
    for (std::uint32_t b = 0; b < bands; ++b)
      m = std::min(m, bracket[b] >= 0 && sampled[b] <= least + 1.01f * kCurveStep
                          ? refine(pre, c, bracket[b], y[b], ln_band[b], e, v, moving)
                          : sampled[b]);
    return m;
  }
};

struct Scheduler::EyeCache {
  double position[3];
  float rotation[4];
  Vec3 forward;   // world
  Vec3 velocity;  // world [m/s]
  Vec3 omega;     // head angular velocity, world [rad/s]
  bool valid;
  bool gaze;                      // a usable gaze this frame
  Vec3 gaze_dir;                  // world, unit
  bool gaze_moving;               // measured gaze velocity
  Vec3 gaze_velocity;             // world tangent velocity of the gaze direction [deg/s]
  float focal_px;                 // horizontal focal length [px]
  float center_right, center_up;  // tangent offsets of the projection centre (off-axis frusta)
};

// Per eye and object, the last decision made over whole cells or around the object's place in them:
// by the bounds over every view (tabulate()'s pass 3), or through the object's view (pass 6,
// kThroughView in the key; at its place, a still image's; over its cells' quarters, a moving one's),
// with the inputs under which it stands:
// the same key (eccentricity cell, still or not, table set), the same bands shown (f_lo * inv_diam
// <= Nyquist < f_hi * inv_diam: the lowest shown band and the next one, +inf past the profile's), x
// and the cell's weight in the Stand, where no line it compared against lies; through the view also
// the same view_key and speed_key. Tables never change once built, so within these the decision is
// the one the rows would give again: an object kept still, or moving steadily, is decided from its
// own memo without reading a table. Object slots start (add_object) with no memo.
struct Scheduler::Memo {
  static constexpr std::uint16_t kNone = 0xffff;  // a key no object has
  static constexpr std::uint16_t kThroughView = 1 << 14;
  static std::uint32_t key_of(std::uint32_t ec, std::uint32_t still, std::uint32_t tables) {
    return ec | still << 5 | tables << 6;
  }
  static_assert(kStillE - 1 < 32 && ((kStillE - 1) | 1 << 5 | 255 << 6) < kThroughView,
                "the key's fields (bias_tables_ is a byte) fit under kThroughView (and so kNone)");
  // Through the view: the view (Max3: the lookup cell, whose candidates are the views), whether the
  // image slips in the view's axes, and then its eccentricity cell on the moving grid and each
  // orientation's speed cell, 4 bits each (profiles of at most kSpeedKeyOrientations orientations:
  // a moving object of a profile with more is not remembered through its view). A moving image's
  // decision that its whole cells leave open may stand over the quarters of its cells it lies in
  // (kQuartered; the eccentricity cell of the still grid too, in w_from and w_to): the keys then
  // also hold the moving eccentricity cell's quarter and each orientation's speed quarter, 2 bits
  // each (profiles of at most kQuarterKeyOrientations orientations).
  static constexpr std::uint32_t kSpeedKeyOrientations = 16, kQuarterKeyOrientations = 10;
  static constexpr std::uint32_t kQuartered = 1 << 7;
  // A decision through the view that stands only at the object's place (the whole cells left it
  // open, and it moves, or no box around its place keeps it): its fine and coarse level in the memo.
  static constexpr std::uint8_t kAtPlace = 255;
  static_assert(kMovingE - 2 < 16 && kMovingS - 2 < 16, "cells fit 4 bits");
  static_assert(6 * kMaxLookupResolution * kMaxLookupResolution < (1u << 24) && kMaxViews < (1u << 24),
                "view_key's fields fit 32 bits");
  static_assert(6 * kQuarterKeyOrientations <= 64, "speed_key's cells and quarters fit 64 bits");
  static bool keyable(bool moving, std::uint32_t T) { return !moving || T <= kSpeedKeyOrientations; }
  static bool quarterable(std::uint32_t T) { return T <= kQuarterKeyOrientations; }
  // The keys of a probe's view and cells (o.cells set where it moves), with the quarters or not.
  static std::uint32_t view_key_of(const Probe& o, bool quartered);
  static std::uint64_t speed_key_of(const Probe& o, std::uint32_t T, bool quartered);
  // A decision stands for x [1/1024 ln deg] in [x_from, x_to] (Stand's (lo, hi]) and for the
  // eccentricity cell's weight w in [w_from, w_to] / kWeightSteps (every w for a decision made over
  // the whole cell).
  std::vector<std::uint16_t> key;
  std::vector<std::int16_t> x_from, x_to;
  std::vector<std::uint16_t> w_from, w_to;
  std::vector<float> f_lo, f_hi;  // band centres [cpod]
  std::vector<std::uint8_t> fine, coarse;
  std::vector<std::uint32_t> view_key;  // read only where the key has kThroughView
  std::vector<std::uint64_t> speed_key;
  // Where a decision through the view (not kAtPlace) keeps its view_key and speed_key, so that the
  // frame loop need not find the view and the slip in its axes again: while the direction from the
  // object to the eye (object space) stays within `turn` [chord of unit vectors] of `direction`, the
  // retinal slip [deg/s] within `reach` of `slip`, and the eccentricity [deg] in [e_from, e_to], and
  // the object's rotation is the same (set_transform ends it otherwise). turn < 0: none.
  struct Hold {
    float direction[3];
    float turn;
    float slip[3];
    float reach;
    float e_from, e_to;
  };
  std::vector<Hold> hold;
  // Rests: while the eye stays within rest_m [m] of where it was in frame rest_frame, and its gaze
  // and head turn at most rest_deg from where they pointed, every input the memo tests stays inside
  // its box (stands_at_rest()), so the memo decides without the object's geometry. rest_m < 0: none.
  // A rest lasts fewer than kPoses frames (staggered by id, so they do not all end in one frame). One
  // the eye left is set again after kLeftRetry frames, and where none could be set, after kRetry (an
  // eye that keeps moving sets few).
  static constexpr std::uint32_t kPoses = 256, kLeftRetry = 8, kRetry = 64;
  static std::uint32_t rest_frames(ObjectId id) { return kPoses / 2 + (id & (kPoses / 2 - 1)); }
  std::vector<std::uint32_t> rest_frame;
  std::vector<float> rest_m, rest_deg;
  // The eye of the last kPoses frames (by frame % kPoses) and how far it is from each now: moved [m]
  // and turned [deg] (gaze or head, the larger), +inf where either frame could not rest (the eye
  // moved by a velocity, an image slipped, no valid eye, another gaze state or focal length).
  struct Pose {
    double position[3];
    Vec3 gaze, forward;
    float focal_px;
    bool gaze_valid, usable;
  };
  Pose pose[kPoses]{};
  float moved[kPoses], turned[kPoses];
  float recent_m = 0, recent_deg = 0;  // the most moved and turned over the last 4 frames that could rest
  bool usable = false;                 // this frame's pose can rest
  void end_rest(ObjectId id) { rest_m[id] = -1.0f; }
  void end_hold(ObjectId id) { hold[id].turn = -1.0f; }
  explicit Memo(std::size_t n = 0)
      : key(n, kNone),
        x_from(n, 0),
        x_to(n, 0),
        w_from(n, 0),
        w_to(n, 0),
        f_lo(n, kInf),
        f_hi(n, kInf),
        fine(n, 0),
        coarse(n, 0),
        view_key(n, 0),
        speed_key(n, 0),
        hold(n, Hold{{0, 0, 0}, -1.0f, {0, 0, 0}, 0.0f, 0.0f, 0.0f}),
        rest_frame(n, 0u - kPoses),
        rest_m(n, -1.0f),
        rest_deg(n, -1.0f) {
    std::fill(moved, moved + kPoses, kInf);
    std::fill(turned, turned + kPoses, kInf);
  }
  // Frame `frame`'s pose of an eye (nullptr: an eye not used this frame).
  void observe(std::uint32_t frame, const EyeCache* eye);
  // Remembers object id's decision (fine, coarse) where it stands, with `bands` of the profile's
  // band centres `frequency` shown.
  void remember(ObjectId id, std::uint32_t key_bits, const Stand& stand, const float* frequency,
                std::uint32_t bands, int fine_level, int coarse_level) {
    key[id] = static_cast<std::uint16_t>(key_bits);
    end_rest(id);  // a rest and a hold are set for the decision they stand with
    end_hold(id);
    x_from[id] = static_cast<std::int16_t>(stand.lo + 1);
    x_to[id] = static_cast<std::int16_t>(stand.hi);
    w_from[id] = stand.w_from;
    w_to[id] = stand.w_to;
    f_lo[id] = frequency[bands - 1];
    f_hi[id] = bands < kMaxBands ? frequency[bands] : kInf;
    fine[id] = static_cast<std::uint8_t>(fine_level);
    coarse[id] = static_cast<std::uint8_t>(coarse_level);
  }
};

void Scheduler::Memo::observe(std::uint32_t frame, const EyeCache* eye) {
  Pose now{};
  const auto zero = [](Vec3 v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; };
  // A still image stays still only while nothing moves it: no eye or head velocity, no gaze velocity.
  usable = eye && eye->valid && zero(eye->velocity) && zero(eye->omega) && !eye->gaze_moving;
  if (usable) {
    now = {{eye->position[0], eye->position[1], eye->position[2]},
           eye->gaze_dir,
           eye->forward,
           eye->focal_px,
           eye->gaze,
           true};
  }
  pose[frame % kPoses] = now;
  const auto turn_deg = [](Vec3 a, Vec3 b) {  // in double: the angle between the floats as they are
    const double x = double(a.y) * b.z - double(a.z) * b.y, y = double(a.z) * b.x - double(a.x) * b.z,
                 z = double(a.x) * b.y - double(a.y) * b.x;
    const double c = double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z;
    return std::atan2(std::sqrt(x * x + y * y + z * z), c) * (180.0 / std::numbers::pi);
  };
  recent_m = recent_deg = 0.0f;
  for (std::uint32_t k = 0; k < kPoses; ++k) {
    const Pose& p = pose[k];
    if (!(usable && p.usable && p.gaze_valid == now.gaze_valid && p.focal_px == now.focal_px)) {
      moved[k] = turned[k] = kInf;
      continue;
    }
    double dd = 0;
    for (int c = 0; c < 3; ++c) dd += (now.position[c] - p.position[c]) * (now.position[c] - p.position[c]);
    moved[k] = static_cast<float>(std::sqrt(dd) * (1.0 + 1e-6));
    turned[k] =
        static_cast<float>(std::max(turn_deg(now.gaze, p.gaze), turn_deg(now.forward, p.forward)) + 1e-6);
    if ((frame - k) % kPoses < 4) {  // frame's and the 3 before it
      recent_m = std::max(recent_m, moved[k]);
      recent_deg = std::max(recent_deg, turned[k]);
    }
  }
}

// What a rest's check reads of an object and one eye now.
struct Scheduler::RestProbe {
  float d, r;                       // distance, radius [m]
  float gaze_angle, forward_angle;  // from the direction to the object to the gaze's and the head's [deg]
  float view_margin;                // how far [rad] the direction may turn before its view can change
  float half_focal, offset;         // as look_block() reads them
};

// Whether the memo of object id keeps deciding while the eye moves at most m [m] and the gaze and head
// turn at most t [deg]: each input the memo tests (table_inputs()), computed as the frame loop
// computes it at the ends of its range, stays inside the memo's box. The direction to the object
// turns by at most asin(m / d); the angular radius and x are monotone in d (a table step of room for
// the fast functions' ulps); the eccentricity cell and its weight are monotone in e.
bool Scheduler::stands_at_rest(const Memo& memo, ObjectId id, const RestProbe& h, float m, float t) const {
  const float room_d = 1e-5f * h.d;  // float error of the distance as computed
  const float d_near = h.d - m - room_d, d_far = h.d + m + room_d;
  if (!(d_near > h.r) || !(m + room_d < h.d)) return false;
  const float alpha = std::asin((m + room_d) / h.d);  // [rad]
  if (!(alpha + 1e-5f < h.view_margin)) return false;
  const float radius_near = angular_radius_deg(d_near, h.r), radius_far = angular_radius_deg(d_far, h.r);
  // x: one table step of room each side (the box's ends past the entries need none).
  const std::int32_t x_near = size_steps_above(ln_positive(2.0f * radius_near)),
                     x_far = size_steps_above(ln_positive(2.0f * radius_far));
  if (!(memo.x_from[id] == kLeastEntry || x_far > memo.x_from[id])) return false;
  if (!(memo.x_to[id] == Stand::kNoHigh || x_near < memo.x_to[id])) return false;
  // Eccentricity: max(0, angle to the gaze - radius - offset).
  const float turn = kDeg * alpha + t;
  const float room_e = 1e-3f + 1e-5f * (h.gaze_angle + radius_near);
  const Cell low = e_cell<kStillE>(std::max(0.0f, h.gaze_angle - turn - radius_near - h.offset - room_e));
  const Cell high = e_cell<kStillE>(std::max(0.0f, h.gaze_angle + turn - radius_far - h.offset + room_e));
  const std::uint32_t cell = memo.key[id] & 31u;
  if (low.j != cell || high.j != cell) return false;
  if (!(float(memo.w_from[id]) <= low.w * kWeightSteps && high.w * kWeightSteps <= float(memo.w_to[id])))
    return false;
  // The bands shown: f_lo / diameter <= Nyquist < f_hi / diameter over the range of both.
  const double phi_low = std::max(0.0, double(h.forward_angle) - turn - 1e-3) * kRad,
               phi_high = std::min(180.0, double(h.forward_angle) + turn + 1e-3) * kRad;
  const float cos_most = std::clamp(float(std::cos(phi_low)) + 1e-6f, 0.05f, 1.0f),
              cos_least = std::clamp(float(std::cos(phi_high)) - 1e-6f, 0.05f, 1.0f);
  const float nyquist_least = h.half_focal / (cos_most * cos_most) * (1.0f - 1e-5f),
              nyquist_most = h.half_focal / (cos_least * cos_least) * (1.0f + 1e-5f);
  const float inv_diam_most = 1.0f / (2.0f * radius_far) * (1.0f + 1e-5f),
              inv_diam_least = 1.0f / (2.0f * radius_near) * (1.0f - 1e-5f);
  return memo.f_lo[id] * inv_diam_most <= nyquist_least && memo.f_hi[id] * inv_diam_least > nyquist_most;
}

Scheduler::Scheduler(const SchedulerConfig& config) : config_(config) {
  if (config_.triangle_budget > 0) config_.keep_scores = true;  // the budget pass needs them
  const std::size_t n = config_.max_objects;
  profiles_.resize(config_.max_profiles);
  profile_of_.assign(n, -1);
  for (int k = 0; k < 3; ++k) {
    position_[k].assign(n, 0.0);
    previous_position_[k].assign(n, 0.0);
    velocity_[k].assign(n, 0.0f);
  }
  for (int k = 0; k < 4; ++k) {
    rotation_[k].assign(n, k == 3 ? 1.0f : 0.0f);
    sphere_[k].assign(n, 0.0f);
  }
  bias_.assign(n, 1.0f);
  bias_tables_.assign(n, 0);
  table_bias_count_ = table_biases(config_, table_bias_);
  explicit_velocity_.assign(n, 0);
  fresh_.assign(n, 0);
  min_level_.assign(n, 0);
  max_level_.assign(n, 255);
  chosen_.assign(n, 0);
  next_.assign(n, 0);
  level_.assign(n, 0);
  from_level_.assign(n, 0);
  flags_.assign(n, 0);
  calm_frames_.assign(n, 0);
  wait_frames_.assign(n, 0);
  fade_.assign(n, 1.0f);
  rest_.assign(n, 0);
  if (config_.keep_scores) scores_.assign(n * kMaxLevels, 0.0f);
  free_list_.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) free_list_.push_back(static_cast<std::uint32_t>(n - 1 - i));
  heap_.reserve(n);
  eyes_.resize(2);
  const std::size_t slots = std::size_t(config_.max_profiles) * kMaxLevels;
  level_count_.assign(config_.max_profiles, 1);
  band_frequency_.assign(std::size_t(config_.max_profiles) * kMaxBands, kInf);
  triangles_.assign(slots, 0);
  error_size_.assign(slots, 0.0f);
  for (std::vector<float>& t : error_threshold_) t.assign(slots, kInf);
  pre_ = std::make_unique<Precomputed>();
  Precomputed& pre = *pre_;
  pre.daly = daly_constants(config_.params);
  const bool daly_model =
      config_.model == ThresholdModel::Default || config_.model == ThresholdModel::KellyDaly;
  pre.floor_velocity = daly_model ? pre.daly.v_floor : static_cast<float>(config_.params.drift);
  // Reddy's H(v) is flat up to 0.825 deg/s, so its speed grid may start at the default drift whatever
  // the configured one (a floor near 0 would crowd the grid's octaves below 1 deg/s); the exact
  // path's speeds are floored there too, which changes no threshold, H being flat there.
  if (config_.model == ThresholdModel::Reddy)
    pre.floor_velocity = std::max(pre.floor_velocity, static_cast<float>(ModelParams{}.drift));
  pre.static_terms = velocity_terms(std::max(pre.floor_velocity, 1e-3f), pre.daly);
  pre.ln_quality = std::log(config_.quality);
  pre.ln_margin = std::log(std::max(1e-6f, 1.0f - config_.hysteresis_margin));
  pre.ecc_slope = static_cast<float>(config_.params.alpha / config_.params.e2);
  pre.distance_per_error = config_.distance_scale / std::tan(kRad / 60.0f);
  pre.speed_offset = 2.0f / pre.daly.c2;
  for (int i = 0; i < Precomputed::kTermsSize; ++i)
    pre.terms[i] = velocity_terms(
        std::exp(Precomputed::kTermsLnV0 + (Precomputed::kTermsLnV1 - Precomputed::kTermsLnV0) * float(i) /
                                               float(Precomputed::kTermsSize - 1)),
        pre.daly);
  const double step = (kEnvelopeLnF1 - kEnvelopeLnF0) / (kEnvelopeSize - 1);
  double previous = argmax_speed(std::exp(kEnvelopeLnF0), config_.params);
  for (int j = 0; j < kEnvelopeSize; ++j) {
    const double ln_f = kEnvelopeLnF0 + step * j;
    const double mid = argmax_speed(std::exp(ln_f + 0.5 * step), config_.params);
    const double next = argmax_speed(std::exp(ln_f + step), config_.params);
    const double u = std::max({previous, mid, next}) * 1.02;  // the interval's largest, plus a step
    pre_->upper[j] = u <= config_.params.drift * 1.02 ? 0.0f : float(u);
    if (pre_->upper[j] > 0) pre_->upper_terms[j] = velocity_terms(pre_->upper[j], pre_->daly);
    pre_->largest = std::max(pre_->largest, pre_->upper[j]);
    previous = next;
  }
  if (tabulated()) {
    memos_ = std::unique_ptr<Memo[]>(new Memo[2]{Memo(n), Memo(n)});
    curves_ = std::make_unique<Curves>();
    curves_->still.resize(std::size_t(kStillE) * kCurveSamples);
    curves_->slow.resize(std::size_t(kStillE) * kCurveSamples);
    for (std::uint32_t j = 0; j < kStillE; ++j) {
      Curves::sample(pre, config_, still_e_node(j), pre.floor_velocity, false,
                     &curves_->still[j * std::size_t(kCurveSamples)]);
      Curves::sample(pre, config_, still_e_node(j), pre.floor_velocity, true,
                     &curves_->slow[j * std::size_t(kCurveSamples)]);
    }
    curves_->moving.resize(std::size_t(kMovingS) * kMovingE * kCurveSamples);
    for (std::uint32_t i = 0; i < kMovingS; ++i)
      for (std::uint32_t j = 0; j < kMovingE; ++j)
        Curves::sample(pre, config_, moving_e_node(j), Curves::speed(i, pre.floor_velocity), true,
                       &curves_->moving[(i * kMovingE + j) * std::size_t(kCurveSamples)]);
    // Each cell's interpolation is checked against the truth: Reddy's per axis in advance, the other
    // models' at the cell's midpoint (curves there).
    if (config_.model == ThresholdModel::Reddy) {
      curves_->reddy_lifts(pre.floor_velocity, pre.speed_offset);
    } else {
      curves_->still_centre.resize(std::size_t(kStillE - 1) * kCurveSamples);
      curves_->slow_centre.resize(std::size_t(kStillE - 1) * kCurveSamples);
      for (std::uint32_t j = 0; j + 1 < kStillE; ++j) {
        Curves::sample(pre, config_, Curves::still_centre_e(j), pre.floor_velocity, false,
                       &curves_->still_centre[j * std::size_t(kCurveSamples)]);
        Curves::sample(pre, config_, Curves::still_centre_e(j), pre.floor_velocity, true,
                       &curves_->slow_centre[j * std::size_t(kCurveSamples)]);
      }
      curves_->centre.resize(std::size_t(kMovingS - 1) * (kMovingE - 1) * kCurveSamples);
      for (std::uint32_t i = 0; i + 1 < kMovingS; ++i)
        for (std::uint32_t j = 0; j + 1 < kMovingE; ++j)
          Curves::sample(pre, config_, Curves::centre_e(j),
                         Curves::centre_speed(i, pre.floor_velocity, pre.speed_offset), true,
                         &curves_->centre[(i * (kMovingE - 1) + j) * std::size_t(kCurveSamples)]);
    }
  }
}

// Fills the tabulated path's tables of one profile (see ProfileCache).
void Scheduler::build_tables(ProfileCache& c) const {
  const Profile& p = c.profile;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count, L = K - 1;
  const Precomputed& pre = *pre_;
  const auto margins = static_cast<std::uint32_t>(margin_sets(config_));
  const bool midpoints = curves_->still_lift.empty();  // each cell checked at its midpoint (not Reddy)
  for (std::uint32_t set = 0; set < 2 * table_bias_count_; ++set) {
    if (set % 2 >= margins) continue;
    const float ln_bias_q = pre.ln_quality_at(table_bias_[set / 2]);
    const float ln_q = set % 2 ? ln_bias_q + pre.ln_margin : ln_bias_q;
    std::vector<std::int16_t>& still = c.sets[set].still;
    std::vector<std::int16_t>& moving = c.sets[set].moving;
    still.assign(std::size_t(V) * L * B * kStillE, 0);
    c.sets[set].slow.assign(std::size_t(V) * L * B * kStillE, 0);
    moving.assign(std::size_t(V) * L * T * kMovingS * kMovingE, 0);
    for (std::uint32_t w = 0; w < V; ++w)
      for (std::uint32_t k = 1; k < K; ++k) {
        const std::size_t kv = std::size_t(k - 1) * V + w;
        // Still and slow: per band, then the minimum over the bands the display shows (prefix minima).
        // Where a cell's midpoint shows the interpolation above the truth (a convex kink: the CSF's
        // peak, a model's eccentricity step), the cell's two nodes come down by the excess.
        for (int moving_floor = 0; moving_floor < 2; ++moving_floor) {
          const bool slow = moving_floor != 0;
          float node[kStillE][kMaxBands], mid[kStillE][kMaxBands];
          int hint[kMaxBands], mid_hint[kMaxBands];  // each band's bracket at the previous node
          std::fill(hint, hint + kMaxBands, kCurveSamples / 2);
          std::fill(mid_hint, mid_hint + kMaxBands, kCurveSamples / 2);
          for (std::uint32_t j = 0; j < kStillE; ++j) {
            const float* curve = &(slow ? curves_->slow : curves_->still)[j * std::size_t(kCurveSamples)];
            float prefix = -kNever, mid_prefix = -kNever;
            for (std::uint32_t b = 0; b < B; ++b) {
              const float y = c.ln_lost_any[kv * B + b] - ln_q;
              prefix =
                  std::min(prefix, Curves::largest_size(pre, config_, curve, y, c.ln_band[b], still_e_node(j),
                                                        pre.floor_velocity, slow, &hint[b]));
              node[j][b] = prefix;
              if (j + 1 < kStillE && midpoints) {
                const float* centre =
                    &(slow ? curves_->slow_centre : curves_->still_centre)[j * std::size_t(kCurveSamples)];
                mid_prefix =
                    std::min(mid_prefix, Curves::largest_size(pre, config_, centre, y, c.ln_band[b],
                                                              Curves::still_centre_e(j), pre.floor_velocity,
                                                              slow, &mid_hint[b]));
              }
              mid[j][b] = mid_prefix;
            }
          }
          float lower[kStillE][kMaxBands] = {};
          for (std::uint32_t j = 0; j + 1 < kStillE; ++j)
            for (std::uint32_t b = 0; b < B; ++b) {
              if (node[j][b] <= kNever || node[j + 1][b] >= -kNever) continue;
              if (!midpoints) {  // Reddy: known in advance
                lower[j][b] = std::max(lower[j][b], curves_->still_lift[j].lower);
                lower[j + 1][b] = std::max(lower[j + 1][b], curves_->still_lift[j].upper);
                continue;
              }
              const float excess = 0.5f * (node[j][b] + node[j + 1][b]) - mid[j][b];
              if (excess > 0) {
                lower[j][b] = std::max(lower[j][b], excess);
                lower[j + 1][b] = std::max(lower[j + 1][b], excess);
              }
            }
          std::vector<std::int16_t>& table = slow ? c.sets[set].slow : still;
          for (std::uint32_t j = 0; j < kStillE; ++j)
            for (std::uint32_t b = 0; b < B; ++b)
              table[((std::size_t(w) * B + b) * kStillE + j) * L + (k - 1)] =
                  encode_size(node[j][b] - lower[j][b]);
        }
        // Moving: per orientation, every band.
        for (std::uint32_t t = 0; t < T; ++t) {
          float y[kMaxBands];
          for (std::uint32_t b = 0; b < B; ++b) y[b] = c.ln_lost[(kv * T + t) * B + b] - ln_q;
          int hint[kMaxBands], centre_hint[kMaxBands];  // each band's bracket at the previous node
          std::fill(hint, hint + kMaxBands, kCurveSamples / 2);
          std::fill(centre_hint, centre_hint + kMaxBands, kCurveSamples / 2);
          auto largest = [&](const float* curve, float e, float v, int* h) {
            return Curves::smallest_size(pre, config_, curve, y, c.ln_band.data(), B, e, v, true, h);
          };
          float node[kMovingS * kMovingE];
          for (std::uint32_t i = 0; i < kMovingS; ++i)
            for (std::uint32_t j = 0; j < kMovingE; ++j)
              node[i * kMovingE + j] =
                  largest(&curves_->moving[(i * kMovingE + j) * std::size_t(kCurveSamples)], moving_e_node(j),
                          Curves::speed(i, pre.floor_velocity), hint);
          // Concave along each axis keeps the cell's edges below; where the midpoint shows the
          // bilinear surface above the truth, the cell's corners come down by the excess.
          float lower[kMovingS * kMovingE] = {};
          for (std::uint32_t i = 0; i + 1 < kMovingS; ++i)
            for (std::uint32_t j = 0; j + 1 < kMovingE; ++j) {
              float* corner[4] = {&node[i * kMovingE + j], &node[i * kMovingE + j + 1],
                                  &node[(i + 1) * kMovingE + j], &node[(i + 1) * kMovingE + j + 1]};
              if (*corner[0] <= kNever || *corner[3] >= -kNever) continue;
              if (!midpoints) {  // Reddy: known in advance
                const Curves::Lift v = curves_->speed_lift[i], e = curves_->moving_e_lift[j];
                const float lift[4] = {v.lower + e.lower, v.lower + e.upper, v.upper + e.lower,
                                       v.upper + e.upper};
                for (int n = 0; n < 4; ++n)
                  lower[corner[n] - node] = std::max(lower[corner[n] - node], lift[n]);
                continue;
              }
              const float mean = 0.25f * (*corner[0] + *corner[1] + *corner[2] + *corner[3]);
              const float truth =
                  largest(&curves_->centre[(i * (kMovingE - 1) + j) * std::size_t(kCurveSamples)],
                          Curves::centre_e(j), Curves::centre_speed(i, pre.floor_velocity, pre.speed_offset),
                          centre_hint);
              const float excess = mean - truth;
              if (excess > 0)
                for (float* q : corner) lower[q - node] = std::max(lower[q - node], excess);
            }
          for (std::uint32_t i = 0; i < kMovingS * kMovingE; ++i)
            moving[((std::size_t(w) * T + t) * kMovingS * kMovingE + i) * L + (k - 1)] =
                encode_size(node[i] - lower[i] - kBilinearMargin);
        }
      }
    std::vector<std::int16_t>& any = c.sets[set].any_view;
    const std::size_t width = 2 * std::size_t(L) + 1;
    any.assign(L > 0 ? std::size_t(B) * kStillE * width : 0, 0);
    for (std::uint32_t n = 0; n < B && L > 0; ++n)
      for (std::uint32_t j = 0; j < kStillE; ++j) {
        std::int16_t* row = &any[(std::size_t(n) * kStillE + j) * width];
        std::fill(row, row + L, std::numeric_limits<std::int16_t>::max());
        std::fill(row + L, row + 2 * L, std::numeric_limits<std::int16_t>::min());
        row[2 * L] = std::numeric_limits<std::int16_t>::max();
        for (std::uint32_t w = 0; w < V; ++w)
          for (std::uint32_t k = 0; k < L; ++k) {
            const std::size_t at = ((std::size_t(w) * B + n) * kStillE + j) * L + k;
            row[k] = std::min(row[k], still[at]);
            row[L + k] = std::max(row[L + k], still[at]);
            if (k + 1 == L) row[2 * L] = std::min({row[2 * L], still[at], c.sets[set].slow[at]});
          }
      }
  }
}

std::size_t Scheduler::table_bytes(const ProfileMeta& m, const SchedulerConfig& config) {
  if (!tabulated(config) || m.level_count < 2) return 0;
  const std::size_t per_set =
      std::size_t(m.view_count) * (m.level_count - 1) *
      (2 * std::size_t(m.band_count) * kStillE + std::size_t(m.orientation_count) * kMovingS * kMovingE);
  const std::size_t any_view = std::size_t(m.band_count) * kStillE * (2 * (m.level_count - 1) + 1);
  float biases[1 + kMaxTabulatedBiases];
  return (per_set + any_view) * std::size_t(margin_sets(config)) * table_biases(config, biases) *
         sizeof(std::int16_t);
}

std::size_t Scheduler::table_bytes(int profile) const {
  if (profile < 0 || profile >= static_cast<int>(profile_count_)) return 0;
  const ProfileCache& c = profiles_[profile];
  std::size_t n = 0;
  for (std::uint32_t set = 0; set < kTableSets; ++set)
    n += c.sets[set].still.size() + c.sets[set].slow.size() + c.sets[set].moving.size() +
         c.sets[set].any_view.size();
  return n * sizeof(std::int16_t);
}

float Scheduler::envelope_speed(float frequency_cpd) const { return pre_->speed_at(std::log(frequency_cpd)); }

Scheduler::~Scheduler() = default;

int Scheduler::add_profile(const Profile& p) {
  if (profile_count_ >= config_.max_profiles) return -1;
  ProfileCache& c = profiles_[profile_count_];
  c.profile = p;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count;
  c.ln_lost.resize(std::size_t(K - 1) * V * T * B);
  for (std::size_t i = 0; i < c.ln_lost.size(); ++i)
    c.ln_lost[i] = p.lost[i] > 0 ? std::log(p.lost[i]) : -kInf;
  c.ln_lost_any.assign(std::size_t(K - 1) * V * B, -kInf);
  for (std::size_t kv = 0; kv < std::size_t(K - 1) * V; ++kv)
    for (std::uint32_t t = 0; t < T; ++t)
      for (std::uint32_t b = 0; b < B; ++b)
        c.ln_lost_any[kv * B + b] = std::max(c.ln_lost_any[kv * B + b], c.ln_lost[(kv * T + t) * B + b]);
  c.ln_band.resize(B);
  for (std::uint32_t b = 0; b < B; ++b) c.ln_band[b] = std::log(p.bands[b]);
  c.cos_t.resize(T);
  c.sin_t.resize(T);
  for (std::uint32_t t = 0; t < T; ++t) {
    c.cos_t[t] = std::cos(p.orientations[t] * kRad);
    c.sin_t[t] = std::sin(p.orientations[t] * kRad);
  }
  c.view_right.resize(3 * std::size_t(V));
  for (std::uint32_t v = 0; v < V; ++v) {
    const Vec3 r = cross(-1.0f * load(p.views[v].direction), load(p.views[v].up));
    c.view_right[3 * v] = r.x;
    c.view_right[3 * v + 1] = r.y;
    c.view_right[3 * v + 2] = r.z;
  }
  if (curves_) build_tables(c);
  level_count_[profile_count_] = static_cast<std::uint8_t>(K);
  std::copy(p.bands, p.bands + B, &band_frequency_[std::size_t(profile_count_) * kMaxBands]);
  max_band_count_ = std::max(max_band_count_, B);
  max_level_count_ = std::max(max_level_count_, K);
  for (std::uint32_t k = 0; k < K; ++k) {
    triangles_[std::size_t(profile_count_) * kMaxLevels + k] = p.levels[k].triangles;
    error_size_[std::size_t(profile_count_) * kMaxLevels + k] = 2.0f * p.levels[k].geometric_error;
  }
  return static_cast<int>(profile_count_++);
}

ObjectId Scheduler::add_object(int profile, const ObjectTransform& t) {
  if (profile < 0 || profile >= static_cast<int>(profile_count_) || free_list_.empty()) return kInvalidObject;
  const ObjectId id = free_list_.back();
  free_list_.pop_back();
  profile_of_[id] = profile;
  set_transform(id, t);
  for (int k = 0; k < 3; ++k) {
    previous_position_[k][id] = t.position[k];
    velocity_[k][id] = 0;
  }
  explicit_velocity_[id] = 0;
  fresh_[id] = 1;
  min_level_[id] = 0;
  max_level_[id] = static_cast<std::uint8_t>(level_count_[profile] - 1);
  bias_[id] = 1.0f;
  bias_tables_[id] = bias_tables_of(1.0f);
  level_[id] = from_level_[id] = chosen_[id] = next_[id] = std::min<std::uint8_t>(
      config_.fallback_level, static_cast<std::uint8_t>(profiles_[profile].profile.meta.level_count - 1));
  drawn_triangles_ += triangles_[std::size_t(profile) * kMaxLevels + level_[id]];
  flags_[id] = 0;
  calm_frames_[id] = wait_frames_[id] = 0;
  fade_[id] = 1.0f;
  if (memos_) memos_[0].key[id] = memos_[1].key[id] = Memo::kNone;  // another profile's, maybe
  end_rests(id);
  return id;
}

void Scheduler::remove_object(ObjectId id) {
  if (!alive(id)) return;
  drawn_triangles_ -= triangles_[std::size_t(profile_of_[id]) * kMaxLevels + level_[id]];
  profile_of_[id] = -1;
  sphere_[3][id] = 0.0f;   // a free slot looks invalid to the frame loop
  next_[id] = level_[id];  // and counts nothing in end_frame (the frame loop keeps a free slot's state)
  flags_[id] = 0;
  rest_[id] = 0;
  end_rests(id);
  free_list_.push_back(id);
}

void Scheduler::set_transform(ObjectId id, const ObjectTransform& t) {
  if (!alive(id)) return;
  // The frame reads the sphere scaled (the same products it would form): one array fewer per object.
  const float* sphere = profiles_[profile_of_[id]].profile.meta.sphere;
  bool same = true;  // the same bits: an object set where it was keeps its rests
  for (int k = 0; k < 3; ++k) {
    same = same && std::memcmp(&position_[k][id], &t.position[k], sizeof(double)) == 0;
    position_[k][id] = t.position[k];
  }
  bool same_rotation = true;  // and one not turned, its holds
  for (int k = 0; k < 4; ++k) {
    const float scaled = t.scale * sphere[k];
    same_rotation = same_rotation && std::memcmp(&rotation_[k][id], &t.rotation[k], sizeof(float)) == 0;
    same = same && std::memcmp(&sphere_[k][id], &scaled, sizeof(float)) == 0;
    rotation_[k][id] = t.rotation[k];
    sphere_[k][id] = scaled;
  }
  if (!same || !same_rotation) end_rests(id);
  if (!same_rotation && memos_)
    for (int i = 0; i < 2; ++i) memos_[i].end_hold(id);
}

void Scheduler::set_velocity(ObjectId id, const float v[3]) {
  if (!alive(id)) return;
  for (int k = 0; k < 3; ++k) velocity_[k][id] = v[k];
  explicit_velocity_[id] = 1;
  end_rests(id);
}

void Scheduler::end_rests(ObjectId id) {
  if (memos_)
    for (int i = 0; i < 2; ++i) memos_[i].end_rest(id);
}

void Scheduler::set_clamps(ObjectId id, std::uint8_t min_level, std::uint8_t max_level) {
  if (!alive(id)) return;
  min_level_[id] = min_level;
  max_level_[id] =
      std::min(std::max(min_level, max_level), static_cast<std::uint8_t>(level_count_[profile_of_[id]] - 1));
}

void Scheduler::set_bias(ObjectId id, float quality_bias) {
  if (!alive(id)) return;
  bias_[id] = quality_bias;
  bias_tables_[id] = bias_tables_of(quality_bias);
  end_rests(id);
}

// Its own tables, if it is a tabulated bias; else the exact path (rounding it to a tabulated bias
// would drop what the engine asked for). The frame loop tests an object's bias here, not bias_.
std::uint8_t Scheduler::bias_tables_of(float bias) const {
  const float q = config_.quality * bias;
  if (!(std::isfinite(q) && q > 0.0f)) return kInvalidBias;
  const float* tabulated = std::find(table_bias_, table_bias_ + table_bias_count_, bias);
  return tabulated == table_bias_ + table_bias_count_ ? kExactBias
                                                      : static_cast<std::uint8_t>(tabulated - table_bias_);
}

const float* Scheduler::scores(ObjectId id) const {
  return config_.keep_scores && alive(id) ? &scores_[std::size_t(id) * kMaxLevels] : nullptr;
}

void Scheduler::begin_frame(const Frame& frame) {
  eye_count_ = std::clamp<std::uint32_t>(frame.eye_count, 1, 2);
  dt_ = std::isfinite(frame.dt) && frame.dt > 0 ? frame.dt : 0.0f;
  saccade_ = false;
  const std::size_t alive = config_.max_objects - free_list_.size();
  many_at_rest_ = stats_.at_rest > 0 && stats_.at_rest >= alive / 8;  // last frame's stats
  stats_ = FrameStats{};
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Eye& e = frame.eyes[i];
    const Gaze& g = frame.gaze[i];
    EyeCache& c = eyes_[i];
    for (int k = 0; k < 3; ++k) c.position[k] = e.position[k];
    for (int k = 0; k < 4; ++k) c.rotation[k] = e.orientation[k];
    const float qn = std::sqrt(e.orientation[0] * e.orientation[0] + e.orientation[1] * e.orientation[1] +
                               e.orientation[2] * e.orientation[2] + e.orientation[3] * e.orientation[3]);
    const float tan_l = std::tan(e.fov_deg[0] * kRad), tan_r = std::tan(e.fov_deg[1] * kRad);
    const float tan_u = std::tan(e.fov_deg[2] * kRad), tan_d = std::tan(e.fov_deg[3] * kRad);
    c.valid = std::isfinite(e.position[0]) && std::isfinite(e.position[1]) && std::isfinite(e.position[2]) &&
              std::abs(qn - 1.0f) < 1e-3f && finite(load(e.velocity)) && finite(load(e.angular_velocity)) &&
              tan_r > tan_l && tan_u > tan_d && e.viewport[0] > 0 && e.viewport[1] > 0 &&
              std::isfinite(tan_r - tan_l) && std::isfinite(tan_u - tan_d);
    if (c.valid)
      for (float& q : c.rotation) q /= qn;
    c.forward = rotate(c.rotation, {0, 0, -1});
    c.velocity = load(e.velocity);
    c.omega = kRad * load(e.angular_velocity);
    c.focal_px = static_cast<float>(e.viewport[0]) / (tan_r - tan_l);
    c.center_right = 0.5f * (tan_l + tan_r);
    c.center_up = 0.5f * (tan_u + tan_d);
    const Vec3 gd = load(g.direction);
    const float gl = length(gd);
    c.gaze = g.valid && g.confidence >= config_.min_gaze_confidence && std::isfinite(gl) && gl > 0.5f;
    c.gaze_dir = c.gaze ? rotate(c.rotation, (1.0f / gl) * gd) : c.forward;
    const Vec3 gw = load(g.angular_velocity);
    c.gaze_moving = c.gaze && g.has_velocity && finite(gw);
    if (c.gaze_moving && config_.saccade_speed > 0 && length(gw) > config_.saccade_speed) {
      // A saccade: the time to switch, but its own sweep of the retina lasts a few frames while the
      // level chosen now is seen in the fixation after it. So the eye counts as fixating (Daly's
      // pursuit model), not as moving at saccade speed.
      saccade_ = true;
      c.gaze_moving = false;
    }
    if (c.gaze_moving) {
      // d(gaze)/dt in the world: eye-in-head rotation carried by the head, plus the head's own.
      const Vec3 in_head = rotate(c.rotation, cross(gw, (1.0f / gl) * gd));
      c.gaze_velocity = in_head + kDeg * cross(c.omega, c.gaze_dir);
    }
    stats_.gaze_used |= c.gaze;
    if (!perceptual()) {  // level k's least distance / radius under this eye
      float* threshold = error_threshold_[i].data();
      for (std::uint32_t p = 0; p < profile_count_; ++p)
        for (std::uint32_t k = 1; k < level_count_[p]; ++k)
          threshold[p * kMaxLevels + k] = error_threshold(error_size_[p * kMaxLevels + k], c.focal_px);
    }
  }
  ++frame_;
  resting_ = memos_ != nullptr && !config_.keep_scores;
  // Objects are looked for at rest where an eighth were last frame, and every eighth frame.
  looking_for_rest_ = resting_ && (many_at_rest_ || frame_ % 8 == 0);
  for (std::uint32_t i = 0; memos_ && i < 2; ++i) {
    memos_[i].observe(frame_, i < eye_count_ ? &eyes_[i] : nullptr);
    if (i < eye_count_) resting_ = resting_ && memos_[i].usable;
  }
}

// One eye's view of one object: everything the rules read.
struct Scheduler::Sight {
  float d, r;  // distance to the sphere's centre, radius [m]
  float radius_deg, diameter_deg, ln_diam;
  float focal_px;
  // Perceptual and Reddy only:
  Vec3 u;                     // unit direction eye -> centre, world
  Vec3 image, slip;           // image-plane and retinal angular velocity [deg/s], world tangent vectors
  Vec3 to_eye;                // unit direction centre -> eye, object space
  float e;                    // eccentricity [deg]
  float nyquist_cpd;          // the display's limit in the object's direction
  const std::uint16_t* cand;  // the lookup cell's candidate views
  std::uint32_t view;         // the nearest of them
  float vx, vy;               // slip in the view's image axes [deg/s]
  bool moving;
  std::uint8_t flags;  // kFlagNoGaze
};

// One eye's view of up to kSize consecutive objects, structure of arrays (the frame loop's first pass).
struct Scheduler::Block {
  static constexpr std::uint32_t kSize = kBlock;
  float d[kSize], r[kSize], radius_deg[kSize], ln_diam[kSize];
  // Perceptual and Reddy only:
  float test[kSize];  // 0 where the input is valid (NaN otherwise)
  float e[kSize], nyquist[kSize];
  float u[3][kSize];       // unit direction eye -> centre, world
  float image[3][kSize];   // image-plane angular velocity [deg/s], world tangent vector
  float to_eye[3][kSize];  // unit direction centre -> eye, object space (the view lookup)
  Look state(std::uint32_t j) const {
    return !(test[j] == 0.0f) ? Look::Invalid : !(d[j] > r[j]) ? Look::Inside : Look::Ok;
  }
  Vec3 to_eye_at(std::uint32_t j) const { return {to_eye[0][j], to_eye[1][j], to_eye[2][j]}; }
};

// One block's choices, both eyes combined (the finer need wins), before clamps and hysteresis.
struct Scheduler::Decisions {
  std::uint8_t fine[kBlock], coarse[kBlock], flags[kBlock];
};

namespace {
// How far [rad] a direction d (object space) may turn before it leaves its lookup cell: a cube face's
// coordinate moves at most sqrt(6) per radian (|grad (v_a / v_major)| <= sqrt(1 + s^2) / |v_major|).
// With `views` (kLookupCandidates of them), before another of them is nearer than the nearest: a dot
// product moves at most one per radian.
float view_margin(const float d[3], std::uint32_t resolution, const float (*views)[3] = nullptr) {
  const float ax = std::abs(d[0]), ay = std::abs(d[1]), az = std::abs(d[2]);
  const bool on_x = ax >= ay && ax >= az, on_y = !on_x && ay >= az;  // as cube_cell()
  const double major = on_x ? ax : on_y ? ay : az;
  const double u = on_x ? d[1] : on_y ? d[2] : d[0], v = on_x ? d[2] : on_y ? d[0] : d[1];
  const double half = 0.5 * resolution;
  double edge = 1.0;  // the least distance to a cell's edge, in cells
  for (const double s : {u, v}) {
    const double at = s / major * half + half;
    edge = std::min({edge, at - std::floor(at), std::floor(at) + 1.0 - at});
  }
  double margin = edge / half / std::sqrt(6.0);
  if (views) {
    double dots[kLookupCandidates];
    std::uint32_t best = 0;
    for (std::uint32_t k = 0; k < kLookupCandidates; ++k) {
      dots[k] = double(d[0]) * views[k][0] + double(d[1]) * views[k][1] + double(d[2]) * views[k][2];
      if (dots[k] > dots[best]) best = k;
    }
    for (std::uint32_t k = 0; k < kLookupCandidates; ++k)  // another view (a candidate may repeat)
      if (std::memcmp(views[k], views[best], sizeof views[k]) != 0)
        margin = std::min(margin, 0.5 * (dots[best] - dots[k]));
  }
  return static_cast<float>(margin) - 1e-5f;  // the rounding of the direction as the loop computes it
}
}  // namespace

// Sets object id's rest for one eye from its geometry now (block b's j-th), where its memo decides it
// this frame and it does not move: the wider of two tries stands_at_rest() confirms, else none.
void Scheduler::set_rest(const EyeCache& eye, Memo& memo, ObjectId id, const Block& b,
                         std::uint32_t j) const {
  memo.rest_frame[id] = frame_;
  memo.end_rest(id);
  if (velocity_[0][id] != 0.0f || velocity_[1][id] != 0.0f || velocity_[2][id] != 0.0f) return;
  if ((memo.key[id] & Memo::kThroughView) && (memo.view_key[id] & 1u)) return;  // a moving image's
  if (!(memo.recent_m < b.d[j] * (1.0f / 256))) return;  // the eye moves too far: none would last
  const Vec3 u{b.u[0][j], b.u[1][j], b.u[2][j]};
  const Vec3 f = eye.forward;
  const double cos_forward = double(u.x) * f.x + double(u.y) * f.y + double(u.z) * f.z;
  RestProbe h{b.d[j],
              b.r[j],
              angle_deg(u, eye.gaze ? eye.gaze_dir : eye.forward),
              static_cast<float>(std::acos(std::clamp(cos_forward, -1.0, 1.0)) * (180.0 / std::numbers::pi)),
              kInf,
              0.5f * eye.focal_px * kRad,
              eye.gaze ? config_.gaze_uncertainty_deg : config_.no_gaze_radius_deg};
  if (memo.key[id] & Memo::kThroughView) {
    const Profile& p = profiles_[profile_of_[id]].profile;
    const float to_eye[3] = {b.to_eye[0][j], b.to_eye[1][j], b.to_eye[2][j]};
    float views[kLookupCandidates][3];
    const std::uint16_t* cand = p.lookup + cube_cell(to_eye, p.meta.lookup_resolution) * kLookupCandidates;
    for (std::uint32_t k = 0; k < kLookupCandidates; ++k)
      std::memcpy(views[k], p.views[cand[k]].direction, sizeof views[k]);
    h.view_margin = view_margin(to_eye, p.meta.lookup_resolution,
                                config_.view_blend == ViewBlend::Max3 ? nullptr : views);
  }
  // Wide, then narrower, but never narrower than the eye's recent moves (it would leave at once):
  // four times them, then (the last try) half as much again.
  float tried = 0.0f;
  for (const float share : {1.0f / 64, 1.0f / 1024, 1.0f / (1 << 20)}) {
    const float recent = share < 1.0f / 1024 ? 1.5f : 4.0f;
    const float m = std::max(share * h.d, recent * memo.recent_m);
    const float t = std::max(recent * memo.recent_deg, kDeg * m / h.d);
    if (m == tried) continue;  // the eye's moves, not the share, set it: tried already
    tried = m;
    if (stands_at_rest(memo, id, h, m, t)) {
      memo.rest_m[id] = m;
      memo.rest_deg[id] = t;
      return;
    }
  }
}

void Scheduler::update(std::uint32_t first, std::uint32_t count) {
  const std::uint32_t end =
      first >= config_.max_objects ? first : first + std::min(count, config_.max_objects - first);
  Block blocks[2];
  Sight sights[2][Block::kSize];
  Look looks[2][Block::kSize];
  Decisions decisions{};
  // At rest: which objects are, two blocks ahead, and the arrays of those that are not prefetched.
  std::uint32_t at_rest[3][Block::kSize];
  bool mostly_at_rest[3];
  const auto look_ahead = [&](std::uint32_t start) {
    if (!looking_for_rest_ || start >= end) return;
    const std::uint32_t n = std::min(Block::kSize, end - start), slot = (start - first) / Block::kSize % 3;
    mostly_at_rest[slot] = rest_mask(start, n, at_rest[slot]);
    if (mostly_at_rest[slot]) prefetch_restless(start, n, at_rest[slot]);
  };
  look_ahead(first);
  look_ahead(first + Block::kSize);
  for (std::uint32_t start = first; start < end; start += Block::kSize) {
    const std::uint32_t n = std::min(Block::kSize, end - start);
    look_ahead(start + 2 * Block::kSize);
    const std::uint32_t slot = (start - first) / Block::kSize % 3;
    if (looking_for_rest_ && mostly_at_rest[slot]) {
      decide_at_rest(start, n, at_rest[slot], &decisions);
      settle(start, n, decisions);
      continue;
    }
    if (end - start >= 3 * Block::kSize) prefetch_objects(start + 2 * Block::kSize);
    if (curves_ && end - start >= 2 * Block::kSize) prefetch_holds(start + Block::kSize);
    std::fill(rest_.begin() + start, rest_.begin() + start + n, std::uint8_t(0));
    derive_velocities(start, n);
    for (std::uint32_t i = 0; i < eye_count_; ++i) look_block(eyes_[i], start, n, &blocks[i]);
    if (!perceptual()) {
      choose_by_error(start, n, blocks, &decisions);
      settle(start, n, decisions);
      continue;
    }
    if (curves_) {
      choose_tabulated(start, n, blocks, &decisions);
      settle(start, n, decisions);
      continue;
    }
    // Passes over the block, each prefetching what the next reads: the lookup cell, the candidate
    // views. The misses of a block's objects overlap instead of queueing.
    for (std::uint32_t j = 0; j < n; ++j)
      if (profile_of_[start + j] >= 0)
        for (std::uint32_t i = 0; i < eye_count_; ++i)
          looks[i][j] = sight(start + j, eyes_[i], blocks[i], j, &sights[i][j]);
    for (std::uint32_t j = 0; j < n; ++j)
      if (profile_of_[start + j] >= 0)
        for (std::uint32_t i = 0; i < eye_count_; ++i)
          if (looks[i][j] == Look::Ok) prefetch_views(start + j, sights[i][j]);
    for (std::uint32_t j = 0; j < n; ++j)
      if (profile_of_[start + j] >= 0)
        for (std::uint32_t i = 0; i < eye_count_; ++i)
          if (looks[i][j] == Look::Ok) aim(start + j, &sights[i][j]);
    choose_perceptual(start, n, looks, sights, &decisions);
    settle(start, n, decisions);
  }
}

// A block whose objects are nearly all at rest (the eye within each one's rest, every eye): those
// decided from their memos, the few runs of others through the frame loop. Returns false, deciding
// nothing, where more than kMostRuns runs are not at rest (the whole block's passes cost less then).
bool Scheduler::rest_mask(std::uint32_t first, std::uint32_t n, std::uint32_t* at_rest) const {
  for (std::uint32_t j = 0; j < n; ++j) at_rest[j] = 1;
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Memo& m = memos_[i];
    const std::uint32_t* since = &m.rest_frame[first];
    const float *rest_m = &m.rest_m[first], *rest_deg = &m.rest_deg[first];
    const float *moved = m.moved, *turned = m.turned;
    const std::uint32_t frame = frame_;
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t pose = since[j] % Memo::kPoses;
      at_rest[j] &= std::uint32_t(frame - since[j] < Memo::rest_frames(first + j)) &
                    std::uint32_t(moved[pose] <= rest_m[j]) & std::uint32_t(turned[pose] <= rest_deg[j]);
    }
  }
  std::uint32_t runs = 0, before = 1, restless = 0;  // runs of objects not at rest, and objects
  for (std::uint32_t j = 0; j < n; ++j) {
    runs += (at_rest[j] ^ 1u) & before;
    restless += at_rest[j] ^ 1u;
    before = at_rest[j];
  }
  return runs <= kMostRestlessRuns && restless <= kMostRestless;
}

// The per-object arrays the frame loop reads of the objects of a block not at rest (rest_mask()).
void Scheduler::prefetch_restless(std::uint32_t first, std::uint32_t n, const std::uint32_t* at_rest) const {
  for (std::uint32_t j = 0; j < n; ++j) {
    if (at_rest[j]) continue;
    const ObjectId id = first + j;
    for (int k = 0; k < 3; ++k) {
      ACUITY_PREFETCH(&position_[k][id]);
      ACUITY_PREFETCH(&previous_position_[k][id]);
      ACUITY_PREFETCH(&velocity_[k][id]);
    }
    for (int k = 0; k < 4; ++k) {
      ACUITY_PREFETCH(&rotation_[k][id]);
      ACUITY_PREFETCH(&sphere_[k][id]);
    }
    ACUITY_PREFETCH(&bias_tables_[id]);
    ACUITY_PREFETCH(&explicit_velocity_[id]);
    for (std::uint32_t i = 0; i < eye_count_; ++i) {
      const Memo& m = memos_[i];
      ACUITY_PREFETCH(&m.key[id]);
      ACUITY_PREFETCH(&m.x_from[id]);
      ACUITY_PREFETCH(&m.x_to[id]);
      ACUITY_PREFETCH(&m.w_from[id]);
      ACUITY_PREFETCH(&m.w_to[id]);
      ACUITY_PREFETCH(&m.f_lo[id]);
      ACUITY_PREFETCH(&m.f_hi[id]);
      ACUITY_PREFETCH(&m.view_key[id]);
    }
  }
}

void Scheduler::decide_at_rest(std::uint32_t first, std::uint32_t n, const std::uint32_t* at_rest,
                               Decisions* out) {
  std::uint8_t* rest = &rest_[first];
  for (std::uint32_t j = 0; j < n; ++j) rest[j] = static_cast<std::uint8_t>(at_rest[j]);
  // The memo's decision, both eyes: the finer need wins.
  std::memcpy(out->fine, &memos_[0].fine[first], n);
  std::memcpy(out->coarse, &memos_[0].coarse[first], n);
  for (std::uint32_t i = 1; i < eye_count_; ++i) {
    const std::uint8_t *fine = &memos_[i].fine[first], *coarse = &memos_[i].coarse[first];
    for (std::uint32_t j = 0; j < n; ++j) {
      out->fine[j] = std::min(out->fine[j], fine[j]);
      out->coarse[j] = std::min(out->coarse[j], coarse[j]);
    }
  }
  std::uint8_t flags = 0;
  for (std::uint32_t i = 0; i < eye_count_; ++i)
    flags = static_cast<std::uint8_t>(flags | (eyes_[i].gaze ? 0 : kFlagNoGaze));
  std::memset(out->flags, flags, n);
  for (std::uint32_t j = 0; j < n;) {
    if (at_rest[j]) {
      ++j;
      continue;
    }
    std::uint32_t k = j;
    while (k < n && !at_rest[k]) ++k;
    Block blocks[2];
    Decisions run{};
    derive_velocities(first + j, k - j);
    for (std::uint32_t i = 0; i < eye_count_; ++i) look_block(eyes_[i], first + j, k - j, &blocks[i]);
    choose_tabulated(first + j, k - j, blocks, &run);
    std::copy(run.fine, run.fine + (k - j), out->fine + j);
    std::copy(run.coarse, run.coarse + (k - j), out->coarse + j);
    std::copy(run.flags, run.flags + (k - j), out->flags + j);
    j = k;
  }
}

// The per-object arrays a frame reads, for the kBlock objects from `first`, asked for two blocks
// ahead. A frame reads some thirty of them side by side: more streams than the hardware prefetcher
// follows, so without this every block began with misses in each (measured in docs/benchmarks.md).
// An array the frame loop starts to read belongs here too. Hints only: nothing here changes a result.
void Scheduler::prefetch_objects(std::uint32_t first) const {
  constexpr std::uint32_t n = Block::kSize, kLine = 64;
  const auto lines = [](const void* p, std::size_t bytes) {
    for (std::size_t o = 0; o < bytes; o += kLine) ACUITY_PREFETCH(static_cast<const char*>(p) + o);
  };
  for (int k = 0; k < 3; ++k) lines(&position_[k][first], sizeof(double) * n);
  for (int k = 0; k < 3; ++k) lines(&velocity_[k][first], sizeof(float) * n);
  for (int k = 0; k < 4; ++k) lines(&rotation_[k][first], sizeof(float) * n);
  for (int k = 0; k < 4; ++k) lines(&sphere_[k][first], sizeof(float) * n);
  lines(&profile_of_[first], sizeof(int) * n);
  for (const auto* a : {&calm_frames_, &wait_frames_}) lines(&(*a)[first], sizeof(std::uint32_t) * n);
  for (const auto* a :
       {&explicit_velocity_, &fresh_, &min_level_, &max_level_, &flags_, &chosen_, &next_, &bias_tables_})
    lines(&(*a)[first], n);
  if (!curves_) return;
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Memo& m = memos_[i];
    for (const auto* a : {&m.x_from, &m.x_to}) lines(&(*a)[first], sizeof(std::int16_t) * n);
    for (const auto* a : {&m.key, &m.w_from, &m.w_to}) lines(&(*a)[first], sizeof(std::uint16_t) * n);
    for (const auto* a : {&m.f_lo, &m.f_hi}) lines(&(*a)[first], sizeof(float) * n);
    for (const auto* a : {&m.fine, &m.coarse}) lines(&(*a)[first], n);
  }
}

// The holds of a block's memos made through the view (their keys, prefetched a block earlier, say
// which): the others are never read.
void Scheduler::prefetch_holds(std::uint32_t first) const {
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Memo& m = memos_[i];
    std::uint8_t through[Block::kSize];  // listed without branches (which ones is unpredictable)
    std::uint32_t count = 0;
    for (std::uint32_t j = 0; j < Block::kSize; ++j) {
      through[count] = static_cast<std::uint8_t>(j);
      count += (m.key[first + j] & Memo::kThroughView) != 0;
    }
    for (std::uint32_t k = 0; k < count; ++k) {
      ACUITY_PREFETCH(&m.hold[first + through[k]]);
      ACUITY_PREFETCH(&m.hold[first + through[k]].e_to);
    }
  }
}

// Velocities not given are derived from the positions and dt (a given velocity stays given, so its
// object's previous position is never read again). Blocks whose velocities are all given skip it.
ACUITY_SIMD_CLONES void Scheduler::derive_velocities(std::uint32_t first, std::uint32_t n) {
  const std::uint8_t* given = &explicit_velocity_[first];
  std::uint8_t all = 1;
  for (std::uint32_t j = 0; j < n; ++j) all &= given[j];
  if (all) return;
  const double inv_dt = dt_ > 0 ? 1.0 / double(dt_) : 0.0;
  for (int k = 0; k < 3; ++k) {
    const double* pos = &position_[k][first];
    double* prev = &previous_position_[k][first];
    float* vel = &velocity_[k][first];
    for (std::uint32_t j = 0; j < n; ++j) {
      const float derived = static_cast<float>((pos[j] - prev[j]) * inv_dt);
      vel[j] = given[j] ? vel[j] : derived;
      prev[j] = pos[j];
    }
  }
}

// The first pass, for `count` consecutive objects from `first` and one eye: arithmetic only, no
// branches and no calls, so the compiler vectorises it. Camera-relative geometry subtracts in double
// first, so 1e7 m from the origin is exact. Free slots have radius 0 and come out Invalid.
ACUITY_SIMD_CLONES void Scheduler::look_block(const EyeCache& eye, std::uint32_t first, std::uint32_t count,
                                              Block* out) const {
  const double* px = &position_[0][first];
  const double* py = &position_[1][first];
  const double* pz = &position_[2][first];
  const float* qx = &rotation_[0][first];
  const float* qy = &rotation_[1][first];
  const float* qz = &rotation_[2][first];
  const float* qw = &rotation_[3][first];
  const float* vx = &velocity_[0][first];
  const float* vy = &velocity_[1][first];
  const float* vz = &velocity_[2][first];
  const float* sx = &sphere_[0][first];
  const float* sy = &sphere_[1][first];
  const float* sz = &sphere_[2][first];
  const float* sr = &sphere_[3][first];
  const std::uint8_t* bias_tables = &bias_tables_[first];
  const double ex = eye.position[0], ey = eye.position[1], ez = eye.position[2];
  const float eye_test = eye.valid ? 0.0f : kNaN;  // NaN fails every object
  Block& b = *out;
  float* out_d = b.d;
  float* out_r = b.r;
  float* out_radius = b.radius_deg;
  float* out_ln = b.ln_diam;
  float* out_test = b.test;
  float rx[Block::kSize], ry[Block::kSize], rz[Block::kSize];
  for (std::uint32_t j = 0; j < count; ++j) {
    rx[j] = static_cast<float>(px[j] - ex);
    ry[j] = static_cast<float>(py[j] - ey);
    rz[j] = static_cast<float>(pz[j] - ez);
  }
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < count; ++j) {
    const Vec3 centre = rotate(qx[j], qy[j], qz[j], qw[j], Vec3{sx[j], sy[j], sz[j]});
    const Vec3 rel{rx[j] + centre.x, ry[j] + centre.y, rz[j] + centre.z};
    const float r = sr[j];
    const float qn = qx[j] * qx[j] + qy[j] * qy[j] + qz[j] * qz[j] + qw[j] * qw[j];
    const float bias_test = bias_tables[j] == kInvalidBias ? kNaN : 0.0f;
    // x - x is 0 for a finite x, NaN otherwise; one sum tests them all.
    const float nan_test = (rel.x - rel.x) + (rel.y - rel.y) + (rel.z - rel.z) + (vx[j] - vx[j]) +
                           (vy[j] - vy[j]) + (vz[j] - vz[j]) + (r - r) + bias_test + eye_test;
    // Every test folded into one comparison (the loop stays branch-free): r > 0, |q| = 1.
    const float margin = std::min(r, 1e-3f - std::abs(qn - 1.0f));
    const float test = nan_test + (margin > 0.0f ? 0.0f : kNaN);  // 0: valid
    out_d[j] = std::sqrt(dot(rel, rel));
    out_r[j] = r;
    out_test[j] = test;
    rx[j] = rel.x;
    ry[j] = rel.y;
    rz[j] = rel.z;
  }
  if (!perceptual()) return;  // Distance and ScreenSize need no angles
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < count; ++j) {
    const float radius_deg = angular_radius_deg(out_d[j], out_r[j]);
    out_radius[j] = radius_deg;
    out_ln[j] = ln_positive(2.0f * radius_deg);
  }
  const Vec3 eye_velocity = eye.velocity, omega = eye.omega, forward = eye.forward;
  const Vec3 gaze = eye.gaze ? eye.gaze_dir : eye.forward;
  const float offset = eye.gaze ? config_.gaze_uncertainty_deg : config_.no_gaze_radius_deg;
  const float half_focal = 0.5f * eye.focal_px * kRad;
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < count; ++j) {
    const float inv_d = b.d[j] > 0.0f ? 1.0f / b.d[j] : 0.0f;
    const Vec3 u = inv_d * Vec3{rx[j], ry[j], rz[j]};
    const Vec3 v_rel = Vec3{vx[j], vy[j], vz[j]} - eye_velocity;
    const Vec3 image = kDeg * (inv_d * (v_rel - dot(v_rel, u) * u) - cross(omega, u));
    const float cos_phi = std::clamp(dot(u, forward), 0.05f, 1.0f);
    const Vec3 to_eye = rotate(-qx[j], -qy[j], -qz[j], qw[j], -1.0f * u);  // the inverse rotation
    b.u[0][j] = u.x;
    b.u[1][j] = u.y;
    b.u[2][j] = u.z;
    b.image[0][j] = image.x;
    b.image[1][j] = image.y;
    b.image[2][j] = image.z;
    b.to_eye[0][j] = to_eye.x;
    b.to_eye[1][j] = to_eye.y;
    b.to_eye[2][j] = to_eye.z;
    b.nyquist[j] = half_focal / (cos_phi * cos_phi);
    b.e[j] = std::max(0.0f, angle_deg(u, gaze) - b.radius_deg[j] - offset);
  }
}

namespace {
// Retinal slip of an image moving at `image` [deg/s]: against the measured gaze motion, or Daly's
// pursuit model.
inline Vec3 retinal_slip(Vec3 image, bool gaze_moving, Vec3 gaze_velocity, const ModelParams& params) {
  if (gaze_moving) return image - gaze_velocity;
  const float vi = length(image);
  return vi > 0 ? (daly_retinal_velocity(vi, params) / vi) * image : Vec3{0, 0, 0};
}
// Whether retinal_slip() is 0 (Daly's pursuit leaves at least the drift of any moving image), without
// branches: the image moves with the measured gaze (`tracked`: the gaze velocity, or 0 without one).
[[gnu::always_inline]] inline bool no_retinal_slip(Vec3 image, Vec3 tracked) {
  return (image.x == tracked.x) & (image.y == tracked.y) & (image.z == tracked.z);
}
// Of a lookup cell's candidates, the view nearest to the direction to the eye (the first on ties).
inline std::uint32_t nearest_view(const Profile& p, const std::uint16_t* cand, Vec3 to_eye) {
  std::uint32_t view = cand[0];
  float best = -2.0f;
  for (std::uint32_t k = 0; k < kLookupCandidates; ++k) {
    const float dd = dot(to_eye, load(p.views[cand[k]].direction));
    view = dd > best ? cand[k] : view;
    best = std::max(best, dd);
  }
  return view;
}
// The slip [deg/s] in a view's image axes (right, up; object space, q the object's rotation): there
// it meets the profile's orientations. 0 for no slip.
inline void slip_in_view(Vec3 slip, const float q[4], const float* right, const float* up, float* vx,
                         float* vy) {
  *vx = *vy = 0;
  if (slip.x == 0.0f && slip.y == 0.0f && slip.z == 0.0f) return;
  *vx = dot(slip, rotate(q, load(right)));
  *vy = dot(slip, rotate(q, load(up)));
}
}  // namespace

// The second pass for one object: the view lookup and retinal slip, what branches.
Scheduler::Look Scheduler::sight(ObjectId id, const EyeCache& eye, const Block& b, std::uint32_t j,
                                 Sight* s) const {
  if (const Look state = b.state(j); state != Look::Ok) return state;
  s->d = b.d[j];
  s->r = b.r[j];
  s->focal_px = eye.focal_px;
  if (!perceptual()) return Look::Ok;
  s->radius_deg = b.radius_deg[j];
  s->diameter_deg = 2.0f * b.radius_deg[j];
  s->ln_diam = b.ln_diam[j];
  const ProfileCache& pc = profiles_[profile_of_[id]];
  const Profile& p = pc.profile;
  s->u = Vec3{b.u[0][j], b.u[1][j], b.u[2][j]};
  s->image = Vec3{b.image[0][j], b.image[1][j], b.image[2][j]};
  s->e = b.e[j];
  s->nyquist_cpd = b.nyquist[j];
  s->flags = eye.gaze ? std::uint8_t(0) : std::uint8_t(kFlagNoGaze);
  s->slip = retinal_slip(s->image, eye.gaze_moving, eye.gaze_velocity, config_.params);
  // The lookup cell of the direction from the object to the eye; aim() picks the nearest view.
  s->to_eye = Vec3{b.to_eye[0][j], b.to_eye[1][j], b.to_eye[2][j]};
  const float dir[3] = {s->to_eye.x, s->to_eye.y, s->to_eye.z};
  s->cand = p.lookup + cube_cell(dir, p.meta.lookup_resolution) * kLookupCandidates;
  ACUITY_PREFETCH(s->cand);
  return Look::Ok;
}

// The candidate views' directions prefetched (between sight() and aim(), a pass apart).
void Scheduler::prefetch_views(ObjectId id, const Sight& s) const {
  const Profile& p = profiles_[profile_of_[id]].profile;
  for (std::uint32_t k = 0; k < kLookupCandidates; ++k) ACUITY_PREFETCH(&p.views[s.cand[k]]);
}

// The profile's view nearest to the direction from the object to the eye, and the retinal slip in
// that snapshot's image axes, so it meets the profile's orientations in one frame.
void Scheduler::aim(ObjectId id, Sight* s) const {
  const ProfileCache& pc = profiles_[profile_of_[id]];
  const Profile& p = pc.profile;
  s->view = nearest_view(p, s->cand, s->to_eye);
  const float q[4] = {rotation_[0][id], rotation_[1][id], rotation_[2][id], rotation_[3][id]};
  slip_in_view(s->slip, q, &pc.view_right[3 * std::size_t(s->view)], p.views[s->view].up, &s->vx, &s->vy);
  s->moving = s->vx != 0.0f || s->vy != 0.0f;
}

// One eye's view of one object (sight() and aim() done) through the configured rule, exactly.
// scores_out (K floats) and ex are optional.
Scheduler::Choice Scheduler::evaluate(ObjectId id, Look look, const Sight& s, float* scores_out,
                                      ObjectExplain* ex) const {
  const Profile& p = profiles_[profile_of_[id]].profile;
  const std::uint32_t K = p.meta.level_count;
  if (scores_out) std::fill(scores_out, scores_out + K, 0.0f);
  switch (look) {
    case Look::Invalid: {
      const auto fallback = static_cast<std::uint8_t>(std::min<std::uint32_t>(config_.fallback_level, K - 1));
      return {fallback, fallback, kFlagInvalidInput};
    }
    case Look::Inside:
      return {0, 0, kFlagEyeInside};
    case Look::Ok:
      break;
  }
  switch (config_.rule) {
    case SelectionRule::Distance:
    case SelectionRule::ScreenSize:
      return choose_by_error(id, s);
    case SelectionRule::Reddy:
      return choose_exact(id, s, scores_out, ex);
    case SelectionRule::Perceptual:
      return choose_exact(id, s, scores_out, ex);
  }
  return {0, 0, 0};
}

// Distance (OpenSceneGraph-style) and ScreenSize (Unity-style): the least distance / radius at which
// a level whose geometric error is error_size radii is allowed, for an eye of this focal length [px]
// (+inf: never). Distance: d >= distance_scale / tan(1 arcmin) x error. ScreenSize: error / d x
// focal <= pixel_error, so never for pixel_error < 0 (or NaN), only an error of 0 for pixel_error 0.
float Scheduler::error_threshold(float error_size, float focal_px) const {
  if (config_.rule == SelectionRule::Distance) return pre_->distance_per_error * error_size;
  const float allowed = config_.pixel_error;
  if (allowed > 0) return error_size * focal_px / allowed;
  return allowed == 0 && error_size == 0 ? 0.0f : kInf;
}

// One object (explain()): the coarsest level whose geometric error passes the rule's test.
Scheduler::Choice Scheduler::choose_by_error(ObjectId id, const Sight& s) const {
  const std::size_t at = std::size_t(profile_of_[id]) * kMaxLevels;
  float threshold[kMaxLevels];
  for (std::uint32_t k = 1; k < level_count_[profile_of_[id]]; ++k)
    threshold[k] = error_threshold(error_size_[at + k], s.focal_px);
  const std::uint8_t level = level_by_ratio(s.d / s.r, threshold, level_count_[profile_of_[id]]);
  return {level, level, 0};
}

// A block through Distance or ScreenSize: per object and eye the ratio distance / radius against
// the profile's thresholds of this frame (begin_frame).
void Scheduler::choose_by_error(std::uint32_t first, std::uint32_t n, const Block* blocks, Decisions* out) {
  const std::uint32_t count = max_level_count_;
  for (std::uint32_t j = 0; j < n; ++j) {
    const int p = profile_of_[first + j];
    if (p < 0) continue;
    const auto fallback =
        static_cast<std::uint8_t>(std::min<std::uint32_t>(config_.fallback_level, level_count_[p] - 1u));
    std::uint8_t fine = 255, flags = 0;
    for (std::uint32_t i = 0; i < eye_count_; ++i) {
      const Block& b = blocks[i];
      const std::uint8_t level =
          level_by_ratio(b.d[j] / b.r[j], &error_threshold_[i][std::size_t(p) * kMaxLevels], count);
      const Look look = b.state(j);
      fine = std::min(fine, look == Look::Ok ? level : look == Look::Inside ? std::uint8_t(0) : fallback);
      flags |= look == Look::Ok ? 0 : look == Look::Inside ? kFlagEyeInside : kFlagInvalidInput;
    }
    out->fine[j] = out->coarse[j] = fine;
    out->flags[j] = flags;
  }
  if (config_.keep_scores)  // these rules have no scores: 0
    for (std::uint32_t j = 0; j < n; ++j)
      if (profile_of_[first + j] >= 0)
        std::fill_n(&scores_[std::size_t(first + j) * kMaxLevels], level_count_[profile_of_[first + j]],
                    0.0f);
}

// ---- The tabulated path, a block at a time (update()) ----------------------------------------------
// One object's place in its profile's tables, seen by one eye: what the decision reads.
struct Scheduler::Probe {
  float x;                                 // ln angular diameter [ln deg]
  std::uint8_t tables;                     // the object's bias's first table set (kTableSets)
  float vx, vy;                            // retinal slip in the view's image axes [deg/s]
  Cell ec;                                 // eccentricity cell of the still grid
  std::uint32_t bands;                     // the lowest bands the display shows (0: none)
  std::uint16_t views[kLookupCandidates];  // the views whose tables bound it (one, or Max3's three)
  std::uint8_t view_count;
  std::uint32_t where;    // the view (Max3: the lookup cell), as the memo keys it
  std::uint32_t nearest;  // the view nearest to the eye, in whose image axes vx and vy are
  Vec3 slip;              // retinal slip [deg/s], eye space
  bool moving;
  bool decided;                             // by its memo through the view (pass 4)
  bool at_place;                            // ... which says the whole cells do not decide
  bool cells;                               // moving: em and sc are set (where a slow bound does not pass)
  Cell em;                                  // eccentricity cell of the moving grid
  std::uint32_t speed_j[kMaxOrientations];  // each orientation's speed cell: lower node
  float speed_w[kMaxOrientations];          // and the weight of the upper one
  // Where candidate view c's rows start (profile of B bands, L coarser levels): in the still and
  // slow tables (the lower eccentricity node's levels, then the upper one's), and in the moving
  // table for orientation t (its lower speed node's two eccentricity nodes; the upper speed node's
  // are kMovingE * L further). ProfileCache describes the layouts.
  std::size_t still_row(std::uint32_t c, std::uint32_t B, std::uint32_t L) const {
    return ((std::size_t(views[c]) * B + (bands - 1)) * kStillE + ec.j) * L;
  }
  std::size_t moving_row(std::uint32_t c, std::uint32_t t, std::uint32_t T, std::uint32_t L) const {
    return (((std::size_t(views[c]) * T + t) * kMovingS + speed_j[t]) * kMovingE + em.j) * L;
  }
};

namespace {
// The quarter q of a cell a weight w in [0, 1] lies in: w in [q / 4, (q + 1) / 4] (w * 4 is exact).
constexpr std::uint32_t kQuarters = 4;
[[gnu::always_inline]] inline std::uint32_t quarter_of(float w) {
  return std::min(static_cast<std::uint32_t>(w * float(kQuarters)), kQuarters - 1);
}
// The weights [*from, *to] of a cell a decision at weight w stands over: its quarter, or the whole
// cell [0, 1].
inline void weight_range(bool quartered, float w, float* from, float* to) {
  const float q = quartered ? float(quarter_of(w)) : 0.0f, span = quartered ? 1.0f / kQuarters : 1.0f;
  *from = q * span;
  *to = (q + 1.0f) * span;
}
}  // namespace

std::uint32_t Scheduler::Memo::view_key_of(const Probe& o, bool quartered) {
  if (!o.moving) return o.where << 8;
  const std::uint32_t quarter = quartered ? kQuartered | quarter_of(o.em.w) << 5 : 0u;
  return o.where << 8 | quarter | o.em.j << 1 | 1u;
}

std::uint64_t Scheduler::Memo::speed_key_of(const Probe& o, std::uint32_t T, bool quartered) {
  std::uint64_t k = 0;
  for (std::uint32_t t = 0; o.moving && t < T; ++t) {
    k |= std::uint64_t(o.speed_j[t]) << (4 * t);
    if (quartered) k |= std::uint64_t(quarter_of(o.speed_w[t])) << (4 * T + 2 * t);
  }
  return k;
}

// Whether x passes `entry` (x <= entry), narrowing (*lo, *hi] to the x where the outcome is the same.
[[gnu::always_inline]] inline bool passes_narrowing(std::int32_t x, std::int32_t entry, std::int32_t* lo,
                                                    std::int32_t* hi) {
  const bool passes = x <= entry;
  *lo = passes ? *lo : std::max(*lo, entry);
  *hi = passes ? std::min(*hi, entry) : *hi;
  return passes;
}

// The level the bounds over every view decide for one object (set 0: score <= 1, set 1: <= 1 - margin),
// or -1 where its view would matter. A view's bound between its cell's two nodes lies between the
// least and the most of them, so for a still object the coarsest level passing the least bound
// passes in its view too, and no coarser one passes where it fails the most: when the two agree,
// that is the level. A moving one (or one whose view's image axes see no slip) is decided only where
// the least still and slow bound passes the coarsest level. Integers: x [ln deg] rounded up to the
// tables' step passes an entry exactly where x does.
// The row of the cell's lower node (the upper node's follows it).
[[gnu::always_inline]] inline const std::int16_t* Scheduler::any_view_row(const ProfileCache& pc,
                                                                          std::uint32_t L,
                                                                          std::uint32_t bands,
                                                                          std::uint32_t ec, int set) {
  return &pc.sets[set].any_view[((std::size_t(bands) - 1) * kStillE + ec) * (2 * std::size_t(L) + 1)];
}
// row: any_view_row()'s for a profile of L coarser levels; x: the object's ln angular diameter
// rounded up to the tables' step [1/1024 ln deg]. Over the whole cell: each entry the least (or most)
// of its two nodes'. (*lo, *hi] narrows to the x where each entry compared keeps its outcome (lo the
// largest below x, hi the least at or above it): there the result is the same, so a memo of it
// stands there.
[[gnu::always_inline]] inline int Scheduler::any_view_level(const std::int16_t* row, std::uint32_t L,
                                                            std::int32_t x, bool still, std::int32_t* lo,
                                                            std::int32_t* hi) {
  const std::int16_t* upper = row + 2 * L + 1;
  if (!still)
    return passes_narrowing(x, std::min(row[2 * L], upper[2 * L]), lo, hi) ? static_cast<int>(L) : -1;
  int passes = 0, may_pass = 0;
  for (std::uint32_t k = 1; k <= L; ++k) {
    passes = passes_narrowing(x, std::min(row[k - 1], upper[k - 1]), lo, hi) ? static_cast<int>(k) : passes;
    may_pass = passes_narrowing(x, std::max(row[L + k - 1], upper[L + k - 1]), lo, hi) ? static_cast<int>(k)
                                                                                       : may_pass;
  }
  return passes == may_pass ? passes : -1;
}
namespace {
// between() rounds: a few float steps at |bound| <= 32 ln deg; this much more keeps the bounds' sides
// at an object's place in the any-view cell (the views' own bounds are rounded too).
constexpr float kAnyViewRounding = 1.0f / 4096;
// The lines any_view_level_at() compares x against (stand_at_place()'s `lines`), for a row as there.
template <class Line>
void any_view_lines(const std::int16_t* row, std::uint32_t L, bool still, const Line& line) {
  const std::int16_t* upper = row + 2 * L + 1;
  if (!still) return line(row[2 * L], upper[2 * L], -kAnyViewRounding);
  for (std::uint32_t k = 1; k <= L; ++k) {
    line(row[k - 1], upper[k - 1], -kAnyViewRounding);
    line(row[L + k - 1], upper[L + k - 1], kAnyViewRounding);
  }
}
}  // namespace

// The same at the object's place in the cell: the nodes' least (and most) interpolated at the upper
// node's weight w, as each view's bound is. Each view's bound is linear in w between its nodes, so
// the least (most) over the views is at least (at most) the line between the nodes' least (most):
// still a bound over every view, and a closer one. x: the object's ln angular diameter [ln deg].
// Decides more objects than any_view_level(), for this eccentricity (stand_at_place() finds how far
// around it the decision stands).
[[gnu::always_inline]] inline int Scheduler::any_view_level_at(const std::int16_t* row, std::uint32_t L,
                                                               float x, float w, bool still) {
  const std::int16_t* upper = row + 2 * L + 1;
  const auto at = [&](std::uint32_t i) { return between(row[i], upper[i], w); };
  if (!still) return x <= at(2 * L) - kAnyViewRounding ? static_cast<int>(L) : -1;
  int passes = 0, may_pass = 0;
  for (std::uint32_t k = 1; k <= L; ++k) {
    passes = x <= at(k - 1) - kAnyViewRounding ? static_cast<int>(k) : passes;
    may_pass = x <= at(L + k - 1) + kAnyViewRounding ? static_cast<int>(k) : may_pass;
  }
  return passes == may_pass ? passes : -1;
}

// The level that table_choice() would give wherever the object is in its cells (its still or slow
// cell's two eccentricity nodes and, moving, each orientation's moving cell's four corners) for table
// set o.tables + set, or -1 where its place in them matters; `quartered`: wherever it is in the
// quarters of its cells it lies in (quarter_of() of each weight; a moving object's). Each bound
// table_choice() interpolates lies between the least and the most of its values at the ends of the
// weights' ranges (interpolation rounds monotonically), so the coarsest level passing the least
// passes there too, and none failing the most does. Integers, x and (*lo, *hi] as in
// any_view_level(): a bound in table steps rounded down for the least, up for the most (entries,
// the whole cells' corners, are exact). A moving object's cells must be set (o.cells).
int Scheduler::view_cell_level(const ProfileCache& pc, const Probe& o, std::int32_t x, int set,
                               bool quartered, std::int32_t* lo, std::int32_t* hi) {
  const ProfileMeta& m = pc.profile.meta;
  const std::uint32_t T = m.orientation_count, B = m.band_count, L = m.level_count - 1;
  const ProfileCache::Tables& tables = pc.sets[o.tables + set];
  const std::vector<std::int16_t>& near = o.moving ? tables.slow : tables.still;
  float ec_from, ec_to, em_from, em_to;
  weight_range(quartered, o.ec.w, &ec_from, &ec_to);
  if (o.moving) weight_range(quartered, o.em.w, &em_from, &em_to);
  // A bound in table steps, rounded down (up).
  const auto step_below = [](float v) { return std::int32_t(std::floor(v * kSizeSteps)); };
  const auto step_above = [](float v) { return std::int32_t(std::ceil(v * kSizeSteps)); };
  for (std::uint32_t k = L; k >= 1; --k) {
    bool least = true, most = true;  // every view passes its least (most) bound
    for (std::uint32_t c = 0; c < o.view_count && most; ++c) {
      const std::int16_t* row = &near[o.still_row(c, B, L) + (k - 1)];
      const float near_from = between(row[0], row[L], ec_from), near_to = between(row[0], row[L], ec_to);
      bool view_least = passes_narrowing(x, step_below(std::min(near_from, near_to)), lo, hi);
      bool view_most = view_least || passes_narrowing(x, step_above(std::max(near_from, near_to)), lo, hi);
      if (o.moving && !view_least) {  // the moving bound: its least (most) over the orientations
        bool moving_least = true, moving_most = !view_most;
        for (std::uint32_t t = 0; t < T && (moving_least || moving_most); ++t) {
          const std::int16_t* r0 = &tables.moving[o.moving_row(c, t, T, L) + (k - 1)];
          const std::int16_t* r1 = r0 + std::size_t(kMovingE) * L;
          float s_from, s_to;
          weight_range(quartered, o.speed_w[t], &s_from, &s_to);
          float corners[4];
          for (int e = 0; e < 2; ++e) {  // at each eccentricity end, the speed interpolation's ends
            const float w = e ? em_to : em_from;
            const float slow_node = between(r0[0], r0[L], w), fast_node = between(r1[0], r1[L], w);
            corners[2 * e] = slow_node + s_from * (fast_node - slow_node);
            corners[2 * e + 1] = slow_node + s_to * (fast_node - slow_node);
          }
          const float least_corner =
              std::min(std::min(corners[0], corners[1]), std::min(corners[2], corners[3]));
          const float most_corner =
              std::max(std::max(corners[0], corners[1]), std::max(corners[2], corners[3]));
          // A step of room: inside the box, the speed interpolation of two interpolated floats can
          // round an ulp past its corners.
          if (moving_least) moving_least = passes_narrowing(x, step_below(least_corner) - 1, lo, hi);
          if (moving_most) moving_most = passes_narrowing(x, step_above(most_corner) + 1, lo, hi);
        }
        view_least = moving_least;
        view_most = view_most || moving_most;
      }
      least = least && view_least;
      most = most && view_most;
    }
    if (least) return static_cast<int>(k);
    if (most) return -1;
  }
  return 0;
}

// The inputs of the tables for a block's objects (tabulate()'s pass 1), branch-free so that it
// vectorises: the tables' x and eccentricity cell and whether the image is still on the retina (as
// retinal_slip() finds it); with these, whether each object's memo stands (never with use_memo false).
struct Scheduler::Inputs {
  std::int32_t x_step[kBlock];  // ln angular diameter in table steps, rounded up
  std::uint32_t ec_j[kBlock];
  float ec_w[kBlock], inv_diam[kBlock];
  std::uint32_t still[kBlock];      // 0 or 1, as wide as the loop's floats (so it vectorises)
  std::uint32_t memo_hit[kBlock];   // 0 or 1: decided by its memo
  std::uint32_t view_memo[kBlock];  // 0 or 1: by its memo if the view and speed cells are the same
};
ACUITY_SIMD_CLONES void Scheduler::table_inputs(const EyeCache& eye, std::uint32_t first, std::uint32_t n,
                                                const Block& b, const Memo& memo, bool use_memo,
                                                Inputs* out) const {
  const Vec3 tracked = eye.gaze_moving ? eye.gaze_velocity : Vec3{0, 0, 0};
  const std::uint16_t* memo_key = &memo.key[first];
  const std::int16_t *x_from = &memo.x_from[first], *x_to = &memo.x_to[first];
  const std::uint16_t *w_from = &memo.w_from[first], *w_to = &memo.w_to[first];
  const float *f_lo = &memo.f_lo[first], *f_hi = &memo.f_hi[first];
  const std::uint8_t* bias_tables = &bias_tables_[first];
  const std::uint32_t check = use_memo;
  Inputs& o = *out;
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::int32_t x = size_steps_above(b.ln_diam[j]);
    o.x_step[j] = x;
    const Cell ec = e_cell<kStillE>(b.e[j]);
    o.ec_j[j] = ec.j;
    o.ec_w[j] = ec.w;
    const std::uint32_t still = no_retinal_slip(Vec3{b.image[0][j], b.image[1][j], b.image[2][j]}, tracked);
    o.still[j] = still;
    const float inv_diam = 1.0f / (2.0f * b.radius_deg[j]);  // as the exact path computes each frequency
    o.inv_diam[j] = inv_diam;
    const std::uint32_t seen = (b.test[j] == 0.0f) & (b.d[j] > b.r[j]);
    const std::uint32_t same_bands =
        (f_lo[j] * inv_diam <= b.nyquist[j]) & !(f_hi[j] * inv_diam <= b.nyquist[j]);
    const std::uint32_t key = memo_key[j], through_view = (key & Memo::kThroughView) != 0;
    const std::uint32_t stands =
        check & seen &
        ((key & ~std::uint32_t(Memo::kThroughView)) == Memo::key_of(ec.j, still, bias_tables[j])) &
        same_bands & (x_from[j] <= x) & (x <= x_to[j]) & (float(w_from[j]) <= ec.w * kWeightSteps) &
        (ec.w * kWeightSteps <= float(w_to[j]));
    o.memo_hit[j] = stands & (through_view ^ 1u);
    o.view_memo[j] = stands & through_view;
  }
}

// Sets object id's hold (Memo::Hold) for the decision through its view just made or confirmed
// (block b's j-th; o its probe, with its cells where it moves; cand its lookup cell's candidates):
// the widest turn of the direction to the eye, change of slip and range of eccentricity within
// which view_key and speed_key stay, less room for the rounding of each as the frame loop computes
// it (a ten-thousandth of the quantity or of its cell). None where the image slips but
// not in the view's axes (then any change of slip may move it).
void Scheduler::hold_view(Memo& memo, ObjectId id, const ProfileCache& pc, const Probe& o,
                          const std::uint16_t* cand, const Block& b, std::uint32_t j, bool quartered,
                          bool still) const {
  Memo::Hold& h = memo.hold[id];
  h.turn = -1.0f;
  if (!o.moving && !still) return;
  const Profile& p = pc.profile;
  const Vec3 to_eye = b.to_eye_at(j);
  const float d[3] = {to_eye.x, to_eye.y, to_eye.z};
  // Moving, the nearest view's image axes carry the slip (Max3 too): it must stay the nearest.
  float views[kLookupCandidates][3];
  for (std::uint32_t k = 0; k < kLookupCandidates; ++k)
    std::memcpy(views[k], p.views[cand[k]].direction, sizeof views[k]);
  const bool cell_only = config_.view_blend == ViewBlend::Max3 && !o.moving;
  const float margin = std::min(view_margin(d, p.meta.lookup_resolution, cell_only ? nullptr : views), 0.5f);
  if (!(margin > 0.0f)) return;
  float reach = kInf, e_from = -kInf, e_to = kInf;
  if (o.moving) {
    // Each orientation's speed |vx cos t + vy sin t| stays in its cell (and quarter) while (vx, vy)
    // moves less than its distance to their ends, and (vx, vy) stays off 0 within its length.
    const float floor = pre_->floor_velocity, v0 = pre_->speed_offset;
    const float length_v = std::sqrt(o.vx * o.vx + o.vy * o.vy);
    float room = length_v * (1.0f - 1e-4f);
    const std::uint32_t T = p.meta.orientation_count;
    for (std::uint32_t t = 0; t < T; ++t) {
      const float u = std::abs(o.vx * pc.cos_t[t] + o.vy * pc.sin_t[t]);
      const std::uint32_t cell = o.speed_j[t];
      const float lo = floor * std::ldexp(1.0f, int(cell)), g_top = lo / (3.0f * lo + 2.0f * v0);
      // The speed at weight w of the cell [lo, 2 lo] (speed_cell()'s weight inverted).
      const auto at = [&](float w) {
        const float g = w * g_top;
        return (lo * (1.0f + g) + 2.0f * g * v0) / (1.0f - g);
      };
      float w_from, w_to;  // past the grid's first and last cells, the ends are open
      weight_range(quartered, o.speed_w[t], &w_from, &w_to);
      const float lower = w_from == 0.0f ? (cell == 0 ? -kInf : lo) : at(w_from);
      const float upper = w_to == 1.0f ? (cell == kMovingS - 2 ? kInf : 2.0f * lo) : at(w_to);
      const float slack = 1e-4f * std::max(u, floor) + 1e-5f * length_v;
      room = std::min(room, std::min(u - lower, upper - u) - slack);
    }
    if (!(room > 0.0f)) return;
    // (vx, vy) = the slip on the view's right and up axes (object space, rotated by the object's
    // rotation, which preserves them): it moves at most the largest singular value of the two
    // times the slip's move.
    const float* right = &pc.view_right[3 * std::size_t(o.nearest)];
    const float* up = p.views[o.nearest].up;
    const float rr = dot(load(right), load(right)), uu = dot(load(up), load(up)),
                ru = dot(load(right), load(up));
    const float stretch =
        std::sqrt(0.5f * (rr + uu) + std::sqrt(0.25f * (rr - uu) * (rr - uu) + ru * ru)) * (1.0f + 1e-5f);
    reach = room / stretch;
    // The eccentricity stays in its cell (and quarter) of the moving grid.
    const std::uint32_t cell = o.em.j;
    const float lower = e_node(cell, kMovingE), upper = e_node(cell + 1, kMovingE);
    float w_from, w_to;
    weight_range(quartered, o.em.w, &w_from, &w_to);
    const float slack = 1e-4f * (upper - lower) + 1e-6f * b.e[j];
    e_from = w_from == 0.0f ? (cell == 0 ? -kInf : lower) : lower + w_from * (upper - lower);
    e_to = w_to == 1.0f ? (cell == kMovingE - 2 ? kInf : upper) : lower + w_to * (upper - lower);
    e_from += slack;
    e_to -= slack;
    if (!(e_from < b.e[j] && b.e[j] < e_to)) return;
  }
  // A chord c between unit vectors spans 2 asin(c / 2) rad: at most the margin for c <= 0.98 of it
  // (margins of at most 0.5 rad).
  std::memcpy(h.direction, d, sizeof d);
  h.slip[0] = o.slip.x;
  h.slip[1] = o.slip.y;
  h.slip[2] = o.slip.z;
  h.reach = reach;
  h.e_from = e_from;
  h.e_to = e_to;
  h.turn = 0.98f * margin;
}

// One eye, the objects of a block, in passes that each prefetch what the next reads, so a block's
// cache misses overlap: the inputs of the bounds over every view and the objects the memo decides
// (pass 1, table_inputs()), the objects decided without tables and the any-view rows of the rest
// (2), the any-view decisions, over the whole cell or at the object's place, remembered where they
// stand (3); for the objects they leave, the view, slip and grid cell, with which a memo made
// through the view decides (4), the moving rows (5) and the decision, over the whole cells or at
// the object's place in them, remembered where it stands (6). Objects not seen (invalid input, eye
// inside) take the fallback or finest level; an object whose bias has no tables (not a tabulated
// bias) is evaluated exactly. Writes out[j], and with `scores` (kMaxLevels per object) each level's
// score (no memo then).
void Scheduler::tabulate(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b,
                         Memo& memo, Choice* out, float (*scores)[kMaxLevels]) const {
  const std::uint16_t* cand[kBlock];
  Probe probe[kBlock];
  std::uint8_t todo[kBlock];    // 2: the bounds over every view first; 1: through the object's view
  std::uint8_t tables[kBlock];  // the object's bias's first table set (kTableSets)
  const std::uint8_t gaze_flag = eye.gaze ? std::uint8_t(0) : std::uint8_t(kFlagNoGaze);
  // Pass 1: the tables' x and eccentricity cell, still or moving, whether the memo stands.
  Inputs in;
  table_inputs(eye, first, n, b, memo, scores == nullptr, &in);
  const std::int32_t* x_step = in.x_step;
  const std::uint32_t *ec_j = in.ec_j, *still = in.still, *memo_hit = in.memo_hit, *view_memo = in.view_memo;
  const float *ec_w = in.ec_w, *inv_diam = in.inv_diam;
  // Objects whose memo through the view stands keep its decision while the view and cells are
  // the same, which they are within its hold (Memo::Hold; only these holds are read).
  std::uint32_t decided[kBlock];  // by a memo
  std::uint8_t viewed[kBlock];
  std::uint32_t viewed_count = 0;
  for (std::uint32_t j = 0; j < n; ++j) {
    decided[j] = memo_hit[j];
    viewed[viewed_count] = static_cast<std::uint8_t>(j);
    viewed_count += view_memo[j];
  }
  for (std::uint32_t i = 0; i < viewed_count; ++i) {
    const std::uint32_t j = viewed[i];
    const Memo::Hold& h = memo.hold[first + j];
    const Vec3 image{b.image[0][j], b.image[1][j], b.image[2][j]};
    const Vec3 turned = b.to_eye_at(j) - load(h.direction);
    const Vec3 slipped =
        retinal_slip(image, eye.gaze_moving, eye.gaze_velocity, config_.params) - load(h.slip);
    decided[j] = std::uint32_t(h.turn >= 0.0f) & std::uint32_t(dot(turned, turned) <= h.turn * h.turn) &
                 std::uint32_t(dot(slipped, slipped) <= h.reach * h.reach) &
                 std::uint32_t(h.e_from <= b.e[j]) & std::uint32_t(b.e[j] <= h.e_to);
  }
  std::uint32_t bands[kBlock];
  // The bands the display shows of the rest (the lowest n: the rest are invisible whatever the eye).
  std::uint8_t miss[kBlock];
  std::uint32_t miss_count = 0;
  for (std::uint32_t j = 0; j < n; ++j) {
    miss[miss_count] = static_cast<std::uint8_t>(j);
    miss_count += decided[j] ^ 1u;
  }
  for (std::uint32_t i = 0; i < miss_count; ++i) {
    const std::uint32_t j = miss[i];
    const float* frequency = &band_frequency_[std::size_t(std::max(profile_of_[first + j], 0)) * kMaxBands];
    std::uint32_t shown = 0;
    for (std::uint32_t k = 0; k < max_band_count_; ++k) shown += frequency[k] * inv_diam[j] <= b.nyquist[j];
    bands[j] = shown;
  }
  // Pass 2: objects decided by their memo; of the rest, those not seen, of a bias without tables or
  // with nothing to choose; the any-view rows of the others found (per table set) and prefetched, so
  // that pass 3 decides without reading a profile.
  const int sets = margin_sets(config_);  // the hysteresis margin's tables too
  const std::int16_t* rows[2][kBlock];
  std::uint8_t standing[kBlock];           // decided by a memo that stands now: its rest may be set
  for (std::uint32_t j = 0; j < n; ++j) {  // the memo's decision for every object: misses overwrite it
    standing[j] = static_cast<std::uint8_t>(decided[j]);
    todo[j] = 0;
    out[j] = {memo.fine[first + j], memo.coarse[first + j], gaze_flag};
  }
  for (std::uint32_t i = 0; i < miss_count; ++i) {
    const std::uint32_t j = miss[i];
    const ObjectId id = first + j;
    const int p = profile_of_[id];
    if (p < 0) continue;
    const Look look = b.state(j);
    if (look != Look::Ok || bias_tables_[id] == kExactBias) {
      Sight s;
      if (look == Look::Ok) {
        sight(id, eye, b, j, &s);
        aim(id, &s);
      }
      out[j] = evaluate(id, look, s, scores ? scores[j] : nullptr, nullptr);
      continue;
    }
    const ProfileCache& pc = profiles_[p];
    const std::uint32_t L = pc.profile.meta.level_count - 1;
    if (L == 0 || bands[j] == 0) {  // one level, or none of it shown: no tables to read
      const auto top = static_cast<std::uint8_t>(bands[j] == 0 ? L : 0);
      out[j] = {top, top, gaze_flag};
      if (scores) std::fill(scores[j], scores[j] + L + 1, 0.0f);
      continue;
    }
    todo[j] = 1;
    tables[j] = static_cast<std::uint8_t>(2 * bias_tables_[id]);
    if (scores) continue;  // every level's score: the view's tables
    if (view_memo[j]) {    // its memo through the view decides if the view and cells are the same
      ACUITY_PREFETCH(&memo.view_key[id]);
      ACUITY_PREFETCH(&memo.speed_key[id]);
      continue;
    }
    todo[j] = 2;
    for (int set = 0; set < sets; ++set) {
      const std::int16_t* row = any_view_row(pc, L, bands[j], ec_j[j], tables[j] + set);
      rows[set][j] = row;
      ACUITY_PREFETCH(row);
      ACUITY_PREFETCH(row + 4 * L + 1);  // the upper node's row ends here
    }
  }
  // Pass 3: the any-view decisions, over the cell or else at the object's place in it, remembered with
  // the x and eccentricity where they stand; the rest have their lookup cell (of the direction to the
  // eye) found and its candidates prefetched.
  for (std::uint32_t i = 0; i < miss_count; ++i) {
    const std::uint32_t j = miss[i];
    if (!todo[j]) continue;
    const ObjectId id = first + j;
    if (todo[j] == 2) {
      const std::uint32_t L = level_count_[profile_of_[id]] - 1u;
      Stand stand;  // the whole cell
      int fine = any_view_level(rows[0][j], L, x_step[j], still[j], &stand.lo, &stand.hi);
      int coarse = sets > 1 && fine >= 0
                       ? any_view_level(rows[1][j], L, x_step[j], still[j], &stand.lo, &stand.hi)
                       : fine;
      bool remembered = coarse >= 0;
      if (coarse < 0) {  // not over the whole cell: at the object's place in it, remembered around it
        const float x = b.ln_diam[j], w = ec_w[j];
        fine = any_view_level_at(rows[0][j], L, x, w, still[j]);
        coarse = sets > 1 && fine >= 0 ? any_view_level_at(rows[1][j], L, x, w, still[j]) : fine;
        const auto lines = [&](const auto& line) {
          for (int set = 0; set < sets; ++set) any_view_lines(rows[set][j], L, still[j], line);
        };
        remembered = coarse >= 0 && stand_at_place(x, x_step[j], w, lines, &stand);
      }
      todo[j] = coarse < 0;
      if (coarse >= 0)
        out[j] = {static_cast<std::uint8_t>(fine), static_cast<std::uint8_t>(coarse), gaze_flag};
      standing[j] = remembered;
      if (remembered)
        memo.remember(id, Memo::key_of(ec_j[j], still[j], bias_tables_[id]), stand,
                      &band_frequency_[std::size_t(profile_of_[id]) * kMaxBands], bands[j], fine, coarse);
    }
    if (todo[j]) {
      const Profile& p = profiles_[profile_of_[id]].profile;
      const float to_eye[3] = {b.to_eye[0][j], b.to_eye[1][j], b.to_eye[2][j]};
      cand[j] = p.lookup + cube_cell(to_eye, p.meta.lookup_resolution) * kLookupCandidates;
      ACUITY_PREFETCH(cand[j]);
    }
  }
  // The objects left for passes 4 to 6, listed without branches (which ones remain is unpredictable).
  static_assert(kBlock <= 256, "left[] holds block indices in bytes");
  std::uint8_t left[kBlock];
  std::uint32_t left_count = 0;
  for (std::uint32_t j = 0; j < n; ++j) {
    left[left_count] = static_cast<std::uint8_t>(j);
    left_count += todo[j] != 0;
  }
  // Pass 4: the nearest view, the slip in its image axes; the objects whose memo through the view
  // stands decided, the still (or slow) rows of the others prefetched.
  const bool max3 = config_.view_blend == ViewBlend::Max3;
  for (std::uint32_t i = 0; i < left_count; ++i) {
    const std::uint32_t j = left[i];
    const ObjectId id = first + j;
    const ProfileCache& pc = profiles_[profile_of_[id]];
    const Profile& p = pc.profile;
    const std::uint32_t B = p.meta.band_count, L = p.meta.level_count - 1;
    Probe& o = probe[j];
    o.x = b.ln_diam[j];
    o.tables = tables[j];
    o.bands = bands[j];
    o.ec = {ec_j[j], ec_w[j]};
    const Vec3 image{b.image[0][j], b.image[1][j], b.image[2][j]};
    const Vec3 slip = retinal_slip(image, eye.gaze_moving, eye.gaze_velocity, config_.params);
    const Vec3 to_eye{b.to_eye[0][j], b.to_eye[1][j], b.to_eye[2][j]};
    const std::uint32_t view = nearest_view(p, cand[j], to_eye);
    const float q[4] = {rotation_[0][id], rotation_[1][id], rotation_[2][id], rotation_[3][id]};
    slip_in_view(slip, q, &pc.view_right[3 * std::size_t(view)], p.views[view].up, &o.vx, &o.vy);
    o.moving = o.vx != 0.0f || o.vy != 0.0f;
    o.cells = false;
    o.em = {0, 0.0f};
    o.view_count = max3 ? std::uint8_t(kLookupCandidates) : std::uint8_t(1);
    o.where = max3 ? static_cast<std::uint32_t>((cand[j] - p.lookup) / kLookupCandidates) : view;
    o.nearest = view;
    o.slip = slip;
    o.decided = o.at_place = false;
    const std::uint32_t T = p.meta.orientation_count;
    if (view_memo[j] && Memo::keyable(o.moving, T)) {  // the same view and cells?
      if (o.moving) speed_cells(pc, b.e[j], &o);
      const bool quartered = (memo.view_key[id] & Memo::kQuartered) != 0;
      const bool same = memo.view_key[id] == Memo::view_key_of(o, quartered) &&
                        memo.speed_key[id] == Memo::speed_key_of(o, T, quartered);
      o.at_place = same && memo.fine[id] == Memo::kAtPlace;
      o.decided = same && !o.at_place;
      standing[j] = o.decided;
      if (o.decided) {  // out[j] holds its memo's decision; its hold moves here
        hold_view(memo, id, pc, o, cand[j], b, j, quartered, still[j]);
        continue;
      }
    }
    for (std::uint32_t c = 0; c < o.view_count; ++c) {
      o.views[c] = max3 ? cand[j][c] : static_cast<std::uint16_t>(view);
      for (int set = 0; set < sets; ++set) {  // the two nodes' rows, which may cross a line
        const ProfileCache::Tables& ts = pc.sets[o.tables + set];
        const std::int16_t* row = &(o.moving ? ts.slow : ts.still)[o.still_row(c, B, L)];
        ACUITY_PREFETCH(row);
        ACUITY_PREFETCH(row + 2 * L - 1);
      }
    }
  }
  // Pass 5: moving objects whose slow bound (read a pass after its prefetch) does not pass the coarsest
  // level: their grid cells, and the moving tables' rows they read prefetched (most never read them).
  for (std::uint32_t i = 0; i < left_count; ++i) {
    const std::uint32_t j = left[i];
    Probe& o = probe[j];
    if (!o.moving || o.decided) continue;
    const ProfileCache& pc = profiles_[profile_of_[first + j]];
    const std::uint32_t B = pc.profile.meta.band_count, T = pc.profile.meta.orientation_count,
                        L = pc.profile.meta.level_count - 1;
    for (std::uint32_t c = 0; c < o.view_count; ++c) {
      const std::int16_t* slow =
          &pc.sets[o.tables].slow[o.still_row(c, B, L) + (L - 1)];  // the coarsest level
      if (o.x <= between(slow[0], slow[L], o.ec.w)) continue;
      if (!o.cells) speed_cells(pc, b.e[j], &o);
      // At its place, table_choice() mostly decides within the first orientations; over the whole
      // cells (view_cell_level()), it reads them all.
      const std::uint32_t read = o.at_place ? std::min(T, 2u) : T;
      for (std::uint32_t t = 0; t < read; ++t) {
        const std::int16_t* r0 = &pc.sets[o.tables].moving[o.moving_row(c, t, T, L)];
        ACUITY_PREFETCH_L2(r0);
        ACUITY_PREFETCH_L2(r0 + std::size_t(kMovingE) * L);
      }
    }
  }
  // Pass 6: the decisions through the objects' views: over their whole cells where those decide, else
  // at their place in the cells; remembered where they stand (a moving image: over whole cells or over
  // the quarters of its cells it lies in).
  for (std::uint32_t i = 0; i < left_count; ++i) {
    const std::uint32_t j = left[i];
    Probe& o = probe[j];
    if (o.decided) continue;
    const ObjectId id = first + j;
    const ProfileCache& pc = profiles_[profile_of_[id]];
    const std::uint32_t T = pc.profile.meta.orientation_count;
    if (!scores && !o.at_place && Memo::keyable(o.moving, T)) {
      if (o.moving && !o.cells) speed_cells(pc, b.e[j], &o);
      Stand stand;  // the whole cells
      int fine = view_cell_level(pc, o, x_step[j], 0, false, &stand.lo, &stand.hi);
      int coarse =
          sets > 1 && fine >= 0 ? view_cell_level(pc, o, x_step[j], 1, false, &stand.lo, &stand.hi) : fine;
      bool stands = coarse >= 0, quartered = false;
      if (!stands && o.moving && Memo::quarterable(T)) {  // a moving image: over its cells' quarters
        stand = Stand{};
        float w_from, w_to;
        weight_range(true, o.ec.w, &w_from, &w_to);
        stand.w_from = static_cast<std::uint16_t>(w_from * kWeightSteps);
        stand.w_to = static_cast<std::uint16_t>(w_to * kWeightSteps);
        fine = view_cell_level(pc, o, x_step[j], 0, true, &stand.lo, &stand.hi);
        coarse =
            sets > 1 && fine >= 0 ? view_cell_level(pc, o, x_step[j], 1, true, &stand.lo, &stand.hi) : fine;
        stands = quartered = coarse >= 0;
      }
      if (!stands && !o.moving) {  // a still image: decided at its place in the cell, remembered around it
        const Choice at = table_choice(pc, b.e[j], o, nullptr);
        fine = at.fine;
        coarse = at.coarse;
        const std::uint32_t B = pc.profile.meta.band_count, L = pc.profile.meta.level_count - 1;
        const auto lines = [&](const auto& line) {  // table_choice()'s: each set's, view's and level's
          for (int set = 0; set < sets; ++set)
            for (std::uint32_t c = 0; c < o.view_count; ++c) {
              const std::int16_t* row = &pc.sets[o.tables + set].still[o.still_row(c, B, L)];
              for (std::uint32_t k = 1; k <= L; ++k) line(row[k - 1], row[L + k - 1], 0.0f);
            }
        };
        stands = stand_at_place(o.x, x_step[j], o.ec.w, lines, &stand);
      }
      // Where it stands nowhere, the memo says so: next time at its place.
      memo.remember(id, Memo::key_of(ec_j[j], still[j], bias_tables_[id]) | Memo::kThroughView, stand,
                    &band_frequency_[std::size_t(profile_of_[id]) * kMaxBands], bands[j],
                    stands ? fine : Memo::kAtPlace, stands ? coarse : Memo::kAtPlace);
      memo.view_key[id] = Memo::view_key_of(o, quartered);
      memo.speed_key[id] = Memo::speed_key_of(o, T, quartered);
      if (stands) hold_view(memo, id, pc, o, cand[j], b, j, quartered, still[j]);
      standing[j] = stands;
      if (coarse >= 0) {
        out[j] = {static_cast<std::uint8_t>(fine), static_cast<std::uint8_t>(coarse), gaze_flag};
        continue;
      }
    }
    out[j] = table_choice(pc, b.e[j], o, scores ? scores[j] : nullptr);
    out[j].flags |= gaze_flag;
  }
  // Rests for the objects a standing memo decided, where the eye can rest (none with scores); where
  // few objects were at rest last frame, in one block of eight each frame (an eye that keeps moving
  // leaves them at once: little is spent on them).
  if (resting_ && !scores && (many_at_rest_ || (first / kBlock + frame_) % 8 == 0))
    for (std::uint32_t j = 0; j < n; ++j)
      if (standing[j] && frame_ - memo.rest_frame[first + j] >=
                             (memo.rest_m[first + j] >= 0 ? Memo::kLeftRetry : Memo::kRetry))
        set_rest(eye, memo, first + j, b, j);
}

// A moving object's cells on the moving grid: eccentricity e [deg], each orientation's speed.
ACUITY_SIMD_CLONES void Scheduler::speed_cells(const ProfileCache& pc, float e, Probe* o) const {
  const float floor = pre_->floor_velocity, v0 = pre_->speed_offset, vx = o->vx, vy = o->vy;
  const float *cos_t = pc.cos_t.data(), *sin_t = pc.sin_t.data();
  const std::uint32_t T = pc.profile.meta.orientation_count;
  o->em = e_cell<kMovingE>(e);
  ACUITY_NO_ALIAS
  for (std::uint32_t t = 0; t < T; ++t)
    speed_cell(std::max(std::abs(vx * cos_t[t] + vy * sin_t[t]), floor), floor, v0, kMovingS, &o->speed_j[t],
               &o->speed_w[t]);
  o->cells = true;
}

// The perceptual rule through the tables: per level, is the object's angular size at most the largest
// invisible one at its eccentricity (and, moving, per orientation at its retinal speed)? With
// `scores` (K floats) every level's score; without, a moving object's bounds stop at the first that
// decides. For a profile of two or more levels and an object the display shows bands of (tabulate
// decides the others without tables).
Scheduler::Choice Scheduler::table_choice(const ProfileCache& pc, float e, Probe& o, float* scores) const {
  const Profile& p = pc.profile;
  const std::uint32_t K = p.meta.level_count, T = p.meta.orientation_count, B = p.meta.band_count;
  const std::uint32_t L = K - 1;          // coarser levels per view
  const int sets = margin_sets(config_);  // [1]: the hysteresis margin's tables
  const float x = o.x;
  if (scores) std::fill(scores, scores + K, 0.0f);
  const Cell ec = o.ec;
  // Per set, view and level k, the largest invisible ln diameter from the still (or, moving, the
  // slow) tables; the level's bound is the smallest over the views. A still object needs no more.
  float bound[2][kLookupCandidates][kMaxLevels], size[2][kMaxLevels];
  for (int set = 0; set < sets; ++set)
    for (std::uint32_t c = 0; c < o.view_count; ++c) {
      const ProfileCache::Tables& tables = pc.sets[o.tables + set];
      const std::int16_t* row = &(o.moving ? tables.slow : tables.still)[o.still_row(c, B, L)];
      for (std::uint32_t k = 1; k <= L; ++k) {
        bound[set][c][k] = between(row[k - 1], row[L + k - 1], ec.w);
        size[set][k] = c == 0 ? bound[set][c][k] : std::min(size[set][k], bound[set][c][k]);
      }
    }
  if (o.moving) {
    // Per orientation at its own speed, the moving tables' bound where the slow one does not pass;
    // per view the larger of the two holds. Without scores, from the coarsest level until one passes.
    if (!o.cells) speed_cells(pc, e, &o);
    const Cell em = o.em;
    const bool decide_only = scores == nullptr;
    for (std::uint32_t k = L; k >= 1; --k) {
      for (int set = 0; set < sets; ++set) {
        float least = -kNever;  // over the views
        for (std::uint32_t c = 0; c < o.view_count; ++c) {
          const float slow_bound = bound[set][c][k];
          if (decide_only && x <= slow_bound) {
            least = std::min(least, slow_bound);
            continue;
          }
          float m = -kNever;
          for (std::uint32_t t = 0; t < T; ++t) {
            const std::int16_t* r0 = &pc.sets[o.tables + set].moving[o.moving_row(c, t, T, L) + (k - 1)];
            const std::int16_t* r1 = r0 + std::size_t(kMovingE) * L;
            const float lo = between(r0[0], r0[L], em.w), hi = between(r1[0], r1[L], em.w);
            m = std::min(m, lo + o.speed_w[t] * (hi - lo));
            if (decide_only && m < x) break;  // this orientation alone makes the level visible
          }
          least = std::min(least, std::max(m, slow_bound));
        }
        size[set][k] = least;
      }
      if (decide_only && x <= size[sets - 1][k]) break;  // the coarsest level passing every set
    }
  }
  const float* coarse_size = size[sets - 1];  // without a margin, the same tables
  // The coarsest level that passes (levels above a moving object's break passed no set).
  Choice out{0, 0, 0};
  for (std::uint32_t k = 1; k <= L; ++k) {
    out.fine = x <= size[0][k] ? static_cast<std::uint8_t>(k) : out.fine;
    out.coarse = x <= coarse_size[k] ? static_cast<std::uint8_t>(k) : out.coarse;
    if (scores) scores[k] = std::exp(std::min(x - size[0][k], 80.0f));
  }
  return out;
}

// The perceptual rule evaluated in full (and Reddy's rule):
//   per band b: f = f_b / D [cpd]; ln CT(t, b) from the threshold model (bands above the display's
//   Nyquist frequency are invisible); level k's score = max_tb lost_k / (q CT).
Scheduler::Choice Scheduler::choose_exact(ObjectId id, const Sight& s, float* scores_out,
                                          ObjectExplain* ex) const {
  const ProfileCache& pc = profiles_[profile_of_[id]];
  const Profile& p = pc.profile;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count;
  Choice out{0, 0, s.flags};
  const float nyquist_cpd = s.nyquist_cpd, diameter_deg = s.diameter_deg, e = s.e;
  const std::uint32_t view = s.view;
  const std::uint16_t* cand = s.cand;
  const bool moving = s.moving;
  const float vx = s.vx, vy = s.vy;
  const Precomputed& pre = *pre_;
  const float inv_diam = 1.0f / diameter_deg, ln_diam = s.ln_diam;
  const float ln_q = pre.ln_quality_at(bias_[id]);
  const float ln_q_coarse = ln_q + pre.ln_margin;
  const bool all_levels = scores_out || ex;
  const float a = pre.ecc_slope * e;  // ln CT grows by a per cpd with eccentricity

  // ln CT per (orientation, band). A static object's velocity is the drift floor in every
  // orientation, so one row serves all of them (rows = 1).
  float ln_ct[kMaxOrientations * kMaxBands];
  float v_t[kMaxOrientations];
  const std::uint32_t rows = moving || config_.model != ThresholdModel::Default ? T : 1;
  for (std::uint32_t t = 0; t < rows; ++t) {
    v_t[t] = moving ? std::max(std::abs(vx * pc.cos_t[t] + vy * pc.sin_t[t]), pre.floor_velocity)
                    : pre.floor_velocity;
    float* row = ln_ct + t * B;
    if (config_.rule == SelectionRule::Reddy) {  // the visible limit per orientation, in cpod
      row[0] = std::min(reddy_cutoff(v_t[t], e), nyquist_cpd) * diameter_deg;
      continue;
    }
    if (config_.model == ThresholdModel::Default) {
      const VelocityTerms own = moving ? pre.terms_at(v_t[t]) : pre.static_terms;
      for (std::uint32_t b = 0; b < B; ++b) {
        const float f = p.bands[b] * inv_diam;
        const float ln_f = pc.ln_band[b] - ln_diam;
        row[b] =
            f > nyquist_cpd ? kInf : pre.default_ln_ct(pre.band_terms(own, v_t[t], ln_f, moving), ln_f, f, a);
      }
    } else {
      for (std::uint32_t b = 0; b < B; ++b) {
        const float f = p.bands[b] * inv_diam;
        row[b] = f > nyquist_cpd ? kInf : log_threshold(f, e, v_t[t], config_.model, config_.params);
      }
    }
  }
  const std::uint32_t stride = rows == 1 ? 0 : B;  // a static object's one row serves every orientation

  // ln(score_k q) = max over (t, b) of ln lost - ln CT. Levels are scanned from the coarsest; without
  // scores or explain, the scan stops at the first level that passes even the hysteresis margin.
  const std::size_t TB = std::size_t(T) * B;
  // Reddy: a finer level's smallest feature F is visible when it lies at or below the limit, so
  // level k's score is the largest limit / F over the levels j < k and every orientation.
  float reddy_prefix[kMaxLevels] = {};
  if (config_.rule == SelectionRule::Reddy)
    for (std::uint32_t j = 0; j + 1 < K; ++j) {
      float worst = reddy_prefix[j];
      for (std::uint32_t t = 0; t < T; ++t) {
        const float F = p.feature_frequency(j, view, t);
        if (F > 0) worst = std::max(worst, ln_ct[t * stride] / F);
      }
      reddy_prefix[j + 1] = worst;
    }
  bool fine_found = false;
  for (std::uint32_t k = K - 1; k >= 1; --k) {
    float m = -kInf;
    if (config_.rule == SelectionRule::Reddy) {
      m = reddy_prefix[k] > 0 ? std::log(reddy_prefix[k]) : -kInf;
    } else {
      // A static object's thresholds do not depend on orientation: its per-band maxima suffice.
      const std::vector<float>& lost = stride ? pc.ln_lost : pc.ln_lost_any;
      const std::uint32_t t_count = stride ? T : 1;
      const std::size_t per_view = std::size_t(t_count) * B;
      const std::uint32_t blended = config_.view_blend == ViewBlend::Max3 ? kLookupCandidates : 1;
      for (std::uint32_t j = 0; j < blended; ++j) {
        const std::uint32_t w = blended == 1 ? view : cand[j];
        m = std::max(m,
                     max_excess(&lost[((k - 1) * std::size_t(V) + w) * per_view], ln_ct, t_count, B, stride));
      }
    }
    if (!fine_found && m <= ln_q) {
      out.fine = static_cast<std::uint8_t>(k);
      fine_found = true;
    }
    if (out.coarse == 0 && m <= ln_q_coarse) out.coarse = static_cast<std::uint8_t>(k);
    if (scores_out) scores_out[k] = std::exp(m - ln_q);
    if (ex) {
      LevelExplain& le = ex->levels[k];
      le.score = std::exp(m - ln_q);
      std::uint32_t arg = 0;  // the limiting component, found again (explain is not the hot path)
      if (config_.rule == SelectionRule::Reddy) {
        float best_ratio = -kInf;
        for (std::uint32_t j = 0; j < k; ++j)
          for (std::uint32_t t = 0; t < T; ++t) {
            const float F = p.feature_frequency(j, view, t);
            if (F > 0 && ln_ct[t * stride] / F > best_ratio) {
              best_ratio = ln_ct[t * stride] / F;
              arg = t * B;
            }
          }
      } else {
        const float* lost = &pc.ln_lost[((k - 1) * std::size_t(V) + view) * TB];
        float best_x = -kInf;
        for (std::uint32_t i = 0; i < T * B; ++i) {
          const float x = lost[i] - ln_ct[(i / B) * stride + i % B];
          if (x > best_x) {
            best_x = x;
            arg = i;
          }
        }
      }
      le.orientation = static_cast<std::uint8_t>(arg / B);
      le.band = static_cast<std::uint8_t>(arg % B);
      le.frequency_cpd = p.bands[le.band] * inv_diam;
      le.threshold = config_.rule == SelectionRule::Reddy
                         ? 0.0f
                         : std::exp(std::min(ln_ct[(arg / B) * stride + arg % B], 80.0f));
    }
    if (out.coarse != 0 && !all_levels) break;
  }
  if (ex) {
    ex->distance_m = s.d;
    ex->angular_diameter_deg = diameter_deg;
    ex->eccentricity_deg = e;
    ex->image_velocity_deg_s = length(s.image);
    ex->retinal_velocity_deg_s = length(s.slip);
    ex->view = view;
    ex->level_count = static_cast<std::uint8_t>(K);
    ex->levels[0] = LevelExplain{0, 0, 0, 0, 0};
  }
  return out;
}

// The perceptual rules for a block whose passes are done: each eye's choice, the finer need wins.
void Scheduler::choose_perceptual(std::uint32_t first, std::uint32_t n, const Look (*looks)[kBlock],
                                  const Sight (*sights)[kBlock], Decisions* out) {
  for (std::uint32_t j = 0; j < n; ++j) {
    const ObjectId id = first + j;
    if (profile_of_[id] < 0) continue;
    const std::uint32_t K = level_count_[profile_of_[id]];
    std::uint8_t fine = 255, coarse = 255, flags = 0;
    float* kept = config_.keep_scores ? &scores_[std::size_t(id) * kMaxLevels] : nullptr;
    float eye_scores[kMaxLevels];
    for (std::uint32_t i = 0; i < eye_count_; ++i) {  // both eyes agree: the finer need wins
      const Choice c = evaluate(id, looks[i][j], sights[i][j], kept ? eye_scores : nullptr, nullptr);
      fine = std::min(fine, c.fine);
      coarse = std::min(coarse, c.coarse);
      flags |= c.flags;
      if (kept)
        for (std::uint32_t k = 0; k < K; ++k)
          kept[k] = i == 0 ? eye_scores[k] : std::max(kept[k], eye_scores[k]);
    }
    out->fine[j] = fine;
    out->coarse[j] = coarse;
    out->flags[j] = flags;
  }
}

// The tabulated path for a block whose geometry is done: each eye's choice, the finer need wins.
void Scheduler::choose_tabulated(std::uint32_t first, std::uint32_t n, const Block* blocks, Decisions* out) {
  Choice eye_choice[2][kBlock];
  float eye_scores[kBlock][kMaxLevels];  // the second eye's, with keep_scores
  auto* kept = config_.keep_scores
                   ? reinterpret_cast<float(*)[kMaxLevels]>(&scores_[std::size_t(first) * kMaxLevels])
                   : nullptr;
  for (std::uint32_t i = 0; i < eye_count_; ++i)
    tabulate(eyes_[i], first, n, blocks[i], memos_[i], eye_choice[i], kept && i > 0 ? eye_scores : kept);
  for (std::uint32_t j = 0; j < n; ++j) {
    const int p = profile_of_[first + j];
    if (p < 0) continue;
    Choice c = eye_choice[0][j];
    if (eye_count_ > 1) {
      const Choice& d = eye_choice[1][j];
      c = {std::min(c.fine, d.fine), std::min(c.coarse, d.coarse),
           static_cast<std::uint8_t>(c.flags | d.flags)};
      if (kept)
        for (std::uint32_t k = 0; k < level_count_[p]; ++k)
          kept[j][k] = std::max(kept[j][k], eye_scores[j][k]);
    }
    out->fine[j] = c.fine;
    out->coarse[j] = c.coarse;
    out->flags[j] = c.flags;
  }
}

// Clamps and hysteresis for a block, branch-free per object: a new object takes its first level at
// once; a finer level (or the fallback) applies at once; a coarser one after hysteresis_frames
// calm frames and, with saccade gating, in a saccade or after max_coarsen_wait frames (kFlagHeld
// meanwhile). Free slots keep their state.
ACUITY_SIMD_CLONES void Scheduler::settle(std::uint32_t first, std::uint32_t n, const Decisions& d) {
  const std::uint32_t frames = config_.hysteresis_frames, max_wait = config_.max_coarsen_wait;
  const std::uint32_t gate_open = config_.saccade_speed <= 0 || saccade_;
  const int* profile = &profile_of_[first];
  const std::uint8_t *max_level = &max_level_[first], *min_level = &min_level_[first];
  std::uint8_t *chosen = &chosen_[first], *next_level = &next_[first], *flags = &flags_[first],
               *fresh = &fresh_[first];
  std::uint32_t *calm_frames = &calm_frames_[first], *wait_frames = &wait_frames_[first];
  // Plain arithmetic and selects (no short-circuits, every load unconditional): it vectorises.
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::uint32_t alive = profile[j] >= 0;
    const std::uint32_t hi = max_level[j];  // clamped to the profile's coarsest level (set_clamps)
    const std::uint32_t lo = min_level[j] < hi ? min_level[j] : hi;
    const std::uint32_t want_fine = d.fine[j], want_coarse = d.coarse[j];
    const std::uint32_t fine = want_fine < lo ? lo : want_fine > hi ? hi : want_fine;
    const std::uint32_t coarse = want_coarse < lo ? lo : want_coarse > hi ? hi : want_coarse;
    const std::uint32_t current = chosen[j];
    const std::uint32_t calm = calm_frames[j], wait = wait_frames[j];
    const std::uint32_t refine = std::uint32_t(fresh[j] != 0) |
                                 std::uint32_t((d.flags[j] & kFlagInvalidInput) != 0) |
                                 std::uint32_t(fine < current);
    const std::uint32_t coarsen = (refine ^ 1u) & std::uint32_t(coarse > current);
    const std::uint32_t settled = calm + 1 >= frames;
    const std::uint32_t go = coarsen & settled & (gate_open | std::uint32_t(wait >= max_wait));
    const std::uint32_t held = coarsen & (go ^ 1u);
    const auto level = static_cast<std::uint8_t>(refine ? fine : go ? coarse : current);
    const auto flag = static_cast<std::uint8_t>(d.flags[j] | (held ? kFlagHeld : 0));
    // A free slot keeps its state: masks, not selects (GCC turns those into conditional stores).
    const auto keep = static_cast<std::uint8_t>(alive - 1u), take = static_cast<std::uint8_t>(~keep);
    const std::uint32_t keep_count = alive - 1u;
    chosen[j] = static_cast<std::uint8_t>((level & take) | (chosen[j] & keep));
    next_level[j] = static_cast<std::uint8_t>((level & take) | (next_level[j] & keep));
    flags[j] = static_cast<std::uint8_t>((flag & take) | (flags[j] & keep));
    fresh[j] = static_cast<std::uint8_t>(fresh[j] & keep);
    calm_frames[j] = ((held ? calm + 1 : 0u) & ~keep_count) | (calm & keep_count);
    wait_frames[j] = ((held ? wait + settled : 0u) & ~keep_count) | (wait & keep_count);
  }
}

void Scheduler::end_frame() {
  if (config_.triangle_budget > 0) apply_budget();
  FrameStats& st = stats_;
  st.changed = st.invalid = st.budget_forced = st.at_rest = 0;
  const bool fades = config_.transition_seconds > 0;  // else every fade_ stays 1 (not read)
  constexpr std::uint32_t kChunk = 256;
  for (std::uint32_t first = 0; first < config_.max_objects; first += kChunk) {
    const std::uint32_t n = std::min(kChunk, config_.max_objects - first);
    if (count_flags(first, n, &st) == 0 && !fades) continue;  // nothing to write
    for (std::uint32_t id = first; id < first + n; ++id) {
      if (profile_of_[id] < 0) continue;
      if (next_[id] != level_[id]) {  // a change event; the cross-fade starts from the drawn level
        const std::uint32_t* triangles = &triangles_[std::size_t(profile_of_[id]) * kMaxLevels];
        drawn_triangles_ += triangles[next_[id]] - std::uint64_t(triangles[level_[id]]);
        from_level_[id] = level_[id];
        fade_[id] = fades ? 0.0f : 1.0f;
        flags_[id] |= kFlagChanged;
        level_[id] = next_[id];
      } else if (fades && fade_[id] < 1.0f) {
        fade_[id] = std::min(1.0f, fade_[id] + dt_ / config_.transition_seconds);
      }
    }
  }
  st.triangles = drawn_triangles_;
}

// Counts the flags of `count` objects from `first` into st as end_frame() leaves them (kFlagChanged
// where the next level is not the drawn one), and returns how many levels change. Reads only: it
// vectorises, and the objects whose level stays are not written. Free slots count nothing (their
// flags and rest are 0 and their next level the drawn one: remove_object()).
ACUITY_SIMD_CLONES std::uint32_t Scheduler::count_flags(std::uint32_t first, std::uint32_t n,
                                                        FrameStats* st) const {
  const std::uint8_t *next = &next_[first], *level = &level_[first], *flags = &flags_[first],
                     *rest = &rest_[first];
  std::uint32_t changes = 0, changed = 0, invalid = 0, forced = 0, at_rest = 0;
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::uint32_t change = next[j] != level[j];
    const std::uint32_t flag = flags[j];
    changes += change;
    changed += change | std::uint32_t((flag & kFlagChanged) != 0);
    invalid += (flag & kFlagInvalidInput) != 0;
    forced += (flag & kFlagBudgetForced) != 0;
    at_rest += rest[j];
  }
  st->changed += changed;
  st->invalid += invalid;
  st->budget_forced += forced;
  st->at_rest += at_rest;
  return changes;
}

// Funkhouser & Sequin: while over budget, coarsen by one level the object whose next level costs
// the least perceptual harm (its score) per triangle saved. Ties go to the lower id.
void Scheduler::apply_budget() {
  std::uint64_t total = 0;
  for (std::uint32_t id = 0; id < config_.max_objects; ++id)
    if (profile_of_[id] >= 0) total += profiles_[profile_of_[id]].profile.levels[next_[id]].triangles;
  if (total <= config_.triangle_budget) return;

  auto can_coarsen = [&](std::uint32_t id) {
    const std::uint32_t K = profiles_[profile_of_[id]].profile.meta.level_count;
    // An object with invalid input keeps its fallback level: a tracking glitch must not drop it.
    return next_[id] + 1u < std::min<std::uint32_t>(max_level_[id] + 1u, K) &&
           !(flags_[id] & (kFlagEyeInside | kFlagInvalidInput));
  };
  auto harm = [&](std::uint32_t id) {
    const Profile& p = profiles_[profile_of_[id]].profile;
    const std::uint32_t l = next_[id];
    const float saved =
        static_cast<float>(p.levels[l].triangles) - static_cast<float>(p.levels[l + 1].triangles);
    return scores_[std::size_t(id) * kMaxLevels + l + 1] / std::max(saved, 1.0f);
  };
  // Min-heap on (harm, id).
  auto later = [&](std::uint32_t x, std::uint32_t y) {
    const float hx = harm(x), hy = harm(y);
    return hx != hy ? hx > hy : x > y;
  };
  heap_.clear();
  for (std::uint32_t id = 0; id < config_.max_objects; ++id)
    if (profile_of_[id] >= 0 && can_coarsen(id)) heap_.push_back(id);
  std::make_heap(heap_.begin(), heap_.end(), later);
  while (total > config_.triangle_budget && !heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const std::uint32_t id = heap_.back();
    heap_.pop_back();
    const Profile& p = profiles_[profile_of_[id]].profile;
    const std::uint8_t l = next_[id];
    total -= p.levels[l].triangles - p.levels[l + 1].triangles;
    if (scores_[std::size_t(id) * kMaxLevels + l + 1] > 1.0f) flags_[id] |= kFlagBudgetForced;
    next_[id] = static_cast<std::uint8_t>(l + 1);
    if (can_coarsen(id)) {
      heap_.push_back(id);
      std::push_heap(heap_.begin(), heap_.end(), later);
    }
  }
}

bool Scheduler::explain(ObjectId id, ObjectExplain* out) const {
  if (!alive(id) || !out) return false;
  *out = ObjectExplain{};
  // The eye that needs the finer level is the one that decides.
  std::uint8_t best = 255;
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    ObjectExplain tmp{};
    Block block;
    look_block(eyes_[i], id, 1, &block);
    Sight s;
    const Look look = sight(id, eyes_[i], block, 0, &s);
    if (look == Look::Ok && perceptual()) aim(id, &s);
    const Choice c = evaluate(id, look, s, nullptr, &tmp);
    if (c.fine < best) {
      best = c.fine;
      *out = tmp;
    }
  }
  out->level = level_[id];
  out->level_count = static_cast<std::uint8_t>(profiles_[profile_of_[id]].profile.meta.level_count);
  return true;
}

namespace {
constexpr const char* kRuleNames[] = {"perceptual", "reddy", "distance",
                                      "screen-size"};               // SelectionRule order
constexpr const char* kEvaluationNames[] = {"tabulated", "exact"};  // Evaluation order
template <class E, std::size_t N>
bool parse_name(const char* name, const char* const (&names)[N], E* out) {
  if (!name) return false;
  for (std::size_t i = 0; i < N; ++i)
    if (std::strcmp(name, names[i]) == 0) {
      *out = static_cast<E>(i);
      return true;
    }
  return false;
}
}  // namespace

const char* to_string(SelectionRule rule) {
  const auto i = static_cast<std::size_t>(rule);
  return i < std::size(kRuleNames) ? kRuleNames[i] : "unknown";
}
const char* to_string(Evaluation evaluation) {
  const auto i = static_cast<std::size_t>(evaluation);
  return i < std::size(kEvaluationNames) ? kEvaluationNames[i] : "unknown";
}
bool parse_selection_rule(const char* name, SelectionRule* out) { return parse_name(name, kRuleNames, out); }
bool parse_evaluation(const char* name, Evaluation* out) { return parse_name(name, kEvaluationNames, out); }

}  // namespace acuity
