// The scheduler's branch-free atan2 and log (scheduler/src/fast_math.hpp) against std:: in double
// precision over their whole domain: every binade, zeros, subnormals, infinities, NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "fast_math.hpp"

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

}  // namespace
