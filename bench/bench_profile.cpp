// Profiling speed against prediction error. A 100k-triangle, 6-level chain (armadillo, refined
// once by OpenSubdiv and decimated to 100k, then halved five times) is profiled with several
// settings; each profile then predicts the lost contrast at random new views, against a direct
// render-and-analyze at exactly those views. Error is measured on what decisions use: each level's
// switching distance (design: ProfileSettings::view_tolerance). Two prediction schemes are
// compared: the nearest stored view (the scheduler's ViewBlend::Nearest) and the maximum over the
// three nearest (ViewBlend::Max3). Bounds (ProfileSettings::bound_cells) are measured by how often
// the profile's score at the direct switching angle falls below 1 / 1.1 (the direct score there is
// 1): a prediction optimistic by more than 10%, and by the median ratio of the direct switching
// angle to the predicted one (> 1: conservative; what the bound costs in switching distance).
// Run: build/bench/bench_profile [MESH_DIR] [random views] [all: every setting; else the first 3]
// (docs/spectra.md holds its output as a figure: scripts/regenerate_docs.py --only profile-bench)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <string>

#include "acuity/lodgen/decimate.hpp"
#include "acuity/lodgen/refine.hpp"
#include "acuity/spectra/profile_builder.hpp"

using namespace acuity;
using namespace acuity::spectra;

namespace {

struct Setting {
  const char* name;
  std::uint32_t views, pixels, orientations, bands;
  bool bound;
  std::uint32_t bound_views;
};

struct ErrorStats {
  double median, p95, worst, optimistic;
};

// One prediction scheme's record over levels and probes.
struct Scheme {
  std::vector<double> logs;               // |ln(predicted / direct)| switching angles
  std::vector<double> ratios;             // direct / predicted switching angle
  std::size_t optimistic = 0;             // predicted switches later than direct
  std::size_t optimistic10 = 0;           // predicted score at the direct switching angle < 1 / 1.1
  std::vector<double> predicted, direct;  // switching angles, K - 1 per probe

  void add(const float* lost, std::size_t T, const std::vector<float>& bands, double truth) {
    const double p = switching_angle(lost, T, bands);
    predicted.push_back(p);
    direct.push_back(truth);
    logs.push_back(std::abs(std::log(p / truth)));
    ratios.push_back(truth / p);
    optimistic += p > truth * 1.0001;
    // The direct score is 1 at its switching angle (180 deg: never visible; 1e-4: always).
    const double at = std::clamp(truth, 1e-4, 180.0);
    optimistic10 += truth < 180.0 && still_score(lost, T, bands, at) < 1.0 / 1.1;
  }
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Decisions at the probes for a still object at the fovea, sizes log-uniform over [lo, hi] deg:
// the rule takes the coarsest level k whose predicted switching angle is at least the size; the
// exact-view check calls it visible when the size exceeds k's direct switching angle. Returns the
// visible share and the mean triangles relative to the exact view's own choice (the oracle).
std::pair<double, double> decide(const Scheme& s, const std::vector<ProfileLevel>& levels, double lo,
                                 double hi) {
  const std::size_t L = levels.size() - 1;
  constexpr int kSizes = 64;
  std::size_t visible = 0, decisions = 0;
  double triangles = 0, oracle = 0;
  for (std::size_t at = 0; at + L <= s.predicted.size(); at += L)
    for (int i = 0; i < kSizes; ++i) {
      const double size = lo * std::pow(hi / lo, (i + 0.5) / kSizes);
      std::size_t rule = 0, best = 0;
      for (std::size_t k = 1; k <= L; ++k) {
        if (size <= s.predicted[at + k - 1]) rule = k;
        if (size <= s.direct[at + k - 1]) best = k;
      }
      visible += rule > 0 && size > s.direct[at + rule - 1];
      triangles += levels[rule].triangles;
      oracle += levels[best].triangles;
      ++decisions;
    }
  return {double(visible) / double(decisions), triangles / oracle};
}

// [half the smallest, twice the largest] median direct switching angle over the levels [deg].
std::pair<double, double> size_range(const Scheme& s, std::size_t L) {
  double lo = 180, hi = 1e-4;
  for (std::size_t k = 0; k < L; ++k) {
    std::vector<double> v;
    for (std::size_t at = k; at < s.direct.size(); at += L) v.push_back(s.direct[at]);
    lo = std::min(lo, median(v));
    hi = std::max(hi, median(v));
  }
  return {0.5 * lo, 2 * hi};
}

// |ln(predicted / direct)| of switching angles over levels and views; `optimistic` is the share of
// predictions that switch later (a larger angle) than the truth: a visible loss let through.
ErrorStats stats(std::vector<double> logs, std::size_t optimistic) {
  std::sort(logs.begin(), logs.end());
  const auto at = [&](double q) { return std::exp(logs[std::size_t(q * double(logs.size() - 1))]) - 1; };
  return {at(0.5), at(0.95), std::exp(logs.back()) - 1, double(optimistic) / double(logs.size())};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "build/cgal-data/data/meshes";
  const int random_views = argc > 2 ? std::atoi(argv[2]) : 24;
  // The chain.
  const lodgen::Mesh refined =
      lodgen::refine(lodgen::to_polygons(lodgen::load_mesh(dir + "/armadillo.off")), 1)[0];
  std::vector<lodgen::Mesh> meshes = {lodgen::decimate(refined, 100000)};
  for (int k = 1; k < 6; ++k) meshes.push_back(lodgen::decimate(meshes[0], meshes[0].triangle_count() >> k));
  std::vector<LevelInput> levels;
  for (const auto& m : meshes) {
    LevelInput l;
    l.mesh = {m.positions.data(), m.vertex_count(), m.indices.data(),
              m.indices.size(),   m.normals.data(), nullptr};
    levels.push_back(l);
  }
  std::printf("chain: armadillo refined and decimated; triangles");
  for (const auto& m : meshes) std::printf(" %zu", m.triangle_count());
  std::printf("\n\n");

  std::mt19937 rng(7);
  std::normal_distribution<float> normal;
  std::vector<ProfileView> probes;
  for (int i = 0; i < random_views; ++i) probes.push_back(make_view(normal(rng), normal(rng), normal(rng)));

  const bool all = argc > 3 && std::string(argv[3]) == "all";
  const Setting settings[] = {
      {"before: adaptive views, own measurement (bound_cells = false)", 0, 256, 8, 0, false, 0},
      {"default: adaptive views, cell bounds", 0, 256, 8, 0, true, 0},
      {"cell bounds, refined to 48 views", 0, 256, 8, 0, true, 48},
      {"6 views", 6, 256, 8, 0, false, 0},
      {"12 views", 12, 256, 8, 0, false, 0},
      {"42 views", 42, 256, 8, 0, false, 0},
      {"128 px", 0, 128, 8, 0, false, 0},
      {"128 px, cell bounds", 0, 128, 8, 0, true, 0},
      {"4 orientations", 0, 256, 4, 0, false, 0},
      {"4 bands", 0, 256, 8, 4, false, 0},
  };
  std::printf(
      "| setting | views kept | directions measured | profile time [s] | CPU time [s] | size [bytes] | bound "
      "pessimism (median) "
      "| nearest: median / p95 / worst error | nearest: optimistic | nearest: optimistic > 10%% | nearest: "
      "median direct / predicted | max of 3: median / p95 / worst | max of 3: optimistic | max of 3: "
      "optimistic > 10%% |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  struct Decision {
    const char* name;
    double lo, hi, near_visible, near_triangles, max_visible, max_triangles, cpu, near_optimistic10;
  };
  std::vector<Decision> decisions;
  for (const Setting& s : settings) {
    if (!all && &s - settings >= 3) continue;  // the bounds' settings only
    ProfileSettings ps;
    ps.views = s.views;
    ps.render.pixels = s.pixels;
    ps.analysis.orientations = s.orientations;
    ps.analysis.bands = s.bands;
    ps.bound_cells = s.bound;
    ps.bound_views = s.bound_views;
    ProfileReport report;
    const std::clock_t cpu_start = std::clock();  // process CPU time: less sensitive to a shared machine
    const ProfileData profile = build_profile(levels, Material{}, ps, {}, &report);
    const double cpu = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    const std::size_t size = encode_profile(profile).size;
    // Ground truth at the probes with the same analysis settings.
    const ProfileMeasurer measurer(levels, Material{}, ps);
    const std::size_t K = levels.size(), T = profile.orientations.size(), B = profile.bands.size(),
                      V = profile.views.size();
    Scheme nearest, max3;
    for (const ProfileView& probe : probes) {
      const ViewMeasurement truth = measurer.measure(probe);
      std::vector<std::pair<float, std::size_t>> order;
      for (std::size_t v = 0; v < V; ++v) {
        const float* d = profile.views[v].direction;
        order.push_back(
            {-(d[0] * probe.direction[0] + d[1] * probe.direction[1] + d[2] * probe.direction[2]), v});
      }
      std::sort(order.begin(), order.end());
      for (std::size_t k = 1; k < K; ++k) {
        auto lost_at = [&](std::size_t v) { return &profile.lost[((k - 1) * V + v) * T * B]; };
        std::vector<float> worst(T * B, 0.0f);
        for (std::size_t j = 0; j < std::min<std::size_t>(3, V); ++j)
          for (std::size_t i = 0; i < T * B; ++i) worst[i] = std::max(worst[i], lost_at(order[j].second)[i]);
        nearest.add(lost_at(order[0].second), T, profile.bands, truth.switching[k - 1]);
        max3.add(worst.data(), T, profile.bands, truth.switching[k - 1]);
      }
    }
    const ErrorStats a = stats(nearest.logs, nearest.optimistic), b = stats(max3.logs, max3.optimistic);
    const double n = double(nearest.logs.size());
    const auto [lo, hi] = size_range(nearest, K - 1);
    const auto dn = decide(nearest, profile.levels, lo, hi), dm = decide(max3, profile.levels, lo, hi);
    decisions.push_back(
        {s.name, lo, hi, dn.first, dn.second, dm.first, dm.second, cpu, double(nearest.optimistic10) / n});
    std::printf(
        "| %s | %u | %u | %.2f | %.1f | %zu | %.1f%% | %.1f%% / %.1f%% / %.1f%% | %.0f%% | %.1f%% | %.2f | "
        "%.1f%% / %.1f%% / "
        "%.1f%% | %.0f%% | %.1f%% |\n",
        s.name, report.views_kept, report.views_sampled, report.seconds, cpu, size,
        100 * report.bound_pessimism, 100 * a.median, 100 * a.p95, 100 * a.worst, 100 * a.optimistic,
        100 * double(nearest.optimistic10) / n, median(nearest.ratios), 100 * b.median, 100 * b.p95,
        100 * b.worst, 100 * b.optimistic, 100 * double(max3.optimistic10) / n);
    std::fflush(stdout);
  }
  std::printf(
      "\nDecisions (still object, fovea, q = 1) at the probes, sizes log-uniform over [half the smallest, "
      "twice the largest] median direct switching angle:\n\n"
      "| setting | sizes [deg] | nearest: visible by the exact-view check | nearest: triangles / exact "
      "view's "
      "choice | max of 3: visible | max of 3: triangles / exact view's |\n|---|---|---|---|---|---|\n");
  for (const Decision& d : decisions)
    std::printf("| %s | %.2f-%.1f | %.1f%% | %.3f | %.1f%% | %.3f |\n", d.name, d.lo, d.hi,
                100 * d.near_visible, d.near_triangles, 100 * d.max_visible, d.max_triangles);
  if (decisions.size() >= 2) {  // the first two settings: without and with cell bounds
    const Decision &before = decisions[0], &bounded = decisions[1];
    std::printf(
        "\nNearest view, %s -> %s: predictions optimistic > 10%% %.1f%% -> %.1f%%, decisions visible by "
        "the exact-view check %.1f%% -> %.1f%%, triangles / exact view's %.3f -> %.3f (%+.1f%%), profiling "
        "CPU time %.1fx.\n",
        before.name, bounded.name, 100 * before.near_optimistic10, 100 * bounded.near_optimistic10,
        100 * before.near_visible, 100 * bounded.near_visible, before.near_triangles, bounded.near_triangles,
        100 * (bounded.near_triangles / before.near_triangles - 1), bounded.cpu / before.cpu);
  }
}
