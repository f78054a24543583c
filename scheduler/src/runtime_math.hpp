#pragma once
// The runtime's internal arithmetic (scheduler/src only): vectors, the Default model's fast terms,
// the velocity envelope, and what depends only on the configuration (Scheduler::Impl::Precomputed).
#include "acuity/scheduler.hpp"

#include "fast_math.hpp"
#include "vectorize.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>

// Internal names live in acuity::internal (not an anonymous namespace: the per-frame types hold
// them, and every scheduler source shares them); namespace acuity sees them unqualified.
namespace acuity::internal {

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
// A score's or a threshold's ln is capped here before exp (e^80 ~ 5.5e34: finite, and "invisible").
constexpr float kLnCeiling = 80.0f;

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
// A rotation quaternion (x y z w) counts as a unit one, and is normalised, where its length (the
// block loop: its squared length) is within this of 1; beyond it, or not finite: invalid input.
constexpr float kUnitQuaternionRoom = 1e-3f;
inline float quaternion_length(const float* q) {
  return std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
}
inline bool unit_length(float length) { return std::abs(length - 1.0f) < kUnitQuaternionRoom; }

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
inline DalyConstants daly_constants(const ModelParams& p) {
  const DalyFitConstants f = daly_fit_constants(p.fit);
  return {float(std::log(f.prefactor)), float(f.c1), float(f.c2),
          float(std::log(2 * std::numbers::pi * f.c1)), float(std::max(p.drift, f.v_floor))};
}

inline VelocityTerms velocity_terms(float v, const DalyConstants& c) {
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

inline double argmax_speed(double f, const ModelParams& p) {
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

// ln of the pooled visibility of one level's loss in every channel (stela-csf on a profile with a
// Detail section, docs/design.md section 5): x = lost[t B + b] - ct[t B + b] (ln lost / CT per
// orientation t < T and band b < B); within a band the orientations add as energy (the analyzer's
// angular windows split a grating's energy between two neighbours, cos^2 + sin^2 = 1), and the bands
// by probability summation with exponent kBandPooling:
//   ln (sum_b (sum_t e^(2 x))^(kBandPooling / 2))^(1 / kBandPooling).
// One channel alone gives its x exactly; N equal channels within a band sqrt N times it. -inf
// entries (nothing lost, or above the display's Nyquist frequency) add nothing; a NaN counts as
// +inf (visible). Log-sum-exp from each sum's largest term: no overflow.
inline float pooled_excess(const float* lost, const float* ct, std::uint32_t T, std::uint32_t B) {
  float band[kMaxBands];
  float most = -kInf;
  for (std::uint32_t b = 0; b < B; ++b) {
    float top = -kInf;
    for (std::uint32_t t = 0; t < T; ++t) {
      const float x = lost[std::size_t(t) * B + b] - ct[std::size_t(t) * B + b];
      top = std::isnan(x) ? kInf : std::max(top, x);
      if (top == kInf) break;
    }
    float sum = 0.0f;  // sum_t e^(2 (x - top)), in [1, T]
    if (top > -kInf && top < kInf)
      for (std::uint32_t t = 0; t < T; ++t)
        sum += std::exp(2.0f * (lost[std::size_t(t) * B + b] - ct[std::size_t(t) * B + b] - top));
    band[b] = top > -kInf && top < kInf ? top + 0.5f * std::log(sum) : top;
    most = std::max(most, band[b]);
  }
  if (!(most > -kInf && most < kInf)) return most;
  float sum = 0.0f;  // sum_b e^(kBandPooling (band - most)), in [1, B]
  for (std::uint32_t b = 0; b < B; ++b) sum += std::exp(kBandPooling * (band[b] - most));
  return most + std::log(sum) / kBandPooling;
}

}  // namespace acuity::internal

namespace acuity {
using namespace internal;
}  // namespace acuity

#include "impl.hpp"  // Scheduler::Impl, whose members hold the types above

namespace acuity {

// Everything that depends only on the configuration, computed once at creation.
struct Scheduler::Impl::Precomputed {
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

}  // namespace acuity
