#include "acuity/spectra/profile_builder.hpp"

#include "acuity/models.hpp"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace acuity::spectra {

SphereMesh icosphere(int subdivisions) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  SphereMesh m;
  m.positions = {-1, t,  0,  1, t, 0,  -1, -t, 0,  1, -t, 0, 0,  -1, t,  0,  1, t,
                 0,  -1, -t, 0, 1, -t, t,  0,  -1, t, 0,  1, -t, 0,  -1, -t, 0, 1};
  m.indices = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
               4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
               6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  auto& p = m.positions;
  auto normalize = [&](std::size_t i) {
    const float n =
        std::sqrt(p[3 * i] * p[3 * i] + p[3 * i + 1] * p[3 * i + 1] + p[3 * i + 2] * p[3 * i + 2]);
    for (int k = 0; k < 3; ++k) p[3 * i + k] /= n;
  };
  for (std::size_t i = 0; i < 12; ++i) normalize(i);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      const auto i = static_cast<std::uint32_t>(p.size() / 3);
      for (int k = 0; k < 3; ++k) p.push_back(0.5f * (p[3 * a + k] + p[3 * b + k]));
      normalize(i);
      return mid[key] = i;
    };
    std::vector<std::uint32_t> g;
    for (std::size_t i = 0; i < m.indices.size(); i += 3) {
      const std::uint32_t a = m.indices[i], b = m.indices[i + 1], c = m.indices[i + 2];
      const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      for (std::uint32_t x : {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca}) g.push_back(x);
    }
    m.indices = std::move(g);
  }
  return m;
}

std::vector<ProfileView> fibonacci_views(std::uint32_t count) {
  std::vector<ProfileView> out;
  const float golden = 3.14159265f * (3.0f - std::sqrt(5.0f));
  for (std::uint32_t i = 0; i < count; ++i) {
    const float z = count == 1 ? 1.0f : 1.0f - 2.0f * (float(i) + 0.5f) / float(count);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), a = golden * float(i);
    out.push_back(make_view(r * std::cos(a), z, r * std::sin(a)));
  }
  return out;
}

ProfileMeasurer::ProfileMeasurer(const std::vector<LevelInput>& levels, const Material& material,
                                 const ProfileSettings& settings)
    : levels_(levels),
      material_(material),
      render_(settings.render),
      analysis_(settings.analysis),
      analyzer_(settings.render.pixels, settings.analysis) {
  if (levels_.empty()) throw std::invalid_argument("profile: no levels");
  bounding_sphere(levels_[0].mesh, render_.sphere);  // every level is framed by level 0's sphere
  if (!(render_.sphere[3] > 0) || !std::isfinite(render_.sphere[3]))
    throw std::invalid_argument("profile: level 0 has no extent (empty, a point, or non-finite)");
}

ViewMeasurement ProfileMeasurer::measure(const ProfileView& view) const {
  const std::size_t K = levels_.size(), T = analyzer_.orientation_count(), B = analyzer_.band_count();
  ViewMeasurement m;
  m.lost.assign((K - 1) * T * B, 0.0f);
  const Image reference = render_snapshot(levels_[0].mesh, material_, view, render_);
  m.features = reddy_features(reference, analysis_);
  const auto prepared = analyzer_.prepare(reference);
  for (std::size_t k = 1; k < K; ++k) {
    const Image image = render_snapshot(levels_[k].mesh, material_, view, render_);
    analyzer_.measure(image, *prepared, &m.lost[(k - 1) * T * B]);
    m.switching.push_back(switching_angle(&m.lost[(k - 1) * T * B], T, analyzer_.bands()));
    const std::vector<float> f = reddy_features(image, analysis_);
    m.features.insert(m.features.end(), f.begin(), f.end());
  }
  return m;
}

float switching_angle(const float* lost, std::size_t orientations, const std::vector<float>& bands) {
  const std::size_t B = bands.size();
  std::vector<double> peak(B, 0.0);  // a still object's thresholds do not depend on orientation
  for (std::size_t t = 0; t < orientations; ++t)
    for (std::size_t b = 0; b < B; ++b) peak[b] = std::max(peak[b], double(lost[t * B + b]));
  auto score = [&](double theta) {  // falls as theta shrinks: thresholds rise with frequency
    double s = 0;
    for (std::size_t b = 0; b < B; ++b)
      s = std::max(s, peak[b] / threshold(double(bands[b]) / theta, 0.0, 0.0));
    return s;
  };
  constexpr double kSmallest = 1e-4, kLargest = 180.0;
  if (score(kLargest) <= 1) return float(kLargest);
  if (score(kSmallest) > 1) return float(kSmallest);
  double lo = std::log(kSmallest), hi = std::log(kLargest);
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (score(std::exp(mid)) > 1 ? hi : lo) = mid;
  }
  return float(std::exp(0.5 * (lo + hi)));
}

float view_difference(const ViewMeasurement& a, const ViewMeasurement& b) {
  float worst = 0;
  for (std::size_t k = 0; k < a.switching.size(); ++k)
    worst = std::max(worst, std::abs(std::log(a.switching[k] / b.switching[k])));
  return worst;
}

namespace {
float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Index (into `kept`) of the kept view nearest to direction d, skipping `skip`.
std::size_t nearest(const std::vector<ProfileView>& views, const std::vector<std::size_t>& kept,
                    const float* d, std::size_t skip) {
  std::size_t best = kept.size();
  float best_dot = -2;
  for (std::size_t j = 0; j < kept.size(); ++j) {
    if (kept[j] == skip) continue;
    const float x = dot3(views[kept[j]].direction, d);
    if (x > best_dot) {
      best_dot = x;
      best = j;
    }
  }
  return best;
}

// The largest difference between any measured view and its nearest kept view (itself excluded
// when `leave_one_out`).
float prediction_error(const std::vector<ProfileView>& views, const std::vector<ViewMeasurement>& data,
                       const std::vector<std::size_t>& kept, bool leave_one_out) {
  float worst = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const std::size_t j = nearest(views, kept, views[v].direction, leave_one_out ? v : views.size());
    if (j == kept.size()) continue;
    worst = std::max(worst, view_difference(data[v], data[kept[j]]));
  }
  return worst;
}
}  // namespace

ProfileData build_profile(const std::vector<LevelInput>& levels, const Material& material,
                          const ProfileSettings& settings, const ProgressFn& progress,
                          ProfileReport* report) {
  const auto start = std::chrono::steady_clock::now();
  const ProfileMeasurer measurer(levels, material, settings);
  const unsigned jobs = settings.jobs ? settings.jobs : std::max(1u, std::thread::hardware_concurrency());
  oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, jobs);

  std::vector<ProfileView> views;
  std::vector<ViewMeasurement> data;
  std::mutex progress_mutex;
  std::size_t done = 0;
  auto measure_new = [&](std::size_t total) {  // measures views[data.size() ..) in parallel
    const std::size_t first = data.size();
    data.resize(views.size());
    oneapi::tbb::parallel_for(first, views.size(), [&](std::size_t v) {
      data[v] = measurer.measure(views[v]);
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress("views", ++done, total);
      }
    });
  };

  const float tolerance = std::log1p(std::max(0.0f, settings.view_tolerance));  // in log distance
  std::vector<std::size_t> kept;
  if (settings.views > 0) {
    views = fibonacci_views(settings.views);
    measure_new(views.size());
  } else {
    // Nested icosphere vertex sets: 12, 42, 162.
    const SphereMesh ico = icosphere(2);
    std::size_t count = 12;
    while (true) {
      for (std::size_t v = views.size(); v < count; ++v)
        views.push_back(make_view(ico.positions[3 * v], ico.positions[3 * v + 1], ico.positions[3 * v + 2]));
      measure_new(count);
      std::vector<std::size_t> all(views.size());
      for (std::size_t v = 0; v < all.size(); ++v) all[v] = v;
      const float loo = prediction_error(views, data, all, true);
      const std::size_t next = count == 12 ? 42 : 162;
      if (loo <= tolerance || next > settings.max_views || count == 162) break;
      count = next;
    }
  }
  for (std::size_t v = 0; v < views.size(); ++v) kept.push_back(v);

  // Prune: drop views (last first) while every measured view keeps a close enough predictor.
  if (settings.views == 0 && settings.prune) {
    for (std::size_t i = views.size(); i-- > 0 && kept.size() > 1;) {
      std::vector<std::size_t> trial;
      for (std::size_t v : kept)
        if (v != i) trial.push_back(v);
      if (prediction_error(views, data, trial, false) <= tolerance) kept = trial;
    }
  }

  ProfileData out;
  std::copy(measurer.sphere(), measurer.sphere() + 4, out.sphere);
  out.snapshot_pixels = settings.render.pixels;
  for (const LevelInput& l : levels)
    out.levels.push_back(
        {l.triangles ? l.triangles : static_cast<std::uint32_t>(l.mesh.index_count / 3), l.geometric_error});
  out.orientations = orientation_angles(settings.analysis);
  out.bands = measurer.analyzer().bands();
  const std::size_t K = levels.size(), T = out.orientations.size(), B = out.bands.size();
  out.lost.resize((K - 1) * kept.size() * T * B);
  out.features.resize(K * kept.size() * T);
  for (std::size_t j = 0; j < kept.size(); ++j) {
    const ViewMeasurement& m = data[kept[j]];
    out.views.push_back(views[kept[j]]);
    for (std::size_t k = 1; k < K; ++k)
      std::copy_n(&m.lost[(k - 1) * T * B], T * B, &out.lost[((k - 1) * kept.size() + j) * T * B]);
    for (std::size_t k = 0; k < K; ++k)
      std::copy_n(&m.features[k * T], T, &out.features[(k * kept.size() + j) * T]);
  }
  if (report) {
    report->views_measured = static_cast<std::uint32_t>(views.size());
    report->views_kept = static_cast<std::uint32_t>(kept.size());
    report->prediction_error = std::exp(prediction_error(views, data, kept, false)) - 1.0f;
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace acuity::spectra
