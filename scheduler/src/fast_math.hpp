// Branch-free replacements for the libm calls of the scheduler's per-object geometry: pure float
// arithmetic and selects, so the object loops vectorise and give the same bits on every IEEE-754
// binary32 target that does not contract a * b + c into one FMA (the project's x86-64 and wasm
// builds): no libm. Internal to scheduler/ (and its tests).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>

namespace acuity::detail {

// atan2(y, x) in degrees for y >= 0 (or y = -0), in [0, 180], within 1e-6 relative of std::atan2
// (test_fast_math, every magnitude): exact reductions to |t| <= tan 15 deg, then the odd Taylor series
// to t^9 (truncation below 6e-8 rad). x = -0 counts as +0 (0, not 180, for y = 0). NaN in either
// gives NaN, as do two infinities; one infinity gives the limit (0, 90 or 180). Negative y: outside
// the contract. Kept to the selects the scheduler's loops need: each more costs in the geometry pass.
[[gnu::always_inline]] inline float atan2_deg(float y, float x) {
  constexpr float kTan15 = 0.26794919f, kSqrt3 = 1.7320508f;
  constexpr float kDeg = 180.0f / std::numbers::pi_v<float>;
  const float ax = std::abs(x);
  const bool swap = y > ax;  // atan(y/x) = 90 - atan(x/y)
  const float num = swap ? ax : y, den = swap ? y : ax;
  float t = den == 0 ? 0.0f : num / den;  // NaN den (x NaN): NaN
  const bool reduce = t > kTan15;         // atan(t) = 30 deg + atan((sqrt3 t - 1) / (sqrt3 + t))
  t = reduce ? (kSqrt3 * t - 1.0f) / (kSqrt3 + t) : t;
  const float base = reduce ? 30.0f : 0.0f;
  const float t2 = t * t;
  const float a =
      base + kDeg * t * (1.0f + t2 * (-1.0f / 3 + t2 * (1.0f / 5 + t2 * (-1.0f / 7 + t2 * (1.0f / 9)))));
  const float first = swap ? 90.0f - a : a;
  return x < 0 ? 180.0f - first : first;
}

// Natural log, within 2 ulp of std::log for every normal positive float (test_fast_math, every
// binade). Outside that, no select (each costs in the geometry pass: a version exact for every
// special value measured up to 7% slower on the still benchmark with its tables in cache): 0 and
// subnormals give a value in [-88.03, -87.33] (ln FLT_MIN = -87.34; a size that small is invisible
// anyway), a negative x gives ln |x|, +inf and NaN a finite value above 88.7. The scheduler passes
// angular sizes, finite and >= 0. x = m 2^k with m in [sqrt(1/2), sqrt(2)), ln x = k ln 2 +
// ln(1 + f), f = m - 1, by a minimax series (Cephes' logf coefficients).
[[gnu::always_inline]] inline float ln_positive(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  int k = int((bits >> 23) & 255u) - 127;
  bits = (bits & 0x007fffffu) | 0x3f800000u;  // m in [1, 2)
  float m;
  std::memcpy(&m, &bits, sizeof m);
  const bool high = m > 1.41421356f;
  m = high ? 0.5f * m : m;
  k += high ? 1 : 0;
  const float f = m - 1.0f, z = f * f;
  float y =
      f * z *
      (3.3333331174e-1f +
       f * (-2.4999993993e-1f +
            f * (2.0000714765e-1f +
                 f * (-1.6668057665e-1f +
                      f * (1.4249322787e-1f +
                           f * (-1.2420140846e-1f +
                                f * (1.1676998740e-1f + f * (-1.1514610310e-1f + f * 7.0376836292e-2f))))))));
  const float kf = float(k);
  y += -2.12194440e-4f * kf - 0.5f * z;
  return f + y + 0.693359375f * kf;
}

}  // namespace acuity::detail
