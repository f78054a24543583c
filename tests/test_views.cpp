// Views beyond the eyes: shadow maps' light views (orthographic, perspective) and secondary cameras.
// A level per view class; a Footprint level is never coarser than its projected geometric error in
// texels allows (against an independent, sampled computation of that error); hard cases; as an eye
// without gaze (AsEye); no allocation and the same bits every run.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "acuity/scheduler.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "allocation_counter.hpp"
#include "profile_fixture.hpp"

using namespace acuity;

namespace {

constexpr std::uint32_t kLevels = 6;

struct Fixture {
  spectra::ProfileData data = acuity::testing::small_profile(kLevels);
  Blob blob = spectra::encode_profile(data);
  Profile profile{};
  Fixture() { EXPECT_EQ(open_profile(blob.data(), blob.size, &profile), ProfileStatus::Ok); }
};
const Fixture& fixture() {
  static const Fixture f;
  return f;
}

// Unit quaternion (x y z w) turning -Z to `dir` (unit), +Y kept as up as far as it can be.
void look_along(const double dir[3], float q[4]) {
  // Rotation matrix columns: right, up, back (= -dir).
  double back[3] = {-dir[0], -dir[1], -dir[2]};
  double up0[3] = {0, 1, 0};
  if (std::abs(back[1]) > 0.99) up0[1] = 0, up0[2] = 1;
  double right[3] = {up0[1] * back[2] - up0[2] * back[1], up0[2] * back[0] - up0[0] * back[2],
                     up0[0] * back[1] - up0[1] * back[0]};
  const double rn = std::sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
  for (double& c : right) c /= rn;
  const double up[3] = {back[1] * right[2] - back[2] * right[1], back[2] * right[0] - back[0] * right[2],
                        back[0] * right[1] - back[1] * right[0]};
  const double m[3][3] = {{right[0], up[0], back[0]}, {right[1], up[1], back[1]}, {right[2], up[2], back[2]}};
  const double t = m[0][0] + m[1][1] + m[2][2];
  double x, y, z, w;
  if (t > 0) {
    const double s = 0.5 / std::sqrt(t + 1.0);
    w = 0.25 / s, x = (m[2][1] - m[1][2]) * s, y = (m[0][2] - m[2][0]) * s, z = (m[1][0] - m[0][1]) * s;
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]);
    w = (m[2][1] - m[1][2]) / s, x = 0.25 * s, y = (m[0][1] + m[1][0]) / s, z = (m[0][2] + m[2][0]) / s;
  } else if (m[1][1] > m[2][2]) {
    const double s = 2.0 * std::sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]);
    w = (m[0][2] - m[2][0]) / s, x = (m[0][1] + m[1][0]) / s, y = 0.25 * s, z = (m[1][2] + m[2][1]) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]);
    w = (m[1][0] - m[0][1]) / s, x = (m[0][2] + m[2][0]) / s, y = (m[1][2] + m[2][1]) / s, z = 0.25 * s;
  }
  q[0] = float(x), q[1] = float(y), q[2] = float(z), q[3] = float(w);
}

// v rotated by the inverse of q (world to view), in double.
void to_view(const float q[4], const double v[3], double out[3]) {
  const double x = -q[0], y = -q[1], z = -q[2], w = q[3];
  const double tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  out[0] = v[0] + w * tx + (y * tz - z * ty);
  out[1] = v[1] + w * ty + (z * tx - x * tz);
  out[2] = v[2] + w * tz + (x * ty - y * tx);
}

// The independent computation: the largest number of texels a geometric error of e metres anywhere
// in the sphere (centre c, radius r) covers in view v, sampled: at the centre and 200 points of its
// surface, the projection's largest singular value (central differences in double) times e.
// Orthographic: e x texels per metre along each axis, the larger. Returns +inf where the sphere
// reaches the view's plane, -1 where it lies wholly behind it.
double texels(const View& v, const double c[3], double r, double e) {
  const double w = v.viewport[0], h = v.viewport[1];
  if (v.projection == ViewProjection::Orthographic)
    return e *
           std::max(w / (double(v.extent_m[1]) - v.extent_m[0]), h / (double(v.extent_m[2]) - v.extent_m[3]));
  const double kr = 3.14159265358979323846 / 180;
  const double tl = std::tan(v.fov_deg[0] * kr), tr = std::tan(v.fov_deg[1] * kr);
  const double tu = std::tan(v.fov_deg[2] * kr), td = std::tan(v.fov_deg[3] * kr);
  const double fx = w / (tr - tl), fy = h / (tu - td);
  double centre[3], rel[3] = {c[0] - v.position[0], c[1] - v.position[1], c[2] - v.position[2]};
  to_view(v.orientation, rel, centre);
  if (-centre[2] + r <= 0) return -1;
  if (-centre[2] - r <= 0) return std::numeric_limits<double>::infinity();
  const auto project = [&](const double p[3], double out[2]) {
    out[0] = fx * p[0] / -p[2];
    out[1] = fy * p[1] / -p[2];
  };
  double most = 0;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int s = 0; s <= 200; ++s) {
    double p[3] = {centre[0], centre[1], centre[2]};
    if (s > 0) {
      double d[3] = {normal(rng), normal(rng), normal(rng)};
      if (s <= 6) d[0] = d[1] = d[2] = 0, d[(s - 1) / 2] = (s % 2) ? 1 : -1;  // the six poles first
      const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (int k = 0; k < 3; ++k) p[k] += r * d[k] / n;
    }
    double J[2][3];
    const double step = 1e-6 * std::max(1.0, -p[2]);
    for (int k = 0; k < 3; ++k) {
      double a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]}, pa[2], pb[2];
      a[k] += step;
      b[k] -= step;
      project(a, pa);
      project(b, pb);
      J[0][k] = (pa[0] - pb[0]) / (2 * step);
      J[1][k] = (pa[1] - pb[1]) / (2 * step);
    }
    const double m00 = J[0][0] * J[0][0] + J[0][1] * J[0][1] + J[0][2] * J[0][2];
    const double m11 = J[1][0] * J[1][0] + J[1][1] * J[1][1] + J[1][2] * J[1][2];
    const double m01 = J[0][0] * J[1][0] + J[0][1] * J[1][1] + J[0][2] * J[1][2];
    const double largest = 0.5 * (m00 + m11) + std::sqrt(0.25 * (m00 - m11) * (m00 - m11) + m01 * m01);
    most = std::max(most, std::sqrt(largest));
  }
  return e * most;
}

// The profile's sphere (small_profile: centre (0.5, -1, 2), radius 1.5) of an object at `pos`,
// unrotated, scaled by `scale`: its world centre and radius; and level k's error [m].
struct Placed {
  double centre[3], radius;
};
Placed placed(const double pos[3], float scale) {
  const auto& d = fixture().data;
  return {{pos[0] + scale * d.sphere[0], pos[1] + scale * d.sphere[1], pos[2] + scale * d.sphere[2]},
          double(scale * d.sphere[3])};
}
double error_m(std::uint32_t k, double radius) {
  return fixture().data.levels[k].geometric_error * 2 * radius;
}

ObjectTransform transform(const double pos[3], float scale) {
  ObjectTransform t;
  for (int k = 0; k < 3; ++k) t.position[k] = pos[k];
  t.scale = scale;
  return t;
}

SchedulerConfig with_views(std::uint32_t objects, std::uint32_t views, std::uint32_t classes) {
  SchedulerConfig c;
  c.max_objects = objects;
  c.max_views = views;
  c.max_view_classes = classes;
  return c;
}

Frame eye_frame(const View* views, std::uint32_t count) {
  Frame f;
  f.gaze[0].valid = true;
  f.dt = 1.0f / 90;
  f.views = views;
  f.view_count = count;
  return f;
}

}  // namespace

// Random objects under random orthographic and perspective light views (maps of 256 to 4096 texels,
// allowances of 0.5 to 4 texels): each Footprint level's error covers at most pixel_error texels by
// the independent computation (never coarser than the footprint allows), the next level's more than
// a quarter of it (not needlessly fine), and the orthographic level is exactly the largest allowed.
TEST(Views, FootprintLevelNeverCoarserThanItsTexels) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  constexpr std::uint32_t kObjects = 150, kViews = 16;
  int coarse = 0, checked_next = 0;
  for (std::uint32_t round = 0; round < kViews; ++round) {
    const bool ortho = round % 2 == 0;
    View v;
    v.projection = ortho ? ViewProjection::Orthographic : ViewProjection::Perspective;
    v.pixel_error = float(0.5 + 3.5 * u(rng));
    const std::uint32_t res = 256u << (round % 5);
    v.viewport[0] = res;
    v.viewport[1] = round % 3 == 0 ? res / 2 : res;
    double dir[3] = {u(rng) - 0.5, -1.0, u(rng) - 0.5};
    const double n = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (double& d : dir) d /= n;
    look_along(dir, v.orientation);
    v.position[0] = -dir[0] * 60, v.position[1] = -dir[1] * 60, v.position[2] = -dir[2] * 60;
    const float half = float(20 + 60 * u(rng));
    v.extent_m[0] = -half, v.extent_m[1] = half * 1.2f, v.extent_m[2] = half, v.extent_m[3] = -half * 0.8f;
    v.fov_deg[0] = -float(20 + 30 * u(rng)), v.fov_deg[1] = float(20 + 30 * u(rng));
    v.fov_deg[2] = float(20 + 30 * u(rng)), v.fov_deg[3] = -float(20 + 30 * u(rng));
    SchedulerConfig c = with_views(kObjects, 1, 1);
    c.evaluation = Evaluation::Exact;  // the eyes' tables are not what is tested
    Scheduler s(c);
    const int p = s.add_profile(fixture().profile);
    std::vector<double> pos(3 * kObjects);
    std::vector<float> scale(kObjects);
    for (std::uint32_t i = 0; i < kObjects; ++i) {
      for (int k = 0; k < 3; ++k) pos[3 * i + k] = (u(rng) - 0.5) * 80;
      scale[i] = float(0.05 + 2 * u(rng) * u(rng));
      ASSERT_EQ(s.add_object(p, transform(&pos[3 * i], scale[i])), i);
    }
    const Frame f = eye_frame(&v, 1);
    s.run_frame(f);
    const std::uint8_t* level = s.view_level_array(0);
    ASSERT_NE(level, nullptr);
    for (std::uint32_t i = 0; i < kObjects; ++i) {
      const Placed o = placed(&pos[3 * i], scale[i]);
      const std::uint32_t k = level[i];
      SCOPED_TRACE(::testing::Message() << "view " << round << " object " << i << " level " << k);
      ASSERT_LT(k, kLevels);
      const double t = texels(v, o.centre, o.radius, error_m(k, o.radius));
      if (t < 0) {  // wholly behind the light: not in its map
        EXPECT_EQ(k, kLevels - 1);
        continue;
      }
      EXPECT_LE(t, v.pixel_error * (1 + 1e-4));
      coarse += k > 0;
      if (k + 1 < kLevels) {
        const double next = texels(v, o.centre, o.radius, error_m(k + 1, o.radius));
        if (ortho) {
          EXPECT_GT(next, v.pixel_error * (1 - 1e-4));  // exactly the largest allowed
        } else if (std::isfinite(next)) {
          EXPECT_GT(next, v.pixel_error / 4);
          ++checked_next;
        }
      }
    }
  }
  EXPECT_GT(coarse, int(kObjects * kViews / 4)) << "most objects should be coarser than the finest";
  EXPECT_GT(checked_next, 100);
}

// An object behind the eye, far outside its view: the eye's level is coarse, its shadow level comes
// from the light's map (orthographic, 2048 texels over 40 m) and is as the footprint allows.
TEST(Views, ObjectOutsideTheEyesViewStillGetsAShadowLevel) {
  Scheduler s(with_views(2, 2, 1));
  const int p = s.add_profile(fixture().profile);
  const double behind[3] = {0, 0, 40}, ahead[3] = {0, 0, -5};
  const ObjectId back = s.add_object(p, transform(behind, 1.0f));
  const ObjectId front = s.add_object(p, transform(ahead, 1.0f));
  View sun;
  sun.projection = ViewProjection::Orthographic;
  const double down[3] = {0, -1, 0};
  look_along(down, sun.orientation);
  sun.position[1] = 50;
  sun.extent_m[0] = -20, sun.extent_m[1] = 20, sun.extent_m[2] = 60, sun.extent_m[3] = -20;
  sun.viewport[0] = sun.viewport[1] = 2048;
  Frame f = eye_frame(&sun, 1);
  s.run_frame(f);
  const std::uint8_t* shadow = s.view_level_array(0);
  EXPECT_EQ(s.level(back), kLevels - 1);  // the eye does not see it
  EXPECT_LT(shadow[back], s.level(back));
  // 2048 texels over 40 m: 51.2 texels per metre; level k's error is 0.01 k x 3 m, 1.54 k texels.
  const Placed o = placed(behind, 1.0f);
  std::uint32_t want = 0;
  while (want + 1 < kLevels &&
         texels(sun, o.centre, o.radius, error_m(want + 1, o.radius)) <= sun.pixel_error)
    ++want;
  EXPECT_EQ(shadow[back], want);
  EXPECT_EQ(shadow[front], want);  // orthographic: the same footprint anywhere
  // A coarser map (256 texels): a coarser shadow level, still independent of the eye.
  sun.viewport[0] = sun.viewport[1] = 256;
  s.run_frame(f);
  EXPECT_GT(shadow[back], want);
  EXPECT_EQ(s.level(back), kLevels - 1);
}

// Hard cases, each with its defined level.
TEST(Views, HardCases) {
  SchedulerConfig c = with_views(8, 3, 3);
  c.fallback_level = 2;
  Scheduler s(c);
  const int p = s.add_profile(fixture().profile);
  const double in_front[3] = {0, 0, -30}, behind[3] = {0, 0, 30}, straddling[3] = {-0.5, 1, -2.5};
  const ObjectId a = s.add_object(p, transform(in_front, 1.0f));
  const ObjectId b = s.add_object(p, transform(behind, 1.0f));
  const ObjectId straddle = s.add_object(p, transform(straddling, 1.0f));  // centre at z -0.5, r 1.5
  const ObjectId bad = s.add_object(p, transform(in_front, 1.0f));
  ObjectTransform nan_t = transform(in_front, 1.0f);
  nan_t.position[0] = std::numeric_limits<double>::quiet_NaN();
  s.set_transform(bad, nan_t);
  View spot;  // at the origin looking along -Z, 512 texels over 90 degrees
  spot.viewport[0] = spot.viewport[1] = 512;
  View views[3] = {spot, spot, spot};
  views[1].view_class = 1;
  views[2].view_class = 1;
  const auto run = [&](std::uint32_t count) {
    s.run_frame(eye_frame(views, count));
    return s.view_level_array(0);
  };
  const std::uint8_t* level = run(1);
  EXPECT_EQ(level[b], kLevels - 1) << "wholly behind the light: not in its map";
  EXPECT_EQ(level[straddle], 0) << "reaching the light's plane: finest";
  EXPECT_EQ(level[bad], 2) << "non-finite object: the fallback level";
  EXPECT_GT(level[a], 0);
  EXPECT_EQ(s.view_level_array(1)[a], kLevels - 1) << "a class no view named: coarsest";
  EXPECT_EQ(s.view_level_array(3), nullptr);
  // Two views of one class: the finer need wins (a near, fine cascade and a coarse one).
  views[1].viewport[0] = views[1].viewport[1] = 64;
  views[2].viewport[0] = views[2].viewport[1] = 4096;
  run(3);
  const std::uint8_t both = s.view_level_array(1)[a];
  run(2);
  const std::uint8_t coarse_only = s.view_level_array(1)[a];
  EXPECT_LT(both, coarse_only);
  // Invalid views: a zero-size map, a NaN position, a non-unit orientation, an empty field of view:
  // every object takes the fallback level.
  for (int k = 0; k < 4; ++k) {
    View v = spot;
    if (k == 0) v.viewport[0] = 0;
    if (k == 1) v.position[1] = std::numeric_limits<double>::quiet_NaN();
    if (k == 2) v.orientation[3] = 2;
    if (k == 3) v.fov_deg[1] = v.fov_deg[0];
    views[0] = v;
    level = run(1);
    EXPECT_EQ(level[a], 2) << k;
    EXPECT_EQ(level[b], 2) << k;
  }
  views[0] = spot;
  views[0].projection = ViewProjection::Orthographic;
  views[0].extent_m[1] = views[0].extent_m[0];  // zero-width map
  EXPECT_EQ(run(1)[a], 2);
  // pixel_error NaN or negative: nothing passes but an error of 0: finest.
  views[0] = spot;
  views[0].pixel_error = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(run(1)[a], 0);
  views[0].pixel_error = -1;
  EXPECT_EQ(run(1)[a], 0);
  // A view of a class past max_view_classes is skipped; views past max_views are not read.
  views[0] = spot;
  views[0].view_class = 7;
  EXPECT_EQ(run(1)[a], kLevels - 1);
  // Clamps hold.
  views[0].view_class = 0;
  s.set_clamps(a, 4, 5);
  EXPECT_EQ(run(1)[a], 4);
  s.set_clamps(b, 0, 1);
  EXPECT_EQ(run(1)[b], 1);
}

// AsEye: a perspective secondary camera decides as the scheduler's rule decides for an eye without
// gaze at its pose (here: against a scheduler whose eye is that camera, exact evaluation).
TEST(Views, AsEyeDecidesAsAnEyeWithoutGaze) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  constexpr std::uint32_t n = 200;
  View mirror;
  mirror.rule = ViewRule::AsEye;
  mirror.position[0] = 3, mirror.position[1] = 1, mirror.position[2] = 4;
  const double dir[3] = {-0.6, 0, -0.8};
  look_along(dir, mirror.orientation);
  mirror.viewport[0] = 1280, mirror.viewport[1] = 720;
  mirror.fov_deg[0] = -40, mirror.fov_deg[1] = 40, mirror.fov_deg[2] = 25, mirror.fov_deg[3] = -25;
  for (const SelectionRule rule : {SelectionRule::Perceptual, SelectionRule::ScreenSize}) {
    SchedulerConfig c = with_views(n, 1, 1);
    c.rule = rule;
    Scheduler s(c);
    SchedulerConfig e;
    e.max_objects = n;
    e.rule = rule;
    e.evaluation = Evaluation::Exact;
    Scheduler ref(e);
    const int p = s.add_profile(fixture().profile);
    ref.add_profile(fixture().profile);
    for (std::uint32_t i = 0; i < n; ++i) {
      const double pos[3] = {30 * u(rng), 5 * u(rng), -20 + 30 * u(rng)};
      s.add_object(p, transform(pos, 1.0f));
      ref.add_object(0, transform(pos, 1.0f));
    }
    s.run_frame(eye_frame(&mirror, 1));
    Frame f;
    std::copy(mirror.position, mirror.position + 3, f.eyes[0].position);
    std::copy(mirror.orientation, mirror.orientation + 4, f.eyes[0].orientation);
    std::copy(mirror.fov_deg, mirror.fov_deg + 4, f.eyes[0].fov_deg);
    std::copy(mirror.viewport, mirror.viewport + 2, f.eyes[0].viewport);
    f.gaze[0].valid = false;
    f.dt = 1.0f / 90;
    ref.run_frame(f);
    int coarse = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      EXPECT_EQ(s.view_level_array(0)[i], ref.level(i)) << i;
      coarse += ref.level(i) > 0;
    }
    EXPECT_GT(coarse, 0);
  }
}

// Views allocate nothing per frame and give the same bits every run.
TEST(Views, NoAllocationAndDeterministic) {
  const auto run = [](std::vector<std::uint8_t>* out, long* allocations) {
    Scheduler s(with_views(500, 4, 2));
    const int p = s.add_profile(fixture().profile);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-40, 40);
    for (int i = 0; i < 500; ++i) {
      const double pos[3] = {u(rng), u(rng) * 0.1, u(rng)};
      s.add_object(p, transform(pos, 1.0f));
    }
    View views[4];
    views[0].projection = ViewProjection::Orthographic;
    const double down[3] = {0.3, -0.9, 0.1};
    look_along(down, views[0].orientation);
    views[1] = views[0];
    views[1].extent_m[0] = -40, views[1].extent_m[1] = 40, views[1].extent_m[2] = 40,
    views[1].extent_m[3] = -40;
    views[2].view_class = 1;
    views[2].rule = ViewRule::AsEye;
    views[3].view_class = 1;
    views[3].position[1] = 10;
    Frame f = eye_frame(views, 4);
    s.run_frame(f);
    out->reserve(5 * 2 * 500);
    *allocations = 0;
    for (int frame = 0; frame < 5; ++frame) {
      views[2].position[0] = 0.5 * frame;
      const long before = g_allocations.load();
      s.run_frame(f);
      *allocations += g_allocations.load() - before;
      for (std::uint32_t c = 0; c < 2; ++c)
        out->insert(out->end(), s.view_level_array(c), s.view_level_array(c) + 500);
    }
  };
  std::vector<std::uint8_t> a, b;
  long alloc_a = -1, alloc_b = -1;
  run(&a, &alloc_a);
  run(&b, &alloc_b);
  EXPECT_EQ(alloc_a, 0);
  EXPECT_EQ(alloc_b, 0);
  EXPECT_EQ(a, b);
}
