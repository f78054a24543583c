// Profiling speed against prediction error. A 100k-triangle, 6-level chain (armadillo, refined
// once by OpenSubdiv and decimated to 100k, then halved five times) is profiled with several
// settings; each profile then predicts the lost contrast at random new views, against a direct
// render-and-analyze at exactly those views. Error is measured on what decisions use: each level's
// switching distance (design: ProfileSettings::view_tolerance). Two prediction schemes are
// compared: the nearest stored view (the scheduler's ViewBlend::Nearest) and the maximum over the
// three nearest (ViewBlend::Max3). Run: build/bench/bench_profile [MESH_DIR] [random views]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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
};

struct ErrorStats {
  double median, p95, worst, optimistic;
};

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

  const Setting settings[] = {
      {"default (adaptive views, 256 px, 8 orientations, all bands)", 0, 256, 8, 0},
      {"6 views", 6, 256, 8, 0},
      {"12 views", 12, 256, 8, 0},
      {"42 views", 42, 256, 8, 0},
      {"128 px", 0, 128, 8, 0},
      {"4 orientations", 0, 256, 4, 0},
      {"4 bands", 0, 256, 8, 4},
  };
  std::printf(
      "| setting | views kept | profile time [s] | size [bytes] | nearest: median / p95 / worst error | "
      "nearest: optimistic | max of 3: median / p95 / worst | max of 3: optimistic |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const Setting& s : settings) {
    ProfileSettings ps;
    ps.views = s.views;
    ps.render.pixels = s.pixels;
    ps.analysis.orientations = s.orientations;
    ps.analysis.bands = s.bands;
    ProfileReport report;
    const ProfileData profile = build_profile(levels, Material{}, ps, {}, &report);
    const std::size_t size = encode_profile(profile).size;
    // Ground truth at the probes with the same analysis settings.
    const ProfileMeasurer measurer(levels, Material{}, ps);
    const std::size_t K = levels.size(), T = profile.orientations.size(), B = profile.bands.size(),
                      V = profile.views.size();
    std::vector<double> near_logs, max_logs;
    std::size_t near_opt = 0, max_opt = 0;
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
        const double t = truth.switching[k - 1];
        const double n = switching_angle(lost_at(order[0].second), T, profile.bands);
        const double m = switching_angle(worst.data(), T, profile.bands);
        near_logs.push_back(std::abs(std::log(n / t)));
        max_logs.push_back(std::abs(std::log(m / t)));
        near_opt += n > t * 1.0001;
        max_opt += m > t * 1.0001;
      }
    }
    const ErrorStats a = stats(near_logs, near_opt), b = stats(max_logs, max_opt);
    std::printf(
        "| %s | %u of %u | %.2f | %zu | %.1f%% / %.1f%% / %.1f%% | %.0f%% | %.1f%% / %.1f%% / %.1f%% | "
        "%.0f%% |\n",
        s.name, report.views_kept, report.views_measured, report.seconds, size, 100 * a.median, 100 * a.p95,
        100 * a.worst, 100 * a.optimistic, 100 * b.median, 100 * b.p95, 100 * b.worst, 100 * b.optimistic);
    std::fflush(stdout);
  }
}
