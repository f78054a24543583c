// The foveation planner (acuity/foveation_plan.hpp): map geometry, full rate around the gaze,
// monotone along every ray from the gaze (dense check), no gaze, two eyes, invalid eyes, one tile
// against the formula computed here independently, every tile never coarser than the exact rule,
// no allocation per frame, and the savings the issue asks for.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

#include "acuity/foveation_plan.hpp"

#include "allocation_counter.hpp"  // the no-allocation test counts with it

using namespace acuity;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = 180.0 / kPi;

Eye make_eye(std::uint32_t w, std::uint32_t h, float half_h_deg, float half_v_deg) {
  Eye eye;
  eye.fov_deg[0] = -half_h_deg;
  eye.fov_deg[1] = half_h_deg;
  eye.fov_deg[2] = half_v_deg;
  eye.fov_deg[3] = -half_v_deg;
  eye.viewport[0] = w;
  eye.viewport[1] = h;
  return eye;
}

Gaze gaze_at(double yaw_deg, double pitch_deg) {  // yaw to the right, pitch up
  Gaze g;
  g.valid = true;
  const double y = yaw_deg / kDeg, p = pitch_deg / kDeg;
  g.direction[0] = static_cast<float>(std::sin(y) * std::cos(p));
  g.direction[1] = static_cast<float>(std::sin(p));
  g.direction[2] = static_cast<float>(-std::cos(y) * std::cos(p));
  return g;
}

struct Plan {
  std::vector<std::uint8_t> rate;
  std::vector<float> bias;
  FoveationMaps maps;
  FoveationStatus status = FoveationStatus::InvalidArgument;
  std::uint8_t rx(std::uint32_t c, std::uint32_t r) const {
    return rate[2 * (std::size_t(r) * maps.cols + c)];
  }
  std::uint8_t ry(std::uint32_t c, std::uint32_t r) const {
    return rate[2 * (std::size_t(r) * maps.cols + c) + 1];
  }
  float b(std::uint32_t c, std::uint32_t r) const { return bias[std::size_t(r) * maps.cols + c]; }
  double saved() const { return 1.0 - maps.shaded / maps.pixels; }
};

const FoveationPlanner& planner_for(const FoveationConfig& config = {}) {
  static std::vector<std::unique_ptr<FoveationPlanner>> cache;  // one per distinct call site config
  auto p = std::make_unique<FoveationPlanner>();
  EXPECT_EQ(init_foveation_planner(config, p.get()), FoveationStatus::Ok);
  cache.push_back(std::move(p));
  return *cache.back();
}

Plan plan(const FoveationPlanner& planner, const Eye& eye, const Gaze& gaze, std::uint32_t tile = 16) {
  Plan p;
  std::uint32_t cols = 0, rows = 0;
  foveation_map_size(eye, tile, &cols, &rows);
  p.rate.assign(2 * std::size_t(cols) * rows, 0xee);
  p.bias.assign(std::size_t(cols) * rows, -1.0f);
  p.maps.tile_px = tile;
  p.maps.capacity = cols * rows;
  p.maps.shading_rate = p.rate.data();
  p.maps.mip_bias = p.bias.data();
  p.status = plan_foveation(planner, eye, gaze, &p.maps);
  return p;
}

// The eye-space direction through pixel (x, y) (x right, y down from the top-left corner).
void pixel_direction(const Eye& eye, double x, double y, double d[3]) {
  const double tl = std::tan(eye.fov_deg[0] / kDeg), tr = std::tan(eye.fov_deg[1] / kDeg);
  const double tu = std::tan(eye.fov_deg[2] / kDeg), td = std::tan(eye.fov_deg[3] / kDeg);
  d[0] = tl + x / eye.viewport[0] * (tr - tl);
  d[1] = tu - y / eye.viewport[1] * (tu - td);
  d[2] = -1;
  const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + 1);
  for (int k = 0; k < 3; ++k) d[k] /= n;
}

double angle_deg(const double a[3], const double b[3]) {
  const double c = std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0);
  return std::acos(c) * kDeg;
}

void unit_gaze(const Gaze& g, double o[3]) {
  const double n =
      std::sqrt(double(g.direction[0]) * g.direction[0] + double(g.direction[1]) * g.direction[1] +
                double(g.direction[2]) * g.direction[2]);
  for (int k = 0; k < 3; ++k) o[k] = g.direction[k] / n;
}

// The exact rule, evaluated here on a dense sampling of one tile: the least angle to `o` and the
// least pixels per degree along x and y (numerically, from neighbouring pixel directions).
struct TileTruth {
  double min_angle = 1e9, ppd_x = 1e9, ppd_y = 1e9;
};
TileTruth tile_truth(const Eye& eye, const double o[3], std::uint32_t c, std::uint32_t r,
                     std::uint32_t tile) {
  TileTruth t;
  const double x0 = double(c) * tile, x1 = std::min<double>(double(c + 1) * tile, eye.viewport[0]);
  const double y0 = double(r) * tile, y1 = std::min<double>(double(r + 1) * tile, eye.viewport[1]);
  const int n = 16;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = x0 + (x1 - x0) * i / n, y = y0 + (y1 - y0) * j / n;
      double d[3], dx[3], dy[3];
      pixel_direction(eye, x, y, d);
      pixel_direction(eye, x + 1e-3, y, dx);
      pixel_direction(eye, x, y + 1e-3, dy);
      t.min_angle = std::min(t.min_angle, angle_deg(d, o));
      t.ppd_x = std::min(t.ppd_x, 1e-3 / angle_deg(d, dx));
      t.ppd_y = std::min(t.ppd_y, 1e-3 / angle_deg(d, dy));
    }
  return t;
}

int coarsest_rate(double ppd, double nyquist) {
  return ppd >= 4 * nyquist ? 4 : (ppd >= 2 * nyquist ? 2 : 1);
}
}  // namespace

TEST(FoveationPlan, MapSizeIsCeilPixelsOverTile) {
  for (std::uint32_t tile : {8u, 16u, 32u})
    for (std::uint32_t w : {1u, 7u, 8u, 1000u, 1920u, 2000u, 3840u}) {
      const Eye eye = make_eye(w, 2160, 45, 30);
      std::uint32_t cols = 0, rows = 0;
      ASSERT_TRUE(foveation_map_size(eye, tile, &cols, &rows));
      EXPECT_EQ(cols, (w + tile - 1) / tile);
      EXPECT_EQ(rows, (2160 + tile - 1) / tile);
      const Plan p = plan(planner_for(), eye, gaze_at(3, -2), tile);
      EXPECT_EQ(p.maps.cols, cols);
      EXPECT_EQ(p.maps.rows, rows);
      for (std::uint8_t v : p.rate) ASSERT_TRUE(v == 1 || v == 2 || v == 4);
      for (float v : p.bias) ASSERT_TRUE(v >= 0 && std::isfinite(v));
    }
  std::uint32_t cols = 7, rows = 7;
  EXPECT_FALSE(foveation_map_size(make_eye(1920, 1080, 45, 30), 12, &cols, &rows));
  EXPECT_EQ(cols, 0u);
  EXPECT_FALSE(foveation_map_size(make_eye(0, 1080, 45, 30), 16, &cols, &rows));
  EXPECT_FALSE(foveation_map_size(make_eye(100000, 1080, 45, 30), 8, &cols, &rows));  // > kMaxFoveationTiles
}

TEST(FoveationPlan, FullRateAtTheGazeAndWithinFovealRadiusPlusUncertainty) {
  FoveationConfig config;
  config.gaze_uncertainty_deg = 2.0f;
  config.foveal_radius_deg = 3.0f;
  const FoveationPlanner& planner = planner_for(config);
  // A sharp display (about 60 px/deg at the centre), where the model alone would coarsen early.
  const Eye eye = make_eye(3840, 2160, 32, 19);
  for (const Gaze& g : {gaze_at(0, 0), gaze_at(15, 5), gaze_at(-25, -12)}) {
    const Plan p = plan(planner, eye, g);
    ASSERT_EQ(p.status, FoveationStatus::Ok);
    double o[3];
    unit_gaze(g, o);
    int checked = 0;
    for (std::uint32_t r = 0; r < p.maps.rows; ++r)
      for (std::uint32_t c = 0; c < p.maps.cols; ++c) {
        double centre[3];
        pixel_direction(eye, c * 16.0 + 8, r * 16.0 + 8, centre);
        if (angle_deg(centre, o) > 10) continue;  // far outside the disc: skip the dense sampling
        const TileTruth t = tile_truth(eye, o, c, r, 16);
        if (t.min_angle <= config.foveal_radius_deg + config.gaze_uncertainty_deg) {
          ++checked;
          EXPECT_EQ(p.rx(c, r), 1) << c << "," << r;
          EXPECT_EQ(p.ry(c, r), 1) << c << "," << r;
          EXPECT_EQ(p.b(c, r), 0.0f) << c << "," << r;
        }
      }
    EXPECT_GT(checked, 100);
    // The model does coarsen this display somewhere.
    EXPECT_GT(p.saved(), 0.3);
    // The tile under the gaze point.
    const auto gc = static_cast<std::uint32_t>(p.maps.origin_px[0] / 16),
               gr = static_cast<std::uint32_t>(p.maps.origin_px[1] / 16);
    EXPECT_EQ(p.rx(gc, gr), 1);
  }
}

// Dense rays from the origin: along each, the tile sequence's rates and bias never fall.
void expect_monotone_along_rays(const Plan& p, std::uint32_t tile, const char* what) {
  const double ox = p.maps.origin_px[0], oy = p.maps.origin_px[1];
  const double W = double(p.maps.cols) * tile, H = double(p.maps.rows) * tile;
  int violations = 0;
  for (int k = 0; k < 2048; ++k) {
    const double a = 2 * kPi * (k + 0.37) / 2048, dx = std::cos(a), dy = std::sin(a);
    int prev_x = 0, prev_y = 0;
    float prev_b = -1;
    for (double s = 0; s < 1.5 * (W + H); s += 0.25) {
      const double x = ox + s * dx, y = oy + s * dy;
      if (x < 0 || y < 0 || x >= W || y >= H) {
        if (prev_b >= 0) break;  // left the image
        continue;                // not yet entered (an origin off the image)
      }
      const auto c = static_cast<std::uint32_t>(x / tile), r = static_cast<std::uint32_t>(y / tile);
      const int rx = p.rx(c, r), ry = p.ry(c, r);
      const float b = p.b(c, r);
      if (rx < prev_x || ry < prev_y || b < prev_b) ++violations;
      prev_x = rx;
      prev_y = ry;
      prev_b = b;
    }
  }
  EXPECT_EQ(violations, 0) << what;
}

TEST(FoveationPlan, NeverFinerFartherOutAlongAnyRay) {
  const FoveationPlanner& planner = planner_for();
  struct Case {
    Eye eye;
    Gaze gaze;
    const char* what;
  };
  Eye rotating = make_eye(2000, 2000, 50, 50);
  rotating.angular_velocity[1] = 150;
  Gaze none;
  const Case cases[] = {
      {make_eye(2000, 2000, 50, 50), gaze_at(0, 0), "centred"},
      {make_eye(2000, 2000, 50, 50), gaze_at(30, 20), "off-centre"},
      {make_eye(2000, 2000, 50, 50), gaze_at(-47, -44), "near a corner"},
      {make_eye(2000, 2000, 50, 50), gaze_at(70, 0), "off the image"},
      {make_eye(3840, 2160, 45, 29), gaze_at(-20, 8), "4K"},
      {make_eye(1920, 1920, 45, 45), none, "no gaze"},
      {rotating, gaze_at(10, -10), "head rotating"},
  };
  FoveationConfig head_turns;
  head_turns.head_rotation = true;
  for (const Case& c : cases) {
    const Plan p = plan(planner, c.eye, c.gaze);
    expect_monotone_along_rays(p, 16, c.what);
    expect_monotone_along_rays(plan(planner_for(head_turns), c.eye, c.gaze), 16, c.what);
  }
  // Also at the other tile sizes, and with the gaze exactly on a tile corner.
  for (std::uint32_t tile : {8u, 32u})
    expect_monotone_along_rays(plan(planner, make_eye(2000, 2000, 50, 50), gaze_at(12, 7), tile), tile,
                               "tile");
}

TEST(FoveationPlan, NoGazeMeansFullRateOverTheNoGazeDisc) {
  FoveationConfig config;
  config.no_gaze_radius_deg = 20.0f;
  const FoveationPlanner& planner = planner_for(config);
  const Eye eye = make_eye(2000, 2000, 50, 50);
  Gaze invalid = gaze_at(30, 0);
  invalid.valid = false;
  Gaze unsure = gaze_at(30, 0);
  unsure.confidence = 0.2f;
  Gaze nan = gaze_at(30, 0);
  nan.direction[1] = std::nanf("");
  Gaze zero = gaze_at(30, 0);
  zero.direction[0] = zero.direction[1] = zero.direction[2] = 0;
  const double centre[3] = {0, 0, -1};
  std::vector<std::uint8_t> first;
  for (const Gaze& g : {invalid, unsure, nan, zero}) {
    const Plan p = plan(planner, eye, g);
    EXPECT_EQ(p.status, FoveationStatus::NoGaze);
    EXPECT_FLOAT_EQ(p.maps.origin_px[0], 1000.0f);
    int inside = 0;
    for (std::uint32_t r = 0; r < p.maps.rows; r += 2)
      for (std::uint32_t c = 0; c < p.maps.cols; c += 2)
        if (tile_truth(eye, centre, c, r, 16).min_angle <=
            config.no_gaze_radius_deg + config.foveal_radius_deg) {
          ++inside;
          EXPECT_EQ(p.rx(c, r) * p.ry(c, r), 1);
          EXPECT_EQ(p.b(c, r), 0.0f);
        }
    EXPECT_GT(inside, 200);
    if (first.empty()) first = p.rate;
    EXPECT_EQ(p.rate, first);  // every kind of missing gaze plans the same
  }
  // A usable gaze saves more than none.
  EXPECT_GT(plan(planner, eye, gaze_at(0, 0)).saved(), plan(planner, eye, invalid).saved());
}

TEST(FoveationPlan, TwoEyesEachGetTheirOwnMap) {
  const FoveationPlanner& planner = planner_for();
  // Canted, asymmetric frusta mirrored about the nose; widths a multiple of the tile.
  Eye left = make_eye(1920, 1920, 50, 45), right = make_eye(1920, 1920, 50, 45);
  left.fov_deg[0] = -55;
  left.fov_deg[1] = 40;
  right.fov_deg[0] = -40;
  right.fov_deg[1] = 55;
  const Gaze gl = gaze_at(8, 5), gr = gaze_at(-8, 5);
  const Plan pl = plan(planner, left, gl), pr = plan(planner, right, gr);
  ASSERT_EQ(pl.maps.cols, pr.maps.cols);
  EXPECT_NE(pl.rate, pr.rate);
  for (std::uint32_t r = 0; r < pl.maps.rows; ++r)
    for (std::uint32_t c = 0; c < pl.maps.cols; ++c) {
      const std::uint32_t m = pl.maps.cols - 1 - c;
      ASSERT_EQ(pl.rx(c, r), pr.rx(m, r)) << c << "," << r;
      ASSERT_EQ(pl.ry(c, r), pr.ry(m, r)) << c << "," << r;
      ASSERT_NEAR(pl.b(c, r), pr.b(m, r), 0.02f) << c << "," << r;
    }
  // The same eye with the two gazes: different maps, each centred on its own gaze.
  const Plan a = plan(planner, left, gl), b = plan(planner, left, gr);
  EXPECT_NE(a.rate, b.rate);
  EXPECT_GT(a.maps.origin_px[0], b.maps.origin_px[0]);
}

TEST(FoveationPlan, InvalidEyesGetFullRateAndAStatus) {
  const FoveationPlanner& planner = planner_for();
  const float nan = std::nanf("");
  std::vector<Eye> bad(7, make_eye(640, 480, 40, 30));
  bad[0].fov_deg[1] = nan;
  bad[1].position[2] = std::nan("");
  bad[2].orientation[3] = 0;  // not a unit quaternion
  bad[3].fov_deg[0] = 40;     // left == right
  bad[4].angular_velocity[0] = INFINITY;
  bad[5].fov_deg[2] = 95;  // beyond 90 deg
  bad[6].velocity[1] = nan;
  for (const Eye& eye : bad) {
    const Plan p = plan(planner, eye, gaze_at(0, 0));
    EXPECT_EQ(p.status, FoveationStatus::InvalidEye);
    for (std::uint8_t v : p.rate) ASSERT_EQ(v, 1);
    for (float v : p.bias) ASSERT_EQ(v, 0.0f);
    EXPECT_EQ(p.maps.shaded, p.maps.pixels);
  }
  // Buffers too small, a bad tile size, or no buffers: nothing written.
  const Eye eye = make_eye(640, 480, 40, 30);
  Plan p = plan(planner, eye, gaze_at(0, 0));
  std::fill(p.rate.begin(), p.rate.end(), std::uint8_t(0xee));
  p.maps.capacity -= 1;
  EXPECT_EQ(plan_foveation(planner, eye, gaze_at(0, 0), &p.maps), FoveationStatus::InvalidArgument);
  p.maps.capacity += 1;
  p.maps.tile_px = 12;
  EXPECT_EQ(plan_foveation(planner, eye, gaze_at(0, 0), &p.maps), FoveationStatus::InvalidArgument);
  p.maps.tile_px = 16;
  p.maps.mip_bias = nullptr;
  EXPECT_EQ(plan_foveation(planner, eye, gaze_at(0, 0), &p.maps), FoveationStatus::InvalidArgument);
  for (std::uint8_t v : p.rate) ASSERT_EQ(v, 0xee);
  EXPECT_EQ(plan_foveation(planner, eye, gaze_at(0, 0), nullptr), FoveationStatus::InvalidArgument);
  // A planner never initialised: full rate and InvalidArgument.
  auto cold = std::make_unique<FoveationPlanner>();
  const Plan q = plan(*cold, eye, gaze_at(0, 0));
  EXPECT_EQ(q.status, FoveationStatus::InvalidArgument);
  for (std::uint8_t v : q.rate) ASSERT_EQ(v, 1);
  // Bad configurations are refused.
  for (int k = 0; k < 4; ++k) {
    FoveationConfig c;
    if (k == 0) c.quality = 0;
    if (k == 1) c.max_rate = 3;
    if (k == 2) c.gaze_uncertainty_deg = nan;
    if (k == 3) c.foveal_radius_deg = -1;
    EXPECT_EQ(init_foveation_planner(c, cold.get()), FoveationStatus::InvalidArgument);
    EXPECT_FALSE(cold->ready);
  }
}

// One tile against the rule written out here: Geisler-Perry's closed-form cutoff at contrast 1/q,
// the pinhole's pixels per degree, the tile's eccentricity bound (centre angle less half the tile's
// diagonal at the on-axis 1/f radians per pixel) and Nyquist.
TEST(FoveationPlan, OneTileMatchesTheFormula) {
  FoveationConfig config;
  config.model = ThresholdModel::GeislerPerry;
  config.quality = 0.8f;
  const FoveationPlanner& planner = planner_for(config);
  const Eye eye = make_eye(2000, 2000, 50, 50);
  const Gaze gaze = gaze_at(0, 0);
  const Plan p = plan(planner, eye, gaze);
  const double f = 1000.0 / std::tan(50 / kDeg);  // focal length [px]
  const ModelParams mp;
  int compared = 0;
  for (std::uint32_t c : {70u, 80u, 95u, 110u, 124u}) {
    const std::uint32_t r = 62;  // the row through the centre: tangent range [-0.008, 0]
    const double u0 = (c * 16.0 - 1000) / f, u1 = ((c + 1) * 16.0 - 1000) / f;
    const double uc = 0.5 * (u0 + u1), vc = (1000 - 63 * 16.0 + 8) / f;
    const double theta = std::atan(std::sqrt(uc * uc + vc * vc)) * kDeg;
    const double rho = 16 * std::sqrt(2.0) / 2 / f * kDeg;
    const double e = theta - rho - config.gaze_uncertainty_deg;
    const double cutoff =
        mp.e2 * std::log((1.0 / config.quality) / mp.ct0) / (mp.alpha * (std::max(e, 0.0) + mp.e2));
    // ppd along x is least at the tile's nearest u and v = 0 (on this row): f (1 + u^2) pi / 180;
    // along y, f sqrt(1 + u^2) at v = 0 ... at the nearest u.
    const double ppd_x = f * (1 + u0 * u0) / kDeg, ppd_y = f * std::sqrt(1 + u0 * u0) / kDeg;
    const double nyquist = 2 * cutoff;
    const double ratio_x = ppd_x / nyquist, ratio_y = ppd_y / nyquist;
    const auto near_step = [](double ratio) {
      return std::abs(ratio / 2 - 1) < 0.1 || std::abs(ratio / 4 - 1) < 0.1;
    };
    const double bias = std::max(0.0, std::log2(std::min(ppd_x, ppd_y) / nyquist));
    // The planner's tables err low by at most one 0.25-degree eccentricity step and one 1/256
    // mantissa step: bias within [formula - 0.1, formula].
    EXPECT_LE(p.b(c, r), bias + 1e-4) << c;
    EXPECT_GE(p.b(c, r), bias - 0.1) << c;
    if (e > config.foveal_radius_deg && !near_step(ratio_x) && !near_step(ratio_y)) {
      ++compared;
      EXPECT_EQ(p.rx(c, r), coarsest_rate(ppd_x, nyquist)) << c << " ratio " << ratio_x;
      EXPECT_EQ(p.ry(c, r), coarsest_rate(ppd_y, nyquist)) << c << " ratio " << ratio_y;
    }
  }
  EXPECT_GE(compared, 3);
}

// Every tile, three gazes, the Default model: never coarser and never more bias than the exact rule
// evaluated here on a dense sampling of the tile with the model's own inverse.
TEST(FoveationPlan, NeverCoarserThanTheExactRule) {
  const FoveationConfig config;
  const FoveationPlanner& planner = planner_for(config);
  const Eye eye = make_eye(1024, 768, 55, 45);
  for (const Gaze& g : {gaze_at(0, 0), gaze_at(-30, 20), gaze_at(40, -30)}) {
    const Plan p = plan(planner, eye, g, 32);
    double o[3];
    unit_gaze(g, o);
    int coarse = 0;
    for (std::uint32_t r = 0; r < p.maps.rows; ++r)
      for (std::uint32_t c = 0; c < p.maps.cols; ++c) {
        const TileTruth t = tile_truth(eye, o, c, r, 32);
        const double e = std::max(0.0, t.min_angle - config.gaze_uncertainty_deg);
        const double nyquist = 2 * max_visible_frequency<double>(1.0 / config.quality, e, config.params.drift,
                                                                 config.model, config.params);
        const bool fovea = t.min_angle <= config.gaze_uncertainty_deg + config.foveal_radius_deg;
        const int rx = fovea ? 1 : coarsest_rate(t.ppd_x * 1.0001, nyquist);
        const int ry = fovea ? 1 : coarsest_rate(t.ppd_y * 1.0001, nyquist);
        const double bias = fovea ? 0.0 : std::max(0.0, std::log2(std::min(t.ppd_x, t.ppd_y) / nyquist));
        EXPECT_LE(p.rx(c, r), rx) << c << "," << r;
        EXPECT_LE(p.ry(c, r), ry) << c << "," << r;
        EXPECT_LE(p.b(c, r), bias + 1e-3) << c << "," << r;
        coarse += p.rx(c, r) > 1;
      }
    EXPECT_GT(coarse, 20);
  }
}

// By default the head's rotation changes nothing: the vestibulo-ocular reflex holds the fixated
// world still on the retina. With head_rotation on (content turning with the head), it lowers the cutoff.
TEST(FoveationPlan, HeadRotationLowersTheCutoffOnlyWhenAsked) {
  FoveationConfig on;
  on.head_rotation = true;
  const FoveationPlanner& planner = planner_for(on);
  Eye still = make_eye(2000, 2000, 50, 50), turning = still;
  turning.angular_velocity[1] = 120;  // yaw, world axis
  const Plan a = plan(planner, still, gaze_at(0, 0)), b = plan(planner, turning, gaze_at(0, 0));
  EXPECT_FLOAT_EQ(a.maps.retinal_speed, 0.15f);  // the drift floor
  EXPECT_GT(b.maps.retinal_speed, 5.0f);
  EXPECT_GT(b.saved(), a.saved());
  for (std::size_t i = 0; i < a.rate.size(); ++i) ASSERT_GE(b.rate[i], a.rate[i]);
  // A rotation about the view axis (roll) of the same speed moves the centre least: below yaw's.
  Eye rolling = still;
  rolling.angular_velocity[2] = 120;
  EXPECT_LT(plan(planner, rolling, gaze_at(0, 0)).maps.retinal_speed, b.maps.retinal_speed);
  const Plan by_default = plan(planner_for(), turning, gaze_at(0, 0));
  EXPECT_EQ(by_default.rate, a.rate);
  EXPECT_FLOAT_EQ(by_default.maps.retinal_speed, 0.15f);
}

// The shading work counts each tile's covered pixels, the last column's and row's partial ones too,
// over its rates: summed here from the maps, for grids whose edges cut tiles, at every tile size.
TEST(FoveationPlan, ShadingWorkCountsPartialTiles) {
  const FoveationPlanner& planner = planner_for();
  for (std::uint32_t tile : {8u, 16u, 32u})
    for (const Gaze& gaze : {gaze_at(0, 0), gaze_at(25, -10), Gaze{}}) {
      const Eye eye = make_eye(1001, 707, 55, 40);
      const Plan p = plan(planner, eye, gaze, tile);
      ASSERT_NE(eye.viewport[0] % tile, 0u);
      double work = 0;
      for (std::uint32_t r = 0; r < p.maps.rows; ++r)
        for (std::uint32_t c = 0; c < p.maps.cols; ++c) {
          const double w = std::min(tile, eye.viewport[0] - c * tile),
                       h = std::min(tile, eye.viewport[1] - r * tile);
          work += w * h / (p.rx(c, r) * p.ry(c, r));
        }
      EXPECT_DOUBLE_EQ(p.maps.shaded, work) << "tile " << tile;
      if (gaze.valid) {  // some tiles coarser: less than every pixel (without gaze all are full rate)
        EXPECT_LT(p.maps.shaded, p.maps.pixels);
      }
    }
}

TEST(FoveationPlan, SavesMoreThanHalfCentredOn2000At100Degrees) {
  const Plan p = plan(planner_for(), make_eye(2000, 2000, 50, 50), gaze_at(0, 0));
  EXPECT_GT(p.saved(), 0.5);
  EXPECT_LT(p.saved(), 1.0 - 1.0 / 16);
  // The shading work is the tiles' pixels over their rates, summed here.
  double work = 0;
  for (std::uint32_t r = 0; r < p.maps.rows; ++r)
    for (std::uint32_t c = 0; c < p.maps.cols; ++c) work += 256.0 / (p.rx(c, r) * p.ry(c, r));
  EXPECT_DOUBLE_EQ(p.maps.shaded, work);  // 2000 = 125 x 16: every tile is whole
  // max_rate = 2 never goes past 2.
  FoveationConfig two;
  two.max_rate = 2;
  const Plan q = plan(planner_for(two), make_eye(2000, 2000, 50, 50), gaze_at(0, 0));
  for (std::uint8_t v : q.rate) ASSERT_LE(v, 2);
  EXPECT_LT(q.saved(), p.saved());
}

TEST(FoveationPlan, DeterministicAndAllocationFree) {
  const FoveationPlanner& planner = planner_for();
  const Eye eye = make_eye(2000, 2000, 50, 50);
  Plan p = plan(planner, eye, gaze_at(10, 5));
  const std::vector<std::uint8_t> rate = p.rate;
  const std::vector<float> bias = p.bias;
  const long before = g_allocations.load();
  for (int i = 0; i < 20; ++i) {
    plan_foveation(planner, eye, gaze_at(10 + i, 5), &p.maps);
    plan_foveation(planner, eye, gaze_at(10, 5), &p.maps);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(p.rate, rate);
  EXPECT_EQ(p.bias, bias);
}

TEST(FoveationPlan, GuenterLayersFromTheSameModel) {
  FoveationConfig config;
  config.model = ThresholdModel::GeislerPerry;
  const FoveationPlanner& planner = planner_for(config);
  const Eye eye = make_eye(3840, 2160, 45, 30);
  const FoveationLayers l = foveation_layers(planner, eye, 3);
  ASSERT_EQ(l.layers.n_layers, 3);
  // The line stays at or below the model's MAR, 1 / f_c(e - uncertainty), finest within the fovea.
  const ModelParams mp;
  for (double e = 0; e <= 90; e += 0.1) {
    const double m = e <= config.gaze_uncertainty_deg + config.foveal_radius_deg
                         ? 1 / geisler_perry_cutoff(0.0, 1.0, mp)
                         : 1 / geisler_perry_cutoff(e - config.gaze_uncertainty_deg, 1.0, mp);
    ASSERT_LE(l.omega0 + l.slope * e, m * (1 + 1e-6)) << e;
  }
  EXPECT_GT(l.slope, 0);
  EXPECT_LT(l.layers.radius[0], l.layers.radius[1]);
  EXPECT_EQ(l.layers.sampling[0], 1.0);
  EXPECT_GT(l.layers.sampling[2], l.layers.sampling[1]);
  EXPECT_GT(l.layers.speedup, 1.5);
  // The same call as guenter_layers() on the eye's display, and no dearer than the line through the
  // model's foveal MAR.
  const GuenterLayers direct =
      guenter_layers(2 * std::tan(45 / kDeg), 1.0, 3840, 2160.0 / 3840, l.slope, 3, l.omega0, 1000);
  EXPECT_DOUBLE_EQ(direct.work, l.layers.work);
  // Invalid eye: no layers.
  Eye bad = eye;
  bad.fov_deg[0] = std::nanf("");
  EXPECT_EQ(foveation_layers(planner, bad, 3).layers.n_layers, 0);
}
