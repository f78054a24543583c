// The runtime's cluster cuts (Scheduler::select_cut, acuity/clusters.hpp) on hierarchies lodgen
// builds from closed real meshes (Debian's libcgal-demo): crack-free and never a mix over 1000
// random views and gazes; visibility monotone in distance and in eccentricity; bad input; and the
// provisional per-group loss (provisional_group_loss) against its stated rule.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/clusters.hpp"
#include "acuity/scheduler.hpp"
#include "allocation_counter.hpp"  // the no-allocation check counts with it
#include "cluster_check.hpp"

using namespace acuity;
using namespace acuity::testing;

namespace {
const std::string kMeshes = ACUITY_MESH_DIR;

struct Built {
  lodgen::Mesh mesh;
  lodgen::ClusterHierarchy h;
  std::vector<std::uint32_t> roots, made;
  double diameter = 0;
  ClusterView view() const { return {h.clusters, h.groups, roots, made}; }
};
Built build(const std::string& file) {
  BuiltHierarchy built = built_hierarchy(kMeshes + "/" + file);
  Built b;
  b.mesh = std::move(built.mesh);
  b.h = std::move(built.h);
  b.roots = cluster_roots(b.h.clusters);
  b.made = cluster_made_index(b.h.clusters, b.h.groups.size());
  b.diameter = lodgen::diameter(b.mesh);
  return b;
}

// A stand-in loss that grows with the group's error (the selector's tests need no measured one):
// band b of 6 (2 .. 64 cycles per diameter) loses error / diameter x 2^b / 16, capped at 1.
const float kBands[6] = {2, 4, 8, 16, 32, 64};
std::vector<float> stand_in_loss(const Built& b, ClusterLoss* loss) {
  std::vector<float> lost;
  for (const ClusterGroup& g : b.h.groups)
    for (int k = 0; k < 6; ++k)
      lost.push_back(float(std::min(1.0, g.error / b.diameter * std::ldexp(1.0, k - 4))));
  loss->bands_cpod = kBands;
  loss->diameter = float(b.diameter);
  return lost;
}

// The stand-in loss of a hierarchy with its values beside it (not copyable: loss points into lost).
struct StandIn {
  ClusterLoss loss;
  std::vector<float> lost;
  explicit StandIn(const Built& b) : lost(stand_in_loss(b, &loss)) { loss.lost = lost; }
  StandIn(const StandIn&) = delete;
};

// Six view cells (+-x, +-y, +-z) whose loss is the stand-in's times a factor in [0, 1] drawn per group
// and cell: each group's loss then depends on the side it is seen from, unlike its parent's.
const float kSixCells[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
std::vector<float> six_cells(const std::vector<float>& lost, std::size_t groups, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<float> out;
  for (std::size_t g = 0; g < groups; ++g)
    for (int v = 0; v < 6; ++v) {
      const float f = u(rng) < 0.3f ? 0.0f : u(rng);
      for (int k = 0; k < 6; ++k) out.push_back(lost[g * 6 + std::size_t(k)] * f);
    }
  return out;
}

// The unit quaternion turning -Z onto unit direction d.
std::array<float, 4> look_along(std::array<double, 3> d) {
  const double a[3] = {0, 0, -1};
  const double c[3] = {a[1] * d[2] - a[2] * d[1], a[2] * d[0] - a[0] * d[2], a[0] * d[1] - a[1] * d[0]};
  const double w = 1 + (a[0] * d[0] + a[1] * d[1] + a[2] * d[2]);
  if (w < 1e-9) return {0, 1, 0, 0};
  const double n = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + w * w);
  return {float(c[0] / n), float(c[1] / n), float(c[2] / n), float(w / n)};
}

// One eye at `eye` looking at `target`, its gaze `gaze_deg` right and up of the view axis.
Frame frame_at(std::array<double, 3> eye, std::array<double, 3> target, float right_deg, float up_deg) {
  Frame f;
  std::array<double, 3> d = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
  const double n = std::hypot(d[0], d[1], d[2]);
  for (double& x : d) x /= n;
  const std::array<float, 4> q = look_along(d);
  for (int k = 0; k < 3; ++k) f.eyes[0].position[k] = eye[std::size_t(k)];
  for (int k = 0; k < 4; ++k) f.eyes[0].orientation[k] = q[std::size_t(k)];
  const float x = std::tan(right_deg * 3.14159265f / 180), y = std::tan(up_deg * 3.14159265f / 180);
  const float l = std::sqrt(x * x + y * y + 1);
  f.gaze[0].direction[0] = x / l;
  f.gaze[0].direction[1] = y / l;
  f.gaze[0].direction[2] = -1 / l;
  f.gaze[0].valid = true;
  return f;
}

SchedulerConfig exact(float quality = 1.0f) {
  SchedulerConfig c;
  c.max_objects = 1;
  c.evaluation = Evaluation::Exact;
  c.quality = quality;
  return c;
}

// A random view of an object: at the origin, turned and scaled at random; an eye 0.3 to 10
// diameters (scaled) away looking near it; the gaze anywhere within 40 degrees of the view axis;
// q 0.5 .. 2; a third moving.
struct RandomView {
  ObjectTransform t;
  Frame frame;
  float quality = 1;
  float velocity[3] = {0, 0, 0};
};
RandomView random_view(std::mt19937& rng, double diameter) {
  std::uniform_real_distribution<double> u(0, 1);
  RandomView v;
  const std::array<float, 4> q = look_along([&] {
    std::array<double, 3> d = {u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1};
    const double n = std::hypot(d[0], d[1], d[2]) + 1e-12;
    return std::array<double, 3>{d[0] / n, d[1] / n, d[2] / n};
  }());
  for (int k = 0; k < 4; ++k) v.t.rotation[k] = q[std::size_t(k)];
  v.t.scale = float(std::pow(10.0, u(rng) * 2 - 1));
  const double size = diameter * v.t.scale;
  std::array<double, 3> dir = {u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1};
  const double n = std::hypot(dir[0], dir[1], dir[2]) + 1e-12, dist = size * 0.3 * std::pow(10 / 0.3, u(rng));
  const std::array<double, 3> eye = {dir[0] / n * dist, dir[1] / n * dist, dir[2] / n * dist};
  const std::array<double, 3> target = {(u(rng) - 0.5) * size, (u(rng) - 0.5) * size, (u(rng) - 0.5) * size};
  v.quality = float(0.5 + 1.5 * u(rng));
  const float right = float(u(rng) * 80 - 40), up = float(u(rng) * 80 - 40);
  v.frame = frame_at(eye, target, right, up);
  v.velocity[0] = float(u(rng) < 0.33 ? size : 0.0);
  return v;
}

class ClosedMesh : public ::testing::TestWithParam<const char*> {};

}  // namespace

TEST_P(ClosedMesh, ThousandRandomViewsAndGazesAreCrackFree) {
  const Built b = build(GetParam());
  const StandIn stand_in(b);
  const ClusterLoss& loss = stand_in.loss;
  const std::vector<float>& lost = stand_in.lost;
  ClusterLoss per_cell = loss;  // every other view: the loss per view cell
  const std::vector<float> cell_lost = six_cells(lost, b.h.groups.size(), 4802);
  per_cell.view_directions = kSixCells;
  per_cell.view_lost = cell_lost;
  const Edges e = edges(b.mesh, b.h);
  CrackCheck crack(e);
  std::mt19937 rng(4803);
  std::vector<std::uint8_t> scratch(b.h.groups.size());
  std::vector<std::uint32_t> drawn(b.h.clusters.size());
  std::vector<bool> is_drawn(b.h.clusters.size(), false);
  std::size_t mixed = 0, coarser = 0;
  for (int view = 0; view < 1000; ++view) {
    const RandomView v = random_view(rng, b.diameter);
    Scheduler s(exact(v.quality));
    s.begin_frame(v.frame);
    const CutResult r = s.select_cut(b.view(), view % 2 ? per_cell : loss, v.t, v.velocity, scratch, drawn);
    ASSERT_EQ(r.status, CutStatus::Ok) << to_string(r.status);
    ASSERT_GT(r.clusters, 0u);
    const std::vector<std::uint32_t> cut(drawn.begin(), drawn.begin() + r.clusters);
    const std::uint32_t c = crack.first(cut);
    ASSERT_EQ(c, UINT32_MAX) << GetParam() << ": view " << view << " opens an edge of cluster " << c;
    for (std::uint32_t k : cut) is_drawn[k] = true;
    std::uint32_t levels_seen = 0;
    bool finest_seen = false;
    for (std::uint32_t k : cut) {
      const std::uint32_t g = b.h.clusters[k].refined;
      finest_seen |= g == kNoGroup;
      if (g == kNoGroup) continue;
      levels_seen |= 1u << std::min(b.h.groups[g].level, 31u);
      for (std::uint32_t m = b.h.groups[g].first_member;
           m < b.h.groups[g].first_member + b.h.groups[g].member_count; ++m)
        ASSERT_FALSE(is_drawn[m]) << "view " << view << " draws cluster " << k << " and " << m
                                  << " it replaces";
    }
    for (std::uint32_t k : cut) is_drawn[k] = false;
    coarser += levels_seen != 0;
    mixed += (levels_seen != 0 && finest_seen) || (levels_seen & (levels_seen - 1));
    // Every evaluated group is below a visible one or the roots: never more than the groups.
    EXPECT_LE(r.groups_evaluated, b.h.groups.size());
  }
  // The views test something: many cuts leave the finest mesh and many mix levels.
  EXPECT_GT(coarser, 300u);
  EXPECT_GT(mixed, 200u);
}

// Nearer, or with the gaze nearer, a group is never less refined. Distance: with every eccentricity 0
// (gaze_uncertainty_deg 180), the visible groups (scratch bit 4 on return) of a view are a subset of
// those of a view nearer along the same line, so it never draws fewer triangles. Gaze: a group
// visible with the gaze anywhere stays visible with the gaze on its centre (its eccentricity and its
// ancestors' then 0).
TEST_P(ClosedMesh, NearerOrCloserToTheGazeNeverCoarser) {
  const Built b = build(GetParam());
  ClusterLoss loss;
  const std::vector<float> lost = stand_in_loss(b, &loss);
  loss.lost = lost;
  std::mt19937 rng(4804);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::uint8_t> far_state(b.h.groups.size()), near_state(b.h.groups.size());
  std::vector<std::uint32_t> drawn(b.h.clusters.size());
  SchedulerConfig everywhere = exact();
  everywhere.gaze_uncertainty_deg = 180;
  Scheduler foveal(everywhere), s(exact());
  ObjectTransform t;
  std::size_t differed = 0, gazed = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::array<double, 3> dir = {u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1};
    const double n = std::hypot(dir[0], dir[1], dir[2]) + 1e-12;
    for (double& x : dir) x /= n;
    const double dist = b.diameter * 0.6 * std::pow(10.0, u(rng) * 2);
    const auto cut = [&](Scheduler& sch, const Frame& f, std::vector<std::uint8_t>& state) {
      sch.begin_frame(f);
      const CutResult r = sch.select_cut(b.view(), loss, t, nullptr, state, drawn);
      EXPECT_EQ(r.status, CutStatus::Ok);
      return r.triangles;
    };
    const auto eye_at = [&](double d) { return std::array<double, 3>{dir[0] * d, dir[1] * d, dir[2] * d}; };
    const std::uint64_t far = cut(foveal, frame_at(eye_at(dist), {0, 0, 0}, 0, 0), far_state);
    const std::uint64_t nearer = cut(foveal, frame_at(eye_at(dist * 0.7), {0, 0, 0}, 0, 0), near_state);
    EXPECT_GE(nearer, far) << "trial " << trial;
    for (std::size_t g = 0; g < far_state.size(); ++g)
      if (far_state[g] & 4) { ASSERT_TRUE(near_state[g] & 4) << "trial " << trial << ": group " << g; }
    differed += nearer != far;
    // The gaze anywhere within 30 degrees, then on a group it left visible.
    const float gx = float(u(rng) * 60 - 30), gy = float(u(rng) * 60 - 30);
    cut(s, frame_at(eye_at(dist), {0, 0, 0}, gx, gy), far_state);
    std::vector<std::uint32_t> visible;
    for (std::size_t g = 0; g < far_state.size(); ++g)
      if (far_state[g] & 4) visible.push_back(std::uint32_t(g));
    if (visible.empty()) continue;
    const ClusterGroup& g =
        b.h.groups[visible[std::size_t(u(rng) * double(visible.size())) % visible.size()]];
    // The eye looks at the object's centre; the gaze turns onto the group's centre.
    const std::array<double, 3> eye = eye_at(dist);
    const std::array<float, 4> q = look_along({-dir[0], -dir[1], -dir[2]});
    const double to[3] = {g.center[0] - eye[0], g.center[1] - eye[1], g.center[2] - eye[2]};
    // World to eye: the inverse rotation (conjugate) applied to `to`.
    const double x = -q[0], y = -q[1], z = -q[2], w = q[3];
    const double tx = 2 * (y * to[2] - z * to[1]), ty = 2 * (z * to[0] - x * to[2]),
                 tz = 2 * (x * to[1] - y * to[0]);
    const double local[3] = {to[0] + w * tx + (y * tz - z * ty), to[1] + w * ty + (z * tx - x * tz),
                             to[2] + w * tz + (x * ty - y * tx)};
    if (!(local[2] < 0)) continue;
    Frame f = frame_at(eye, {0, 0, 0}, 0, 0);
    const double ln = std::hypot(local[0], local[1], local[2]);
    for (int k = 0; k < 3; ++k) f.gaze[0].direction[k] = float(local[k] / ln);
    cut(s, f, near_state);
    const std::size_t id = std::size_t(&g - b.h.groups.data());
    ASSERT_TRUE(near_state[id] & 4) << "trial " << trial << ": group " << id << " coarsened under the gaze";
    ++gazed;
  }
  EXPECT_GT(differed, 20u);
  EXPECT_GT(gazed, 50u);
}

// With the loss per view cell, each group reads the cell the eye is in, seen from the group's centre
// in object space: a cell that loses nothing lets every group seen from it coarsen (the roots alone
// are drawn when all are); the other cells' loss, equal to the loss over all views, draws the cut
// without cells. Turning the object turns the cell the eye is in with it. The cells' arrays must
// match the groups and bands (BadHierarchy otherwise).
TEST(ClusterCut, ViewCellsReadTheCellTheEyeIsIn) {
  const Built b = build("armadillo.off");
  ClusterLoss loss;
  const std::vector<float> lost = stand_in_loss(b, &loss);
  loss.lost = lost;
  const std::size_t G = b.h.groups.size();
  std::vector<float> cells;  // +z (cell 4) loses nothing, every other cell what the loss over all views says
  for (std::size_t g = 0; g < G; ++g)
    for (int v = 0; v < 6; ++v)
      for (int k = 0; k < 6; ++k) cells.push_back(v == 4 ? 0.0f : lost[g * 6 + std::size_t(k)]);
  ClusterLoss per_cell = loss;
  per_cell.view_directions = kSixCells;
  per_cell.view_lost = cells;
  std::vector<std::uint8_t> scratch(G);
  std::vector<std::uint32_t> drawn(b.h.clusters.size());
  std::uint64_t roots = 0;
  for (std::uint32_t r : b.roots) roots += b.h.clusters[r].triangle_count;
  const double d = b.diameter * 3;
  const auto cut = [&](const ClusterLoss& l, std::array<double, 3> eye, const std::array<float, 4>& q) {
    Scheduler s(exact());
    s.begin_frame(frame_at(eye, {0, 0, 0}, 0, 0));
    ObjectTransform t;
    for (int k = 0; k < 4; ++k) t.rotation[k] = q[std::size_t(k)];
    const CutResult r = s.select_cut(b.view(), l, t, nullptr, scratch, drawn);
    EXPECT_EQ(r.status, CutStatus::Ok);
    return r.triangles;
  };
  const std::array<float, 4> identity = {0, 0, 0, 1};
  const std::uint64_t finest = b.h.finest_triangles();
  EXPECT_EQ(cut(per_cell, {0, 0, d}, identity), roots);  // the eye in +z: every group reads cell 4
  EXPECT_EQ(cut(per_cell, {d, 0, 0}, identity), cut(loss, {d, 0, 0}, identity));
  EXPECT_GT(cut(loss, {d, 0, 0}, identity), roots);
  EXPECT_LE(cut(loss, {d, 0, 0}, identity), finest);
  // The object turned 90 degrees about y (object +z to world +x): the eye in world +x sees its +z cell.
  const float h = std::sqrt(0.5f);
  EXPECT_EQ(cut(per_cell, {d, 0, 0}, {0, h, 0, h}), roots);
  EXPECT_GT(cut(per_cell, {0, 0, d}, {0, h, 0, h}), roots);
  ClusterLoss bad = per_cell;
  bad.view_lost = std::span<const float>(cells).first(cells.size() - 1);
  Scheduler s(exact());
  s.begin_frame(frame_at({0, 0, d}, {0, 0, 0}, 0, 0));
  EXPECT_EQ(s.select_cut(b.view(), bad, ObjectTransform{}, nullptr, scratch, drawn).status,
            CutStatus::BadHierarchy);
}

INSTANTIATE_TEST_SUITE_P(Real, ClosedMesh, ::testing::Values("fandisk.off", "armadillo.off", "bunny00.off"));

TEST(ClusterCut, BadInputFallsBackToTheFinestCut) {
  const Built b = build("elephant.off");
  ClusterLoss loss;
  const std::vector<float> lost = stand_in_loss(b, &loss);
  loss.lost = lost;
  std::vector<std::uint8_t> scratch(b.h.groups.size());
  std::vector<std::uint32_t> drawn(b.h.clusters.size());
  Scheduler s(exact());
  s.begin_frame(frame_at({0, 0, 30 * b.diameter}, {0, 0, 0}, 0, 0));
  const std::size_t finest_clusters = [&] {
    std::size_t k = 0;
    while (k < b.h.clusters.size() && b.h.clusters[k].refined == kNoGroup) ++k;
    return k;
  }();
  ObjectTransform t;
  CutResult r = s.select_cut(b.view(), loss, t, nullptr, scratch, drawn);
  ASSERT_EQ(r.status, CutStatus::Ok);
  ASSERT_LT(r.triangles, b.h.finest_triangles()) << "the good view draws less than the finest mesh";
  const auto expect_finest = [&](const CutResult& x, CutStatus status, const char* what) {
    EXPECT_EQ(x.status, status) << what;
    EXPECT_EQ(x.clusters, finest_clusters) << what;
    EXPECT_EQ(x.triangles, b.h.finest_triangles()) << what;
    for (std::uint32_t k = 0; k < x.clusters; ++k) EXPECT_EQ(drawn[k], k) << what;
  };
  ObjectTransform bad = t;
  bad.position[1] = NAN;
  expect_finest(s.select_cut(b.view(), loss, bad, nullptr, scratch, drawn), CutStatus::InvalidInput,
                "NaN position");
  EXPECT_EQ(s.select_cut(b.view(), loss, bad, nullptr, scratch, drawn).flags, kFlagInvalidInput);
  bad = t;
  bad.scale = 0;
  expect_finest(s.select_cut(b.view(), loss, bad, nullptr, scratch, drawn), CutStatus::InvalidInput,
                "zero scale");
  bad = t;
  bad.rotation[3] = 0.5f;
  expect_finest(s.select_cut(b.view(), loss, bad, nullptr, scratch, drawn), CutStatus::InvalidInput,
                "rotation");
  const float nan_velocity[3] = {0, NAN, 0};
  expect_finest(s.select_cut(b.view(), loss, t, nan_velocity, scratch, drawn), CutStatus::InvalidInput,
                "velocity");
  ClusterLoss short_loss = loss;
  short_loss.lost = std::span<const float>(lost).first(lost.size() - 1);
  expect_finest(s.select_cut(b.view(), short_loss, t, nullptr, scratch, drawn), CutStatus::BadHierarchy,
                "loss of the wrong size");
  ClusterLoss no_diameter = loss;
  no_diameter.diameter = 0;
  expect_finest(s.select_cut(b.view(), no_diameter, t, nullptr, scratch, drawn), CutStatus::BadHierarchy,
                "diameter 0");
  const CutResult empty = s.select_cut(ClusterView{}, ClusterLoss{}, t, nullptr, scratch, drawn);
  EXPECT_EQ(empty.status, CutStatus::BadHierarchy);
  EXPECT_EQ(empty.clusters, 0u);
  std::vector<std::uint8_t> small_scratch(b.h.groups.size() - 1);
  expect_finest(s.select_cut(b.view(), loss, t, nullptr, small_scratch, drawn), CutStatus::BadHierarchy,
                "scratch");
  // An output buffer too small: the count it needs, nothing written past it.
  std::vector<std::uint32_t> small(r.clusters - 1, 0xABCDu);
  const CutResult too_small = s.select_cut(b.view(), loss, t, nullptr, scratch, small);
  EXPECT_EQ(too_small.status, CutStatus::BufferTooSmall);
  EXPECT_EQ(too_small.clusters, r.clusters);
  // An invalid eye.
  Frame f = frame_at({0, 0, 30 * b.diameter}, {0, 0, 0}, 0, 0);
  f.eyes[0].orientation[0] = NAN;
  s.begin_frame(f);
  expect_finest(s.select_cut(b.view(), loss, t, nullptr, scratch, drawn), CutStatus::InvalidInput, "eye");
  // Deterministic: the same input, the same cut.
  s.begin_frame(frame_at({0, 0, 30 * b.diameter}, {0, 0, 0}, 0, 0));
  std::vector<std::uint32_t> again(drawn.size());
  const CutResult r2 = s.select_cut(b.view(), loss, t, nullptr, scratch, again);
  EXPECT_EQ(r2.clusters, r.clusters);
  s.select_cut(b.view(), loss, t, nullptr, scratch, drawn);
  EXPECT_TRUE(std::equal(again.begin(), again.begin() + r2.clusters, drawn.begin()));
}

// provisional_group_loss's rule on a made-up profile of three levels (errors 0, 0.01, 0.04
// diameters), one view, two orientations, two bands.
TEST(ClusterCut, ProvisionalLossFollowsItsRule) {
  Profile p{};
  p.meta.level_count = 3;
  p.meta.view_count = 1;
  p.meta.orientation_count = 2;
  p.meta.band_count = 2;
  p.meta.sphere[3] = 0.5f;  // diameter 1
  const ProfileLevel levels[3] = {{1000, 0.0f}, {500, 0.01f}, {250, 0.04f}};
  // lost[(k-1)][v][t][b]: level 1 loses (0.02, 0.10) at most; level 2 (0.05, 0.08): its band 1 is
  // raised to level 1's by the running maximum.
  const float lost[2 * 1 * 2 * 2] = {0.01f, 0.10f, 0.02f, 0.03f, 0.05f, 0.01f, 0.04f, 0.08f};
  const float bands[2] = {4, 16};
  p.levels = levels;
  p.lost = lost;
  p.bands = bands;
  ClusterGroup g[5];
  g[0].error = 0;       // nothing lost
  g[1].error = 0.005f;  // level 1
  g[2].error = 0.02f;   // level 2
  g[3].error = 0.08f;   // beyond: level 2's x 2
  g[4].error = 1.0f;    // capped at 1
  ClusterLoss loss;
  const std::vector<float> out = provisional_group_loss(p, g, &loss);
  ASSERT_EQ(out.size(), 10u);
  EXPECT_EQ(loss.lost.data(), out.data());
  EXPECT_EQ(loss.bands_cpod.data(), bands);
  EXPECT_FLOAT_EQ(loss.diameter, 1.0f);
  const float want[10] = {0, 0, 0.02f, 0.10f, 0.05f, 0.10f, 0.10f, 0.20f, 1.0f, 1.0f};
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(out[std::size_t(i)], want[i], 1e-6) << i;
}

namespace {
// The visible groups select_cut leaves in scratch (bit 4).
std::vector<std::uint8_t> visible_of(const std::vector<std::uint8_t>& scratch) {
  std::vector<std::uint8_t> v(scratch.size());
  for (std::size_t g = 0; g < v.size(); ++g) v[g] = (scratch[g] & 4) != 0;
  return v;
}
}  // namespace

// Hysteresis per group, as the object rule's: walking away, the cut keeps its visible groups for
// hysteresis_frames - 1 frames (held, kFlagHeld), then takes the memoryless cut; walking back, it
// refines at once. Every cut on the way is crack-free, and a zeroed memory's first cut is the
// memoryless one.
TEST(ClusterCut, GroupsCoarsenAfterTheHysteresisAndRefineAtOnce) {
  const Built b = build("armadillo.off");
  ClusterLoss loss;
  const std::vector<float> lost = stand_in_loss(b, &loss);
  loss.lost = lost;
  const Edges e = edges(b.mesh, b.h);
  CrackCheck crack(e);
  SchedulerConfig c = exact();
  c.hysteresis_frames = 5;
  c.gaze_uncertainty_deg = 180;  // every eccentricity 0: the nearer view is the finer
  Scheduler s(c);
  const std::size_t G = b.h.groups.size();
  std::vector<CutGroupMemory> memory(G);
  std::vector<std::uint8_t> scratch(G), plain(G);
  std::vector<std::uint32_t> drawn(b.h.clusters.size()), plain_drawn(b.h.clusters.size());
  ObjectTransform t;
  const Frame near = frame_at({0, 0, 1.5 * b.diameter}, {0, 0, 0}, 0, 0);
  const Frame far = frame_at({0, 0, 40 * b.diameter}, {0, 0, 0}, 0, 0);
  const auto cut_both = [&](const Frame& f) {
    s.begin_frame(f);
    const CutResult p = s.select_cut(b.view(), loss, t, nullptr, plain, plain_drawn);
    const CutResult r = s.select_cut(b.view(), loss, t, nullptr, memory, scratch, drawn);
    EXPECT_EQ(p.status, CutStatus::Ok);
    EXPECT_EQ(r.status, CutStatus::Ok);
    EXPECT_EQ(crack.first(std::vector<std::uint32_t>(drawn.begin(), drawn.begin() + r.clusters)), UINT32_MAX);
    return std::pair{r, p};
  };
  auto [first, first_plain] = cut_both(near);
  EXPECT_EQ(visible_of(scratch), visible_of(plain)) << "a zeroed memory takes the cut at once";
  EXPECT_EQ(first.held, 0u);
  const std::vector<std::uint8_t> near_visible = visible_of(scratch);
  for (int frame = 1; frame < 5; ++frame) {
    s.begin_frame(far);
    const long before = g_allocations;
    s.select_cut(b.view(), loss, t, nullptr, std::span<CutGroupMemory>(memory).first(0), plain, plain_drawn);
    EXPECT_EQ(g_allocations, before) << "select_cut allocates nothing";
    auto [r, p] = cut_both(far);
    ASSERT_LT(p.triangles, first.triangles) << "the far view coarsens";
    EXPECT_EQ(visible_of(scratch), near_visible) << "frame " << frame << " is held";
    EXPECT_EQ(r.triangles, first.triangles);
    EXPECT_GT(r.held, 0u);
    EXPECT_TRUE(r.flags & kFlagHeld);
  }
  auto [fifth, fifth_plain] = cut_both(far);
  EXPECT_EQ(visible_of(scratch), visible_of(plain)) << "the fifth frame coarsens";
  EXPECT_EQ(fifth.triangles, fifth_plain.triangles);
  EXPECT_EQ(fifth.held, 0u);
  EXPECT_FALSE(fifth.flags & kFlagHeld);
  auto [back, back_plain] = cut_both(near);
  EXPECT_EQ(visible_of(scratch), visible_of(plain)) << "refining applies at once";
  EXPECT_EQ(back.triangles, first.triangles);
}

// Saccade gating per group: a far view waits for a saccade (up to max_coarsen_wait frames), then
// coarsens in the saccade's frame, where the eye counts as fixating (the memoryless cut's).
TEST(ClusterCut, GroupsCoarsenInASaccade) {
  const Built b = build("bunny00.off");
  ClusterLoss loss;
  const std::vector<float> lost = stand_in_loss(b, &loss);
  loss.lost = lost;
  SchedulerConfig c = exact();
  c.saccade_speed = 100;
  c.max_coarsen_wait = 1000;
  Scheduler s(c);
  const std::size_t G = b.h.groups.size();
  std::vector<CutGroupMemory> memory(G);
  std::vector<std::uint8_t> scratch(G), plain(G);
  std::vector<std::uint32_t> drawn(b.h.clusters.size());
  ObjectTransform t;
  s.begin_frame(frame_at({0, 0, 1.5 * b.diameter}, {0, 0, 0}, 0, 0));
  const CutResult near = s.select_cut(b.view(), loss, t, nullptr, memory, scratch, drawn);
  Frame far = frame_at({0, 0, 40 * b.diameter}, {0, 0, 0}, 0, 0);
  for (int frame = 0; frame < 20; ++frame) {
    s.begin_frame(far);
    const CutResult r = s.select_cut(b.view(), loss, t, nullptr, memory, scratch, drawn);
    EXPECT_EQ(r.triangles, near.triangles) << "frame " << frame << ": no saccade yet";
    EXPECT_TRUE(r.flags & kFlagHeld);
  }
  far.gaze[0].has_velocity = true;
  far.gaze[0].angular_velocity[1] = 300;  // deg/s: a saccade
  s.begin_frame(far);
  const CutResult plain_cut = s.select_cut(b.view(), loss, t, nullptr, plain, drawn);
  const CutResult r = s.select_cut(b.view(), loss, t, nullptr, memory, scratch, drawn);
  EXPECT_LT(r.triangles, near.triangles);
  EXPECT_EQ(r.triangles, plain_cut.triangles);
  EXPECT_EQ(visible_of(scratch), visible_of(plain));
  EXPECT_EQ(r.held, 0u);
}

// explain_cut: every group's score and limiting band, as select_cut's walk decides them: a group the
// cut refines scored above 1, the maker of every drawn cluster is not visible and its group is; the
// score is the limiting band's lost / (q CT) at the frequency it reports. Bad sizes and bad input
// return select_cut's statuses.
TEST(ClusterCut, ExplainNamesEachGroupsLimitingBand) {
  const Built b = build("fandisk.off");
  ClusterLoss loss;
  const std::vector<float> lost = stand_in_loss(b, &loss);
  loss.lost = lost;
  const float q = 1.5f;
  Scheduler s(exact(q));
  const std::size_t G = b.h.groups.size();
  std::vector<std::uint8_t> scratch(G);
  std::vector<std::uint32_t> drawn(b.h.clusters.size());
  std::vector<GroupExplain> ex(G);
  ObjectTransform t;
  s.begin_frame(frame_at({0.3 * b.diameter, 0, 2 * b.diameter}, {0, 0, 0}, 10, -5));
  const CutResult r = s.select_cut(b.view(), loss, t, nullptr, scratch, drawn);
  ASSERT_EQ(s.explain_cut(b.view(), loss, t, nullptr, scratch, ex), CutStatus::Ok);
  std::size_t visible = 0, invisible = 0;
  for (std::size_t g = 0; g < G; ++g) {
    EXPECT_EQ(ex[g].visible != 0, (scratch[g] & 4) != 0) << "group " << g;
    if (ex[g].visible) {
      EXPECT_GT(ex[g].score, 1.0f) << "group " << g;
      ++visible;
    } else if (ex[g].score <= 1.0f) {
      ++invisible;
    }
    ASSERT_LT(ex[g].band, 6);
    EXPECT_EQ(ex[g].eye, 0);
    EXPECT_GT(ex[g].distance_m, 0.0f);
    EXPECT_GE(ex[g].eccentricity_deg, 0.0f);
    const float x = lost[g * 6 + ex[g].band];
    if (ex[g].threshold > 0 && std::isfinite(ex[g].threshold) && x > 0) {
      EXPECT_NEAR(ex[g].score, x / (q * ex[g].threshold), 1e-3 * ex[g].score) << "group " << g;
    }
    // The frequency is the band's cycles per diameter over the diameter's angle at the nearest point.
    const double deg = std::atan(1.0) * 4 / 180;
    EXPECT_NEAR(ex[g].frequency_cpd, kBands[ex[g].band] / (b.diameter / ex[g].distance_m / deg),
                1e-3 * ex[g].frequency_cpd);
  }
  EXPECT_GT(visible, 0u);
  EXPECT_GT(invisible, 0u);
  for (std::uint32_t k = 0; k < r.clusters; ++k) {
    const Cluster& cl = b.h.clusters[drawn[k]];
    if (cl.refined != kNoGroup) { EXPECT_FALSE(ex[cl.refined].visible) << "cluster " << drawn[k]; }
    if (cl.group != kNoGroup) { EXPECT_TRUE(ex[cl.group].visible) << "cluster " << drawn[k]; }
  }
  std::vector<GroupExplain> small(G - 1);
  EXPECT_EQ(s.explain_cut(b.view(), loss, t, nullptr, scratch, small), CutStatus::BadHierarchy);
  ObjectTransform bad = t;
  bad.scale = -1;
  EXPECT_EQ(s.explain_cut(b.view(), loss, bad, nullptr, scratch, ex), CutStatus::InvalidInput);
}

namespace {
// The triangle budget's greedy, naively (no heap, no made index): from the perceptual cut's visible
// groups (visible[g] != 0) drawing `triangles`, coarsen the visible group of least harm (explain_cut's
// score per triangle saved, at least 1; ties to the lower group) none of whose members' makers is
// visible and no eye inside (score +inf), until at most `budget` are drawn.
// Whether none of group g's members' makers is visible (visible(group) says which are).
template <class Visible>
bool frontier(const Built& b, std::size_t g, Visible&& visible) {
  const ClusterGroup& group = b.h.groups[g];
  for (std::uint32_t m = group.first_member; m < group.first_member + group.member_count; ++m)
    if (b.h.clusters[m].refined != kNoGroup && visible(b.h.clusters[m].refined)) return false;
  return true;
}

struct Greedy {
  std::vector<std::uint8_t> visible;
  std::uint64_t triangles = 0;
  std::uint32_t coarsened = 0, forced = 0;
};
Greedy greedy(const Built& b, std::vector<std::uint8_t> visible, std::uint64_t triangles,
              const std::vector<GroupExplain>& ex, std::uint64_t budget) {
  const auto& groups = b.h.groups;
  const auto& clusters = b.h.clusters;
  const auto saved = [&](std::size_t g) {
    std::int64_t s = 0;
    for (std::uint32_t m = groups[g].first_member; m < groups[g].first_member + groups[g].member_count; ++m)
      s += clusters[m].triangle_count;
    for (const Cluster& c : clusters)
      if (c.refined == g) s -= c.triangle_count;
    return s;
  };
  Greedy out;
  while (triangles > budget) {
    std::size_t best = groups.size();
    float best_harm = 0;
    for (std::size_t g = 0; g < groups.size(); ++g) {
      if (!visible[g] || std::isinf(ex[g].score) ||
          !frontier(b, g, [&](std::uint32_t k) { return visible[k] != 0; }))
        continue;
      const float harm = ex[g].score / float(std::max<std::int64_t>(saved(g), 1));
      if (best == groups.size() || harm < best_harm) {
        best = g;
        best_harm = harm;
      }
    }
    if (best == groups.size()) break;
    visible[best] = 0;
    triangles = std::uint64_t(std::int64_t(triangles) - saved(best));
    ++out.coarsened;
    out.forced += ex[best].score > 1.0f;
  }
  out.visible = std::move(visible);
  out.triangles = triangles;
  return out;
}
}  // namespace

// The triangle budget over clusters (select_cut with a CutBudget), over 300 random views per mesh:
// a budget at or above the perceptual cut changes nothing; below it the cut is crack-free, never a
// cluster beside one it replaces, at most the budget whenever a group is left that could coarsen
// (else every visible group whose makers are all invisible has an eye inside), and exactly the
// naive greedy's: the groups coarsened in order of least score per triangle saved, the same count
// forced past visibility (kFlagBudgetForced). A smaller budget coarsens a superset of the groups.
TEST_P(ClosedMesh, TriangleBudgetCoarsensTheLeastVisibleGroupsFirst) {
  const Built b = build(GetParam());
  const StandIn stand_in(b);
  const ClusterLoss& loss = stand_in.loss;
  const Edges e = edges(b.mesh, b.h);
  CrackCheck crack(e);
  std::mt19937 rng(4848);
  std::uniform_real_distribution<double> u(0, 1);
  const std::size_t G = b.h.groups.size();
  std::vector<std::uint8_t> scratch(G), budgeted(G), smaller(G);
  std::vector<CutCandidate> candidates(G);
  std::vector<GroupExplain> ex(G);
  std::vector<std::uint32_t> drawn(b.h.clusters.size()), drawn_budget(b.h.clusters.size());
  std::uint64_t roots = 0;
  for (std::uint32_t r : b.roots) roots += b.h.clusters[r].triangle_count;
  std::size_t met = 0, forced = 0, unmet = 0, coarsened = 0;
  for (int view = 0; view < 300; ++view) {
    const RandomView v = random_view(rng, b.diameter);
    Scheduler s(exact(v.quality));
    s.begin_frame(v.frame);
    const CutResult r = s.select_cut(b.view(), loss, v.t, v.velocity, scratch, drawn);
    ASSERT_EQ(r.status, CutStatus::Ok);
    const auto cut = [&](std::uint64_t triangles, std::vector<std::uint8_t>& state) {
      return s.select_cut(b.view(), loss, v.t, v.velocity, {}, CutBudget{triangles, candidates}, state,
                          drawn_budget);
    };
    for (std::uint64_t above : {r.triangles, r.triangles + 1 + std::uint64_t(u(rng) * 1000)}) {
      const CutResult x = cut(above, budgeted);
      EXPECT_EQ(x.triangles, r.triangles);
      EXPECT_EQ(x.budget_coarsened, 0u);
      ASSERT_EQ(x.clusters, r.clusters);
      EXPECT_TRUE(std::equal(drawn.begin(), drawn.begin() + r.clusters, drawn_budget.begin()));
    }
    if (r.triangles <= roots) continue;
    const std::uint64_t budget = roots / 2 + std::uint64_t(u(rng) * double(r.triangles - roots / 2));
    const long before = g_allocations;
    const CutResult x = cut(budget, budgeted);
    EXPECT_EQ(g_allocations, before) << "a budgeted cut allocates nothing";
    ASSERT_EQ(x.status, CutStatus::Ok);
    const std::vector<std::uint32_t> drawn_cut(drawn_budget.begin(), drawn_budget.begin() + x.clusters);
    ASSERT_EQ(crack.first(drawn_cut), UINT32_MAX) << "view " << view << ": the budgeted cut opens an edge";
    std::vector<bool> is_drawn(b.h.clusters.size(), false);
    std::uint64_t triangles = 0;
    for (std::uint32_t k : drawn_cut) {
      is_drawn[k] = true;
      triangles += b.h.clusters[k].triangle_count;
    }
    EXPECT_EQ(triangles, x.triangles);
    for (std::uint32_t k : drawn_cut) {
      const std::uint32_t g = b.h.clusters[k].refined;
      if (g == kNoGroup) continue;
      for (std::uint32_t m = b.h.groups[g].first_member;
           m < b.h.groups[g].first_member + b.h.groups[g].member_count; ++m) {
        ASSERT_FALSE(is_drawn[m]) << "view " << view << " draws cluster " << k << " and " << m;
      }
    }
    // The naive greedy from explain_cut's scores lands on the same groups.
    ASSERT_EQ(s.explain_cut(b.view(), loss, v.t, v.velocity, smaller, ex), CutStatus::Ok);
    const Greedy want = greedy(b, visible_of(scratch), r.triangles, ex, budget);
    EXPECT_EQ(visible_of(budgeted), want.visible) << "view " << view;
    EXPECT_EQ(x.triangles, want.triangles);
    EXPECT_EQ(x.budget_coarsened, want.coarsened);
    EXPECT_EQ(x.budget_forced, want.forced);
    EXPECT_EQ((x.flags & kFlagBudgetForced) != 0, x.budget_forced > 0);
    coarsened += x.budget_coarsened > 0;
    if (x.triangles <= budget) {
      ++met;
    } else {  // nothing left to coarsen: every candidate has an eye inside
      ++unmet;
      for (std::size_t g = 0; g < G; ++g) {
        if (!(budgeted[g] & 4)) continue;
        const bool could = frontier(b, g, [&](std::uint32_t k) { return (budgeted[k] & 4) != 0; });
        EXPECT_FALSE(could && !std::isinf(ex[g].score))
            << "view " << view << ": group " << g << " could coarsen";
      }
    }
    forced += x.budget_forced > 0;
    // Half the budget coarsens at least the same groups.
    const CutResult y = cut(std::max<std::uint64_t>(budget / 2, 1), smaller);
    EXPECT_LE(y.triangles, x.triangles);
    for (std::size_t g = 0; g < G; ++g)
      if (smaller[g] & 4) { ASSERT_TRUE(budgeted[g] & 4) << "view " << view << ": group " << g; }
  }
  EXPECT_GT(met, 100u);
  EXPECT_GT(coarsened, 200u);
  EXPECT_GT(forced, 20u);
  std::cout << GetParam() << ": budgets met " << met << ", unmet " << unmet << ", coarsened " << coarsened
            << ", forced " << forced << "\n";
}

// The budget with memory: the groups it coarsens are remembered invisible, and refine at once once
// the budget is lifted (the perceptual cut again, however long the hysteresis); far away, a budget of
// 1 triangle leaves the roots alone. Missing budget scratch or made index: BadHierarchy, the finest cut.
TEST(ClusterCut, TriangleBudgetWithMemoryAndBadSizes) {
  const Built b = build("armadillo.off");
  const StandIn stand_in(b);
  const ClusterLoss& loss = stand_in.loss;
  SchedulerConfig c = exact();
  c.hysteresis_frames = 30;
  Scheduler s(c);
  const std::size_t G = b.h.groups.size();
  std::vector<CutGroupMemory> memory(G);
  std::vector<CutCandidate> candidates(G);
  std::vector<std::uint8_t> scratch(G), plain(G);
  std::vector<std::uint32_t> drawn(b.h.clusters.size());
  ObjectTransform t;
  s.begin_frame(frame_at({0, 0, 1.5 * b.diameter}, {0, 0, 0}, 5, 0));
  const CutResult p = s.select_cut(b.view(), loss, t, nullptr, plain, drawn);
  const CutResult x = s.select_cut(b.view(), loss, t, nullptr, memory, CutBudget{p.triangles / 2, candidates},
                                   scratch, drawn);
  ASSERT_EQ(x.status, CutStatus::Ok);
  EXPECT_LE(x.triangles, p.triangles / 2);
  EXPECT_GT(x.budget_forced, 0u);
  for (std::size_t g = 0; g < G; ++g)
    if ((plain[g] & 4) && !(scratch[g] & 4)) { EXPECT_EQ(memory[g].state, kCutKnown) << "group " << g; }
  const CutResult lifted = s.select_cut(b.view(), loss, t, nullptr, memory, CutBudget{}, scratch, drawn);
  EXPECT_EQ(lifted.triangles, p.triangles);
  EXPECT_EQ(visible_of(scratch), visible_of(plain));
  std::uint64_t roots = 0;
  for (std::uint32_t r : b.roots) roots += b.h.clusters[r].triangle_count;
  s.begin_frame(frame_at({0, 0, 3 * b.diameter}, {0, 0, 0}, 0, 0));
  const CutResult least =
      s.select_cut(b.view(), loss, t, nullptr, {}, CutBudget{1, candidates}, scratch, drawn);
  EXPECT_EQ(least.triangles, roots);
  EXPECT_EQ(least.clusters, b.roots.size());
  // Bad sizes.
  const std::span<CutCandidate> short_scratch = std::span<CutCandidate>(candidates).first(G - 1);
  EXPECT_EQ(s.select_cut(b.view(), loss, t, nullptr, {}, CutBudget{1, short_scratch}, scratch, drawn).status,
            CutStatus::BadHierarchy);
  ClusterView no_index = b.view();
  no_index.made = {};
  const CutResult bad =
      s.select_cut(no_index, loss, t, nullptr, {}, CutBudget{1, candidates}, scratch, drawn);
  EXPECT_EQ(bad.status, CutStatus::BadHierarchy);
  EXPECT_EQ(bad.triangles, b.h.finest_triangles());
  // Without a budget the index is not needed.
  EXPECT_EQ(s.select_cut(no_index, loss, t, nullptr, {}, CutBudget{0, {}}, scratch, drawn).status,
            CutStatus::Ok);
}
