// Branch-free replacements for the libm calls of the scheduler's per-object geometry: pure float
// arithmetic and selects, so the object loops vectorise and every compiler gives the same bits on
// IEEE-754 binary32 (no libm, no FMA contraction assumed). Internal to scheduler/ (and its tests).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>

namespace acuity::detail {

// atan2(y, x) in degrees, in [-180, 180] like std::atan2 (signed zeros included), within 1e-6
// relative of it (test_scheduler's FastMath tests, every magnitude): exact
// reductions to |t| <= tan 15 deg, then the odd Taylor series to t^9 (truncation below 6e-8 rad).
// NaN in either gives NaN; infinities give the limits (atan2(inf, inf) = 45).
[[gnu::always_inline]] inline float atan2_deg(float y, float x) {
  constexpr float kTan15 = 0.26794919f, kSqrt3 = 1.7320508f;
  constexpr float kDeg = 180.0f / std::numbers::pi_v<float>;
  const float ax = std::abs(x), ay = std::abs(y);
  const bool swap = ay > ax;  // atan(y/x) = 90 - atan(x/y)
  const float num = swap ? ax : ay, den = swap ? ay : ax;
  float t = num == den ? 1.0f : num / den;  // 0/0 and inf/inf: 45 deg (std::atan2(0, 0) is 0: below)
  t = den > 0 ? t : 0.0f;
  const bool reduce = t > kTan15;  // atan(t) = 30 deg + atan((sqrt3 t - 1) / (sqrt3 + t))
  t = reduce ? (kSqrt3 * t - 1.0f) / (kSqrt3 + t) : t;
  const float base = reduce ? 30.0f : 0.0f;
  const float t2 = t * t;
  const float a =
      base + kDeg * t * (1.0f + t2 * (-1.0f / 3 + t2 * (1.0f / 5 + t2 * (-1.0f / 7 + t2 * (1.0f / 9)))));
  const float first = swap ? 90.0f - a : a;
  const float half = std::signbit(x) ? 180.0f - first : first;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  return x != x ? nan : std::signbit(y) ? -half : half;  // a NaN y is NaN already
}

// Natural log, within 2 ulp of std::log for every positive float (normal or subnormal); 0 gives
// -inf, +inf gives +inf, negative or NaN gives NaN. x = m 2^k with m in [sqrt(1/2), sqrt(2)),
// ln x = k ln 2 + ln(1 + f), f = m - 1, by a minimax series (Cephes' logf coefficients).
[[gnu::always_inline]] inline float ln_positive(float x) {
  constexpr float kMinNormal = std::numeric_limits<float>::min();
  const bool subnormal = x < kMinNormal;                 // also 0, negatives: replaced below
  const float scaled = subnormal ? x * 16777216.0f : x;  // 2^24: exact
  std::uint32_t bits;
  std::memcpy(&bits, &scaled, sizeof bits);
  int k = int((bits >> 23) & 255u) - 127 - (subnormal ? 24 : 0);
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
  const float ln = f + y + 0.693359375f * kf;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  return x == 0 ? -kInf : !(x > 0) ? std::numeric_limits<float>::quiet_NaN() : x == kInf ? kInf : ln;
}

}  // namespace acuity::detail
