// What each group of a cluster hierarchy loses (issue 48 item 2; acuity/spectra/cluster_loss.hpp)
// on hierarchies lodgen builds from closed real meshes (Debian's libcgal-demo): a group drawn
// coarse changes the image only within its own sphere (so its window sees all of it); the stored
// row is the measured windows folded by the stated rules; the stored loss bounds direct
// measurements of sampled groups from random other directions; and a profile's Clusters section
// feeds the runtime's cut (measured_group_loss, Scheduler::select_cut), crack-free.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "acuity/bake/scene.hpp"
#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/clusters.hpp"
#include "acuity/scheduler.hpp"
#include "acuity/spectra/cluster_loss.hpp"
#include "cluster_check.hpp"

using namespace acuity;
using namespace acuity::testing;

namespace {
const std::string kMeshes = ACUITY_MESH_DIR;

struct Built : BuiltHierarchy {
  spectra::ClusterMesh view() const { return bake::cluster_mesh(mesh, h); }
};
// Random directions each group is measured from directly, against its stored loss. The sanitizer
// run (ACUITY_QUICK_TESTS) takes fewer: the same code, a third of the renders.
int check_directions() { return std::getenv("ACUITY_QUICK_TESTS") ? 6 : 16; }

Built build(const std::string& file) { return {built_hierarchy(kMeshes + "/" + file)}; }

spectra::ClusterLossSettings settings(std::uint32_t pixels, std::uint32_t views) {
  spectra::ClusterLossSettings s;
  s.render.pixels = pixels;
  s.views = views;
  return s;
}

// A random unit direction, framed as the profile's views are.
ProfileView random_view(std::mt19937& rng) {
  std::normal_distribution<float> n;
  float d[3];
  do {
    for (float& x : d) x = n(rng);
  } while (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < 1e-4f);
  return spectra::make_view(d[0], d[1], d[2]);
}

// Direct measurements against the stored loss: how many it bounds, and by how much it misses the rest.
struct BoundTally {
  std::size_t values = 0, bounded = 0;
  double worst = 0;  // the largest direct / stored over the values it misses
  void add(float direct, float stored) {
    ++values;
    if (direct <= stored)
      ++bounded;
    else
      worst = std::max(worst, double(direct) / double(stored));
  }
  double share() const { return double(bounded) / double(values); }
};

// One elephant hierarchy and its measurement, shared by the tests (built once).
struct Measured {
  Built b;
  spectra::Material material;
  std::unique_ptr<spectra::ClusterLossMeasurer> m;
  spectra::ProfileClusterData data;
  spectra::ClusterLossReport report;
};
const Measured& elephant() {
  static const Measured* e = [] {
    auto* out = new Measured;
    out->b = build("elephant.off");
    spectra::ClusterLossSettings s = settings(128, 42);
    s.view_cells = true;  // asked for: from 42 directions the cells are not written by default
    out->m = std::make_unique<spectra::ClusterLossMeasurer>(out->b.view(), out->material, s);
    out->data = spectra::measure_cluster_loss(out->b.view(), out->material, s, {}, &out->report);
    return out;
  }();
  return *e;
}
}  // namespace

// The attribution the measurement rests on: with one group drawn coarse and everything else finest,
// the whole object's image differs from the finest mesh's only inside that group's projected sphere
// (so the window, margin x its radius at least, holds all of what the group changes).
TEST(ClusterLoss, AGroupDrawnCoarseChangesTheImageOnlyWithinItsSphere) {
  const Measured& e = elephant();
  const spectra::ClusterMesh cm = e.b.view();
  spectra::RenderSettings r;
  r.pixels = 256;
  std::copy_n(e.m->sphere(), 4, r.sphere);
  std::mt19937 rng(3);
  std::size_t changed = 0;
  for (std::uint32_t g = 0; g < cm.groups.size(); ++g) {
    const std::vector<std::uint32_t> coarse = e.m->coarse_indices(g);
    const std::span<const std::uint32_t> finest = e.m->finest_indices();
    spectra::MeshView a = cm.mesh, c = cm.mesh;
    a.indices = finest.data();
    a.index_count = finest.size();
    c.indices = coarse.data();
    c.index_count = coarse.size();
    const ProfileView view = random_view(rng);
    const spectra::Image fine = spectra::render_snapshot(a, e.material, view, r);
    const spectra::Image coarse_image = spectra::render_snapshot(c, e.material, view, r);
    // The group's sphere in image pixels (render_snapshot's framing: right = -direction x up).
    const ClusterGroup& group = cm.groups[g];
    const float* d = view.direction;
    const float* u = view.up;
    const float right[3] = {-(d[1] * u[2] - d[2] * u[1]), -(d[2] * u[0] - d[0] * u[2]),
                            -(d[0] * u[1] - d[1] * u[0])};
    const float rel[3] = {group.center[0] - r.sphere[0], group.center[1] - r.sphere[1],
                          group.center[2] - r.sphere[2]};
    const float scale = 0.5f * float(r.pixels) / r.sphere[3];
    const float cx =
        0.5f * float(r.pixels) + scale * (rel[0] * right[0] + rel[1] * right[1] + rel[2] * right[2]);
    const float cy = 0.5f * float(r.pixels) - scale * (rel[0] * u[0] + rel[1] * u[1] + rel[2] * u[2]);
    const float reach = scale * group.radius + 1.5f;  // a pixel's footprint either side
    for (std::uint32_t y = 0; y < r.pixels; ++y)
      for (std::uint32_t x = 0; x < r.pixels; ++x) {
        if (fine.at(x, y) == coarse_image.at(x, y)) continue;
        ++changed;
        ASSERT_LE(std::hypot(float(x) + 0.5f - cx, float(y) + 0.5f - cy), reach)
            << "group " << g << " changed pixel " << x << "," << y << " outside its sphere";
      }
  }
  EXPECT_GT(changed, 0u);  // the check saw coarse groups at all
}

// The stored row is the windows' measurements folded as cluster_loss.hpp says: its window bands the
// largest over the 42 directions and orientations; coarser bands its lowest; finer bands at least its
// finest and what the groups that made its members stored there.
TEST(ClusterLoss, TheStoredRowFoldsTheWindowsAsStated) {
  const Measured& e = elephant();
  const spectra::ClusterMesh cm = e.b.view();
  const std::size_t Bc = e.data.bands.size(), Bw = e.m->window_bands(), T = e.m->orientations();
  ASSERT_EQ(e.data.lost.size(), cm.groups.size() * Bc);
  ASSERT_EQ(e.data.hierarchy_hash, cluster_hierarchy_hash(cm.clusters, cm.groups));
  for (std::size_t j = 0; j < Bc; ++j)  // one octave grid from lowest_band
    EXPECT_FLOAT_EQ(e.data.bands[j], 2.0f * std::exp2(float(j)));
  const spectra::SphereMesh ico = spectra::icosphere(2);
  for (std::uint32_t g : {0u, std::uint32_t(cm.groups.size() / 2), std::uint32_t(cm.groups.size() - 1)}) {
    std::vector<float> own(Bw, 0.0f);
    for (std::uint32_t v = 0; v < 42; ++v) {
      const std::vector<float> l = e.m->measure(
          g, spectra::make_view(ico.positions[3 * v], ico.positions[3 * v + 1], ico.positions[3 * v + 2]));
      for (std::size_t t = 0; t < T; ++t)
        for (std::size_t i = 0; i < Bw; ++i) own[i] = std::max(own[i], l[t * Bw + i]);
    }
    const float* row = &e.data.lost[g * Bc];
    const std::size_t first = e.m->first_band(g);
    for (std::size_t j = 0; j < Bc; ++j) {
      if (j < first)
        EXPECT_EQ(row[j], own[0]) << g << " " << j;
      else if (j < first + Bw)
        EXPECT_EQ(row[j], own[j - first]) << g << " " << j;
      else
        EXPECT_GE(row[j], own[Bw - 1]) << g << " " << j;
    }
    EXPECT_GT(*std::max_element(own.begin(), own.end()), 0.0f) << "group " << g << " loses nothing";
  }
}

// What the stored loss claims: for each group and band, the largest lost contrast seen from any
// direction. Checked against direct measurements (the same windows, rendered and analysed again) of
// every group from 16 random directions (6 in the sanitizer run) none of the 42 measured: the share
// of (group, direction, band) values the stored loss bounds, and how far above it the rest reach.
TEST(ClusterLoss, TheStoredLossBoundsDirectMeasurementsFromOtherDirections) {
  const Measured& e = elephant();
  const spectra::ClusterMesh cm = e.b.view();
  const std::size_t Bc = e.data.bands.size(), Bw = e.m->window_bands(), T = e.m->orientations();
  std::mt19937 rng(7);
  BoundTally tally;
  for (std::uint32_t g = 0; g < cm.groups.size(); ++g)
    for (int k = 0; k < check_directions(); ++k) {
      const std::vector<float> l = e.m->measure(g, random_view(rng));
      for (std::size_t i = 0; i < Bw; ++i) {
        float direct = 0;
        for (std::size_t t = 0; t < T; ++t) direct = std::max(direct, l[t * Bw + i]);
        tally.add(direct, e.data.lost[g * Bc + e.m->first_band(g) + i]);
      }
    }
  std::printf(
      "elephant.off: %zu groups, %zu values; the stored loss bounds %.4f of them, the rest by at "
      "most x%.3f\n",
      cm.groups.size(), tally.values, tally.share(), tally.worst);
  EXPECT_GE(tally.share(), 0.95);
  EXPECT_LE(tally.worst, 1.5);
}

// The loss per view cell (the ClusterViews section): each cell's row at most the row over all views,
// which is the largest over the cells; groups hidden from a whole cell lose nothing there; and checked
// as the row over all views is, against direct measurements of every group from 16 random directions
// (6 in the sanitizer run), each against the cell it lies in (the one the cut reads: the nearest cell
// direction). At 42 directions (12 cells) they are not quite a bound.
TEST(ClusterLoss, EachViewCellBoundsDirectMeasurementsFromWithinIt) {
  const Measured& e = elephant();
  const spectra::ClusterMesh cm = e.b.view();
  const std::size_t G = cm.groups.size(), Bc = e.data.bands.size(), Bw = e.m->window_bands(),
                    T = e.m->orientations(), C = e.data.view_directions.size() / 3;
  ASSERT_EQ(C, spectra::kClusterCells);
  ASSERT_EQ(e.data.view_lost.size(), G * C * Bc);
  EXPECT_EQ(e.data.view_samples, 42u);
  std::size_t less = 0;  // (group, band) pairs some cell loses less than half of the row over all views in
  for (std::size_t g = 0; g < G; ++g)
    for (std::size_t j = 0; j < Bc; ++j) {
      float most = 0, least = e.data.lost[g * Bc + j];
      for (std::size_t c = 0; c < C; ++c) {
        const float x = e.data.view_lost[(g * C + c) * Bc + j];
        ASSERT_LE(x, e.data.lost[g * Bc + j]) << g << " " << c << " " << j;
        most = std::max(most, x);
        least = std::min(least, x);
      }
      ASSERT_EQ(most, e.data.lost[g * Bc + j]) << g << " " << j;
      less += least < 0.5f * most;
    }
  EXPECT_GT(less, G * Bc / 4);  // measured: 26 of 60 (group, band) pairs
  std::vector<ProfileView> cells;
  for (std::size_t c = 0; c < C; ++c)
    cells.push_back(spectra::make_view(e.data.view_directions[3 * c], e.data.view_directions[3 * c + 1],
                                       e.data.view_directions[3 * c + 2]));
  std::mt19937 rng(8);
  BoundTally tally;
  for (std::uint32_t g = 0; g < G; ++g)
    for (int k = 0; k < check_directions(); ++k) {
      const ProfileView v = random_view(rng);
      const std::size_t c = spectra::nearest_view(cells, v.direction);
      const std::vector<float> l = e.m->measure(g, v);
      for (std::size_t i = 0; i < Bw; ++i) {
        float direct = 0;
        for (std::size_t t = 0; t < T; ++t) direct = std::max(direct, l[t * Bw + i]);
        tally.add(direct, e.data.view_lost[(g * C + c) * Bc + e.m->first_band(g) + i]);
      }
    }
  std::printf(
      "elephant.off: per view cell, the stored loss bounds %.4f of %zu values, the rest by at most x%.3f\n",
      tally.share(), tally.values, tally.worst);
  // Measured (2026-11-28): 0.90, the rest by at most x1.95 — not a bound at 42 directions, which is
  // why measured_group_loss reads cells only from kMinCellSamples (162) directions.
  EXPECT_GE(tally.share(), 0.85);
}

// Bands coarser than a group's window are its lowest band's value x (f / f_lowest)^2: checked against
// direct measurements in the whole object's window (level 0: bands 2 .. pixels / 4 cycles per
// diameter) of every group of fandisk.off whose own window is smaller, from 4 random directions.
TEST(ClusterLoss, CoarserBandsBoundDirectMeasurementsInTheWholeWindow) {
  const Built b = build("fandisk.off");
  const spectra::Material material;
  const spectra::ClusterLossSettings s = settings(128, 12);
  const spectra::ClusterLossMeasurer m(b.view(), material, s);
  const spectra::ProfileClusterData data = spectra::measure_cluster_loss(b.view(), material, s);
  // From 12 directions, not asked for: no loss per view cell (no ClusterViews section).
  EXPECT_TRUE(data.view_lost.empty() && data.view_directions.empty() && data.view_samples == 0);
  const std::size_t Bc = data.bands.size(), Bw = m.window_bands(), T = m.orientations();
  std::mt19937 rng(9);
  std::size_t groups = 0;
  BoundTally tally;
  for (std::uint32_t g = 0; g < b.h.groups.size(); ++g) {
    if (m.first_band(g) == 0) continue;
    ++groups;
    for (int k = 0; k < 4; ++k) {
      const std::vector<float> l = m.measure(g, random_view(rng), 0);
      for (std::size_t j = 0; j < m.first_band(g) && j < Bw; ++j) {
        float direct = 0;
        for (std::size_t t = 0; t < T; ++t) direct = std::max(direct, l[t * Bw + j]);
        tally.add(direct, data.lost[g * Bc + j]);
      }
    }
  }
  std::printf(
      "fandisk.off: %zu of %zu groups in smaller windows, %zu coarser-band values; the stored loss "
      "bounds %.4f of them, the rest by at most x%.3f\n",
      groups, b.h.groups.size(), tally.values, tally.share(), tally.worst);
  ASSERT_GT(groups, 0u);
  EXPECT_GE(tally.share(), 0.95);
  EXPECT_LE(tally.worst, 1.5);
}

// A profile's Clusters section feeds the cut: measured_group_loss reads it in place for the hierarchy
// it measured (and refuses another), and select_cut's cuts with it are crack-free over random views
// and gazes, and coarser with the gaze far from the object than on it.
TEST(ClusterLoss, TheProfileSectionFeedsACrackFreeCut) {
  const Measured& e = elephant();
  const spectra::ClusterMesh cm = e.b.view();
  spectra::ProfileData d;
  d.levels.push_back({std::uint32_t(e.b.h.finest_triangles()), 0.0f});
  d.views.push_back(spectra::make_view(0, 0, 1));
  d.orientations = {0.0f};
  d.bands = {2.0f};
  d.features = {0.0f};
  std::copy_n(e.m->sphere(), 4, d.sphere);
  d.clusters = e.data;
  const Blob blob = spectra::encode_profile(d);
  Profile p;
  ProfileError error;
  ASSERT_EQ(open_profile(blob.data(), blob.size, &p, &error), ProfileStatus::Ok) << error.message;
  ClusterLoss loss;
  ASSERT_EQ(measured_group_loss(p, cm.clusters, cm.groups, &loss), GroupLossStatus::Measured);
  EXPECT_EQ(loss.lost.data(), p.cluster_lost);  // in place
  EXPECT_EQ(loss.diameter, 2 * e.m->sphere()[3]);
  EXPECT_EQ(loss.bands_cpod.size(), e.data.bands.size());
  {  // another hierarchy: one group's error differs
    std::vector<ClusterGroup> other(cm.groups.begin(), cm.groups.end());
    other.back().error *= 2;
    ClusterLoss untouched;
    EXPECT_EQ(measured_group_loss(p, cm.clusters, other, &untouched), GroupLossStatus::OtherHierarchy);
    EXPECT_TRUE(untouched.lost.empty());
    other.pop_back();
    EXPECT_EQ(measured_group_loss(p, cm.clusters, other, &untouched), GroupLossStatus::OtherHierarchy);
  }
  {  // a profile without the section
    spectra::ProfileData chain = d;
    chain.clusters = {};
    const Blob b = spectra::encode_profile(chain);
    Profile q;
    ASSERT_EQ(open_profile(b.data(), b.size, &q), ProfileStatus::Ok);
    ClusterLoss untouched;
    EXPECT_EQ(measured_group_loss(q, cm.clusters, cm.groups, &untouched), GroupLossStatus::NoSection);
  }

  const std::vector<std::uint32_t> roots = cluster_roots(e.b.h.clusters);
  const ClusterView view{e.b.h.clusters, e.b.h.groups, roots};
  const Edges edges_of = edges(e.b.mesh, e.b.h);
  CrackCheck crack(edges_of);
  std::vector<std::uint8_t> scratch(cm.groups.size());
  std::vector<std::uint32_t> drawn(cm.clusters.size());
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(-1, 1);
  const float radius = e.m->sphere()[3];
  std::size_t coarser = 0;
  for (int i = 0; i < 300; ++i) {
    SchedulerConfig c;
    c.max_objects = 1;
    c.evaluation = Evaluation::Exact;
    c.quality = std::exp2(float(i % 5));  // q = 1 .. 16
    Scheduler s(c);
    Frame f;
    f.gaze[0].direction[0] = 0.4f * u(rng);
    f.gaze[0].direction[1] = 0.4f * u(rng);
    f.gaze[0].direction[2] = -1;
    f.gaze[0].valid = true;
    s.begin_frame(f);
    ObjectTransform t;  // the object ahead, 1.5 .. 300 radii away (log-uniform), turned at random
    const double distance = radius * 1.5 * std::pow(200.0, 0.5 * (1.0 + double(u(rng))));
    t.position[0] = -e.m->sphere()[0];
    t.position[1] = -e.m->sphere()[1];
    t.position[2] = -e.m->sphere()[2] - distance;
    float q[4] = {u(rng), u(rng), u(rng), u(rng)};
    const float n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; ++k) t.rotation[k] = q[k] / n;
    const CutResult r = s.select_cut(view, loss, t, nullptr, scratch, drawn);
    ASSERT_EQ(r.status, CutStatus::Ok);
    const std::span<const std::uint32_t> ids(drawn.data(), r.clusters);
    ASSERT_EQ(crack.first(ids), UINT32_MAX) << "view " << i;
    if (r.triangles < e.b.h.finest_triangles()) ++coarser;
  }
  EXPECT_GT(coarser, 0u);
}
