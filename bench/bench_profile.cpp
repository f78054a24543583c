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
  std::vector<double> logs;      // |ln(predicted / direct)| switching angles
  std::vector<double> ratios;    // direct / predicted switching angle
  std::size_t optimistic = 0;    // predicted switches later than direct
  std::size_t optimistic10 = 0;  // predicted score at the direct switching angle < 1 / 1.1

  void add(const float* lost, std::size_t T, const std::vector<float>& bands, double direct) {
    const double p = switching_angle(lost, T, bands);
    logs.push_back(std::abs(std::log(p / direct)));
    ratios.push_back(direct / p);
    optimistic += p > direct * 1.0001;
    // The direct score is 1 at its switching angle (180 deg: never visible; 1e-4: always).
    const double at = std::clamp(direct, 1e-4, 180.0);
    optimistic10 += direct < 180.0 && still_score(lost, T, bands, at) < 1.0 / 1.1;
  }
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
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
}
