// The judge's detection model (acuity/sim/detection.hpp): calibrated on Gabor patches at stelaCSF's
// threshold, and finite on the hard cases.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "acuity/models.hpp"
#include "acuity/sim/detection.hpp"

namespace {

using acuity::sim::Detection;
using acuity::sim::DetectionSettings;
using acuity::sim::Detector;
using acuity::sim::Placement;
using acuity::spectra::Image;

constexpr double kPi = 3.14159265358979323846, kDeg = 180.0 / kPi;
constexpr std::uint32_t kPixels = 128;
constexpr float kBackground = 0.5f;  // x white 100 cd/m^2 = 50 cd/m^2
constexpr double kLuminance = 50.0;

Image flat(float value, std::uint32_t n = kPixels) {
  Image im;
  im.width = im.height = n;
  im.pixels.assign(std::size_t(n) * n, value);
  return im;
}

// A Gabor patch filling the image: window D = the image's side, sigma = D / 6, `cycles` across D, its
// frequency vector at `angle` [deg] from +x towards up.
Image gabor(double cycles, double contrast, double angle = 0, std::uint32_t n = kPixels) {
  Image im = flat(kBackground, n);
  const double sigma = 1.0 / 6, a = angle / kDeg;
  for (std::uint32_t y = 0; y < n; ++y)
    for (std::uint32_t x = 0; x < n; ++x) {
      const double u = (x + 0.5) / n - 0.5, v = 0.5 - (y + 0.5) / n;  // [diameters], v up
      const double envelope = std::exp(-(u * u + v * v) / (2 * sigma * sigma));
      const double carrier = std::cos(2 * kPi * cycles * (u * std::cos(a) + v * std::sin(a)));
      im.pixels[std::size_t(y) * n + x] = float(kBackground * (1 + contrast * envelope * carrier));
    }
  return im;
}

// The image D degrees across, its centre `e` degrees from the gaze (straight ahead) towards
// `meridian` (0: to the right, horizontal; 90: up, vertical), 1 m away.
Placement placement(double size_deg, double e, double meridian = 0) {
  Placement p;
  const double er = e / kDeg, mr = meridian / kDeg;
  const glm::dvec3 dir(std::sin(er) * std::cos(mr), std::sin(er) * std::sin(mr), -std::cos(er));
  p.centre = dir;
  p.radius = std::tan(0.5 * size_deg / kDeg);
  p.up = glm::normalize(glm::dvec3(0, 1, 0) - dir.y * dir);
  p.right = glm::normalize(glm::cross(dir, p.up));  // the renderer's -direction x up (direction = -dir)
  p.gazes = {glm::dvec3(0, 0, -1)};
  return p;
}

// stelaCSF's threshold contrast for the patch: area pi sigma^2, its centre's eccentricity, with two
// eyes the horizontal meridian is nasal for one of them (vis_field 180), the vertical takes 90.
// A drift of v deg/s across the bars is a temporal frequency f v.
double threshold(double f, double size_deg, double e, double meridian = 0, double v = 0) {
  const double sigma = size_deg / 6;
  return 1.0 / acuity::stela_csf(f, f * v, kLuminance, kPi * sigma * sigma, e, 180.0 - meridian);
}

struct Condition {
  double f, cycles, e, meridian, v = 0;
};

// f 0.5-16 cpd with 4 (on a band), 5.66 (between two bands) or 8 cycles across the window,
// eccentricity 0-20 deg, horizontal and vertical meridians, still or drifting 3 deg/s across the bars.
std::vector<Condition> conditions() {
  std::vector<Condition> out;
  for (double v : {0.0, 3.0})
    for (double f : {0.5, 1.0, 2.0, 4.0, 8.0, 16.0})
      for (double cycles : {4.0, 5.657, 8.0})
        for (double e : {0.0, 5.0, 10.0, 20.0})
          for (double meridian : {0.0, 90.0}) {
            if (e == 0 && meridian != 0) continue;
            if (threshold(f, cycles / f, e, meridian, v) > 0.5) continue;  // no contrast shows it
            out.push_back({f, cycles, e, meridian, v});
          }
  return out;
}

double score_at(const Condition& c, double times_threshold, const Detector& d) {
  const double size = c.cycles / c.f;
  const double contrast = times_threshold * threshold(c.f, size, c.e, c.meridian, c.v);
  Placement p = placement(size, c.e, c.meridian);
  p.retinal_velocity = {c.v, 0.0};  // across the bars (the carrier's frequency vector along +x)
  return d.detect(gabor(c.cycles, contrast), flat(kBackground), p).score;
}

TEST(Detection, GaborPatchesAtStelaThresholdReadJustDetectable) {
  const Detector d(kPixels, DetectionSettings{});
  const std::vector<Condition> all = conditions();
  ASSERT_GE(all.size(), 120u);
  const std::size_t step = std::getenv("ACUITY_QUICK_TESTS") ? 5 : 1;  // the sanitizer run checks fewer
  for (std::size_t i = 0; i < all.size(); i += step) {
    const Condition& c = all[i];
    const double s = score_at(c, 1.0, d);
    EXPECT_GE(s, 0.7) << c.f << " cpd, " << c.cycles << " cycles, e " << c.e << ", meridian " << c.meridian
                      << ", v " << c.v;
    EXPECT_LE(s, 1.4) << c.f << " cpd, " << c.cycles << " cycles, e " << c.e << ", meridian " << c.meridian
                      << ", v " << c.v;
  }
}

TEST(Detection, FarBelowThresholdInvisibleFarAboveVisible) {
  const Detector d(kPixels, DetectionSettings{});
  for (const Condition& c : {Condition{1, 4, 0, 0}, Condition{8, 5.657, 10, 0}, Condition{2, 8, 20, 90},
                             Condition{1, 4, 0, 0, 3}}) {
    EXPECT_LT(score_at(c, 0.25, d), 0.5) << c.f;
    EXPECT_GT(score_at(c, 4.0, d), 2.0) << c.f;
  }
}

TEST(Detection, OrientationAndEccentricityAndMotionMatter) {
  const Detector d(kPixels, DetectionSettings{});
  const Image ref = flat(kBackground);
  const Image patch = gabor(8, 0.05, 0);
  const double size = 8.0 / 4;  // 4 cpd
  const double fovea = d.detect(patch, ref, placement(size, 0)).score;
  EXPECT_GT(fovea, d.detect(patch, ref, placement(size, 10)).score);
  EXPECT_NEAR(fovea, d.detect(gabor(8, 0.05, 33), ref, placement(size, 0)).score, 0.15 * fovea);
  // Across the bars (the carrier's frequency vector along +x) a drift sets a temporal frequency; along
  // them none: 8 cpd at 10 deg/s (80 Hz) is far less visible than along the bars.
  const Image fine = gabor(16, 0.05, 0);
  Placement across = placement(size, 0), along = placement(size, 0);
  across.retinal_velocity = {10, 0};
  along.retinal_velocity = {0, 10};
  const double still = d.detect(fine, ref, placement(size, 0)).score;
  EXPECT_LT(d.detect(fine, ref, across).score, 0.3 * still);
  EXPECT_NEAR(d.detect(fine, ref, along).score, still, 0.2 * still);
  // Beyond the display's Nyquist frequency nothing is seen.
  DetectionSettings coarse;
  coarse.nyquist_cpd = 3;  // the bands of 1 and 2 cpd only: 8 cpd lies beyond their windows (but for
                           // the leak of the window cut at the image's edge)
  EXPECT_LT(Detector(kPixels, coarse).detect(fine, ref, placement(size, 0)).score, 1e-3 * still);
}

TEST(Detection, HardCasesStayFinite) {
  const Detector d(kPixels, DetectionSettings{});
  const Image grey = flat(kBackground), black = flat(0.0f), white = flat(1.0f);
  const Placement p = placement(4, 0);
  // No difference: 0, on grey and on black (the local mean floored there).
  EXPECT_EQ(d.detect(grey, grey, p).score, 0.0);
  EXPECT_EQ(d.detect(black, black, p).score, 0.0);
  EXPECT_EQ(d.detect(gabor(4, 0.0), grey, p).score, 0.0);
  // The largest contrasts: finite, visible.
  const double huge = d.detect(white, black, p).score;
  EXPECT_TRUE(std::isfinite(huge));
  const double full = d.detect(gabor(8, 1.0), grey, p).score;
  EXPECT_TRUE(std::isfinite(full) && full > 10) << full;
  // A tiny object: a 2 x 2 px speck of a 0.05 deg image; finite and invisible far in the periphery.
  Image speck = grey;
  for (std::uint32_t y = 63; y < 65; ++y)
    for (std::uint32_t x = 63; x < 65; ++x) speck.pixels[std::size_t(y) * kPixels + x] = 1.0f;
  const double tiny_fovea = d.detect(speck, grey, placement(0.05, 0)).score;
  const double tiny_far = d.detect(speck, grey, placement(0.05, 40)).score;
  EXPECT_TRUE(std::isfinite(tiny_fovea) && std::isfinite(tiny_far));
  EXPECT_GT(tiny_fovea, tiny_far);
  // No gaze and no disc (every point looked at: more visible than with the gaze on the centre only),
  // a gaze along the head's up (no meridian defined), a huge object with the gaze on its centre
  // pixel, a very fast one.
  Placement none = p;
  none.gazes.clear();
  EXPECT_GT(d.detect(gabor(8, 0.05), grey, none).score, d.detect(gabor(8, 0.05), grey, p).score);
  Placement upward = p;
  upward.gazes = {glm::dvec3(0, 1, 0)};
  upward.head_up = {0, 1, 0};
  EXPECT_TRUE(std::isfinite(d.detect(gabor(8, 0.05), grey, upward).score));
  const Detection big = d.detect(gabor(8, 0.05), grey, placement(120, 0));
  EXPECT_TRUE(std::isfinite(big.score));
  Placement fast = p;
  fast.retinal_velocity = {1000, 300};
  EXPECT_TRUE(std::isfinite(d.detect(gabor(8, 0.5), grey, fast).score));
  for (double b : big.bands) EXPECT_TRUE(std::isfinite(b) && b >= 0);
  // No gaze within a disc (the scheduler's no-gaze radius about the view centre): a point's gaze is
  // the disc's nearest point. Radius 0: the centre, exactly the gaze there; a disc reaching past the
  // patch: every point looked at; between: between.
  const Placement off = placement(4, 12);
  Placement disc = off;
  disc.gazes.clear();
  const Image faint = gabor(8, 0.05);
  const double gazed = d.detect(faint, grey, off).score;
  double previous = 0;
  for (const double radius : {0.0, 6.0, 11.0, 20.0}) {
    disc.no_gaze_radius_deg = radius;
    const double score = d.detect(faint, grey, disc).score;
    if (radius == 0) { EXPECT_DOUBLE_EQ(score, gazed); }
    if (radius == 20) {  // the default radius (180): every point looked at
      Placement anywhere = off;
      anywhere.gazes.clear();
      EXPECT_DOUBLE_EQ(score, d.detect(faint, grey, anywhere).score);
    }
    EXPECT_GT(score, previous) << radius;
    previous = score;
  }
  // Bad geometry is refused, not scored.
  Placement behind = p;
  behind.radius = 0;
  EXPECT_THROW(d.detect(grey, grey, behind), std::invalid_argument);
  EXPECT_THROW(Detector(100, DetectionSettings{}), std::invalid_argument);
}

// The calibration table (not a check: GaborPatchesAtStelaThresholdReadJustDetectable is):
//   build/tests/test_detection --gtest_also_run_disabled_tests --gtest_filter='*Table*'
TEST(Detection, DISABLED_Table) {
  const Detector d(kPixels, DetectionSettings{});
  std::printf(
      "| f [cpd] | cycles in the window | e [deg] | meridian | drift [deg/s] | score at threshold |\n"
      "|---|---|---|---|---|---|\n");
  double lo = 1e9, hi = 0, log_sum = 0;
  int count = 0;
  for (const Condition& c : conditions()) {
    const double s = score_at(c, 1.0, d);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    log_sum += std::log(s);
    ++count;
    std::printf("| %g | %.3g%s | %g | %s | %g | %.2f |\n", c.f, c.cycles,
                c.cycles == 5.657 ? " (between bands)" : "", c.e, c.meridian == 0 ? "horizontal" : "vertical",
                c.v, s);
  }
  std::printf("\n%d conditions: scores %.2f-%.2f, geometric mean %.2f\n", count, lo, hi,
              std::exp(log_sum / count));
}

}  // namespace
