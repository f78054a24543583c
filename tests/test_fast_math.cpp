// The scheduler's branch-free atan2 and log (scheduler/src/fast_math.hpp) against std:: in double
// precision over their whole domain: every binade, zeros, subnormals, infinities, NaN; and the
// channel pooling (runtime_math.hpp, pooled_excess) against the formula in double, hard cases too.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "fast_math.hpp"
#include "runtime_math.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

double atan2_deg_ref(float y, float x) { return std::atan2(double(y), double(x)) * 180.0 / kPi; }

float from_bits(std::uint32_t bits) {
  float x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

TEST(SchedulerFastMath, Atan2WithinOneMillionthOfStdAtEveryAngleAndMagnitude) {
  double worst = 0;
  for (int e = -149; e <= 127; e += 2) {  // radii from the smallest subnormal to near FLT_MAX
    const double radius = std::ldexp(1.0, e);
    for (int i = 0; i <= 3600; ++i) {  // the contract's half plane, y >= 0
      const double angle = i * kPi / 3600 + 1e-4 * i * (3600 - i) / 3600;  // irregular steps
      const auto y = static_cast<float>(radius * std::sin(angle));
      const auto x = static_cast<float>(radius * std::cos(angle));
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      const double ref = atan2_deg_ref(y, x), got = acuity::detail::atan2_deg(y, x);
      // Below 1e-30 deg y / x is itself subnormal (few significant bits): absolute there.
      const double err = std::abs(got - ref) / std::max(std::abs(ref), 1e-30);
      worst = std::max(worst, err);
      ASSERT_LE(err, 1e-6) << "y " << y << " x " << x << " got " << got << " want " << ref;
    }
  }
  std::printf("atan2_deg: worst relative error %.3g\n", worst);
}

TEST(SchedulerFastMath, Atan2EdgesMatchStd) {
  const float ys[] = {0.0f, 1e-45f, 1e-38f, 1.0f, 3e38f, kInf};
  const float xs[] = {0.0f, 1e-45f, -1e-45f, 1e-38f, 1.0f, -1.0f, 3e38f, -3e38f, kInf, -kInf};
  for (float y : ys)
    for (float x : xs) {
      const float got = acuity::detail::atan2_deg(y, x);
      if (std::isinf(x) && std::isinf(y)) {
        EXPECT_TRUE(std::isnan(got)) << "two infinities give NaN (documented), x " << x;
        continue;
      }
      const double ref = atan2_deg_ref(y, x);
      EXPECT_NEAR(got, ref, 1e-6 * std::abs(ref) + 1e-37) << "y " << y << " x " << x;
    }
  EXPECT_EQ(acuity::detail::atan2_deg(0.0f, -0.0f), 0.0f);  // x = -0 counts as +0 (documented)
  EXPECT_EQ(acuity::detail::atan2_deg(1.0f, -0.0f), 90.0f);
  EXPECT_TRUE(std::isnan(acuity::detail::atan2_deg(kNaN, 1.0f)));
  EXPECT_TRUE(std::isnan(acuity::detail::atan2_deg(1.0f, kNaN)));
  EXPECT_TRUE(std::isnan(acuity::detail::atan2_deg(0.0f, kNaN)));
  EXPECT_TRUE(std::isnan(acuity::detail::atan2_deg(kNaN, kNaN)));
  EXPECT_TRUE(std::isnan(acuity::detail::atan2_deg(kInf, kNaN)));
}

TEST(SchedulerFastMath, LnWithinTwoUlpOfStdForEveryNormalFloat) {
  double worst_ulp = 0;
  // Every 257th bit pattern from the smallest normal float to the largest, and the largest.
  for (std::uint64_t bits = 0x00800000u; bits <= 0x7f7fffffu + 256u; bits += 257) {
    const float x = from_bits(static_cast<std::uint32_t>(std::min<std::uint64_t>(bits, 0x7f7fffffu)));
    const double ref = std::log(double(x));
    const float got = acuity::detail::ln_positive(x);
    const double ulp =
        std::nextafter(static_cast<float>(std::abs(ref)), kInf) - static_cast<float>(std::abs(ref));
    const double err = std::abs(got - ref) / ulp;
    worst_ulp = std::max(worst_ulp, err);
    ASSERT_LE(err, 2.0) << "x " << x << " got " << got << " want " << ref;
  }
  std::printf("ln_positive: worst error %.3g ulp\n", worst_ulp);
}

TEST(SchedulerFastMath, LnEdges) {
  EXPECT_EQ(acuity::detail::ln_positive(1.0f), 0.0f);
  EXPECT_NEAR(acuity::detail::ln_positive(std::numeric_limits<float>::min()),
              std::log(double(std::numeric_limits<float>::min())), 1e-5);
  EXPECT_NEAR(acuity::detail::ln_positive(std::numeric_limits<float>::max()),
              std::log(double(std::numeric_limits<float>::max())), 1e-5);
  // Below FLT_MIN (documented): finite, in [-88.03, -87.33], never NaN or -inf.
  for (float x : {0.0f, 1e-45f, 1e-40f, 1.1e-38f}) {
    const float got = acuity::detail::ln_positive(x);
    EXPECT_GE(got, -88.03f) << x;
    EXPECT_LE(got, -87.33f) << x;
  }
  EXPECT_NEAR(acuity::detail::ln_positive(-2.0f), std::log(2.0), 1e-6);  // ln |x| (documented)
}

// ln (sum_b (sum_t (l/c)^2)^(beta/2))^(1/beta) in double, straight from the definition.
double pooled_reference(const std::vector<float>& lost, const std::vector<float>& ct, std::uint32_t T,
                        std::uint32_t B) {
  double total = 0;
  for (std::uint32_t b = 0; b < B; ++b) {
    double energy = 0;
    for (std::uint32_t t = 0; t < T; ++t) energy += std::exp(2.0 * (double(lost[t * B + b]) - ct[t * B + b]));
    total += std::pow(energy, acuity::kBandPooling / 2.0);
  }
  return std::log(total) / acuity::kBandPooling;
}

TEST(SchedulerPooling, MatchesTheFormulaAndItsLimits) {
  using acuity::internal::pooled_excess;
  const std::uint32_t T = 8, B = 6;
  std::vector<float> lost(T * B), ct(T * B);
  std::uint32_t state = 12345;
  const auto uniform = [&] {  // [0, 1)
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (int trial = 0; trial < 200; ++trial) {
    for (std::uint32_t i = 0; i < T * B; ++i) {
      lost[i] = -8.0f * uniform();
      ct[i] = -6.0f * uniform();
    }
    EXPECT_NEAR(pooled_excess(lost.data(), ct.data(), T, B), pooled_reference(lost, ct, T, B), 1e-5) << trial;
  }
  // One channel alone is itself; N equal channels of one band are sqrt N times one; B equal bands
  // B^(1 / beta) times one.
  std::fill(lost.begin(), lost.end(), -kInf);
  std::fill(ct.begin(), ct.end(), -3.0f);
  lost[3 * B + 2] = -1.0f;
  EXPECT_FLOAT_EQ(pooled_excess(lost.data(), ct.data(), T, B), 2.0f);
  for (std::uint32_t t = 0; t < T; ++t) lost[t * B + 2] = -1.0f;
  EXPECT_NEAR(pooled_excess(lost.data(), ct.data(), T, B), 2.0 + 0.5 * std::log(double(T)), 1e-5);
  std::fill(lost.begin(), lost.end(), -kInf);
  for (std::uint32_t b = 0; b < B; ++b) lost[b] = -1.0f;
  EXPECT_NEAR(pooled_excess(lost.data(), ct.data(), T, B), 2.0 + std::log(double(B)) / acuity::kBandPooling,
              1e-5);
  // Huge and tiny ratios neither overflow nor vanish (e^(2 x) alone would).
  std::fill(lost.begin(), lost.end(), 80.0f);
  std::fill(ct.begin(), ct.end(), 0.0f);
  EXPECT_NEAR(pooled_excess(lost.data(), ct.data(), T, B), pooled_reference(lost, ct, T, B), 1e-4);
  std::fill(lost.begin(), lost.end(), -80.0f);
  EXPECT_NEAR(pooled_excess(lost.data(), ct.data(), T, B),
              -80.0 + 0.5 * std::log(double(T)) + std::log(double(B)) / acuity::kBandPooling, 1e-4);
  // Nothing lost, or every band beyond the display: -inf. A NaN, or an infinite loss: +inf.
  std::fill(lost.begin(), lost.end(), -kInf);
  EXPECT_EQ(pooled_excess(lost.data(), ct.data(), T, B), -kInf);
  std::fill(lost.begin(), lost.end(), -1.0f);
  std::fill(ct.begin(), ct.end(), kInf);
  EXPECT_EQ(pooled_excess(lost.data(), ct.data(), T, B), -kInf);
  std::fill(ct.begin(), ct.end(), 0.0f);
  lost[5] = kNaN;
  EXPECT_EQ(pooled_excess(lost.data(), ct.data(), T, B), kInf);
  lost[5] = kInf;
  EXPECT_EQ(pooled_excess(lost.data(), ct.data(), T, B), kInf);
}

}  // namespace
