// Guenter et al. 2012 eccentricity layers: the paper's display numbers, and the dynamic programme
// against the paper's plain brute force over every ordered choice of radii.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "acuity/foveation.hpp"

using namespace acuity;

namespace {
// Eq. 2-5 written out directly: total work for radii e[0..n-2] (degrees).
double work(const double* e, int n, double W, double V, double D, double aspect, double m, double w0,
            double ws) {
  constexpr double deg = 3.14159265358979323846 / 180;
  double total = 0, s = 1;
  for (int i = 0; i < n - 1; ++i) {
    const double d = 2 * (D / s) * std::tan(e[i] * deg) * V / W;
    total += d * d;
    s = std::max(1.0, (m * e[i] + w0) / ws);
  }
  return total + aspect * (D / s) * (D / s);
}

// Brute force over all e_1 < ... < e_(n-1) on the same grid guenter_layers() uses.
double brute_force(int n, int grid, double W, double V, double D, double aspect, double m, double w0) {
  const double e_star = guenter_display_radius(W, V), ws = guenter_display_sharpness(W, V, D);
  double best = std::numeric_limits<double>::infinity();
  double e[8];
  std::function<void(int, int)> rec = [&](int i, int from) {
    if (i == n - 1) {
      best = std::min(best, work(e, n, W, V, D, aspect, m, w0, ws));
      return;
    }
    for (int j = from; j < grid; ++j) {
      e[i] = e_star * j / grid;
      rec(i + 1, j + 1);
    }
  };
  rec(0, 1);
  return best;
}
}  // namespace

TEST(Guenter, PaperDisplay) {
  // V = 59 cm, W = 51 cm, D = 1920: e* = 23.4 deg (Eq. 6), w* = 0.0516 deg (Eq. 7).
  EXPECT_NEAR(guenter_display_radius(51, 59), 23.4, 0.05);
  EXPECT_NEAR(guenter_display_sharpness(51, 59, 1920), 0.0516, 5e-5);
  const GuenterLayers g = guenter_layers(51, 59, 1920, 9.0 / 16, 0.022, 3);
  ASSERT_EQ(g.n_layers, 3);
  EXPECT_NEAR(g.e_star, 23.4, 0.05);
  EXPECT_NEAR(g.omega_star, 0.0516, 5e-5);
  EXPECT_DOUBLE_EQ(g.display_work, 9.0 / 16 * 1920 * 1920);
  EXPECT_GT(g.speedup, 1.0);
}

TEST(Guenter, DynamicProgrammeEqualsBruteForce) {
  struct Case {
    double W, V, D, aspect, m;
    int n, grid;
  };
  for (const Case c :
       {Case{51, 59, 1920, 9.0 / 16, 0.022, 3, 120}, Case{51, 59, 1920, 9.0 / 16, 0.0275, 4, 40},
        Case{100, 40, 7000, 0.75, 0.022, 3, 150}, Case{100, 40, 7000, 0.75, 0.022, 2, 300}}) {
    const GuenterLayers g = guenter_layers(c.W, c.V, c.D, c.aspect, c.m, c.n, 1.0 / 48, c.grid);
    ASSERT_EQ(g.n_layers, c.n);
    const double expected = brute_force(c.n, c.grid, c.W, c.V, c.D, c.aspect, c.m, 1.0 / 48);
    EXPECT_NEAR(g.work / expected, 1.0, 1e-12);
    EXPECT_NEAR(g.work, work(g.radius, c.n, c.W, c.V, c.D, c.aspect, c.m, 1.0 / 48, g.omega_star),
                1e-6 * g.work);
    for (int i = 1; i < c.n; ++i) {
      EXPECT_GT(g.radius[i], g.radius[i - 1]);
      EXPECT_GE(g.sampling[i], g.sampling[i - 1]);
    }
    EXPECT_EQ(g.sampling[0], 1.0);
  }
}

TEST(Guenter, MoreLayersNeverCostMore) {
  double previous = std::numeric_limits<double>::infinity();
  for (int n = 1; n <= 5; ++n) {
    const GuenterLayers g = guenter_layers(100, 40, 7000, 0.75, 0.022, n, 1.0 / 48, 400);
    EXPECT_LE(g.work, previous * (1 + 1e-12));
    previous = g.work;
  }
}

TEST(Guenter, InvalidInput) {
  EXPECT_EQ(guenter_layers(51, 59, 1920, 0.5625, 0.022, 0).n_layers, 0);
  EXPECT_EQ(guenter_layers(51, 59, 1920, 0.5625, 0.022, kMaxGuenterLayers + 1).n_layers, 0);
  EXPECT_EQ(guenter_layers(-1, 59, 1920, 0.5625, 0.022, 3).n_layers, 0);
  EXPECT_EQ(guenter_layers(51, std::nan(""), 1920, 0.5625, 0.022, 3).n_layers, 0);
  EXPECT_TRUE(std::isnan(guenter_layers(51, 0, 1920, 0.5625, 0.022, 3).speedup));
}

TEST(Guenter, HundredfoldAtSeventyDegrees) {
  // Guenter et al. abstract and Fig. 12: about 100x at a 70 deg field of view when the display's
  // sharpness equals foveal acuity (w* = w0), aspect 3/4; four layers at slope A = 0.0275.
  constexpr double deg = 3.14159265358979323846 / 180;
  const double e_star = 35.0, width = 1.0, distance = width / (2 * std::tan(e_star * deg));
  const double pixels = 4 * std::tan(e_star * deg) / std::tan(deg / 48);  // Eq. 9
  const GuenterLayers g = guenter_layers(width, distance, pixels, 0.75, 0.0275, 4);
  EXPECT_NEAR(g.omega_star, 1.0 / 48, 1e-9);
  EXPECT_NEAR(g.speedup, 100.0, 10.0);
}
