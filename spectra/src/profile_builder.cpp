#include "acuity/spectra/profile_builder.hpp"

#include "acuity/models.hpp"
#include "thread_limit.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

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

ViewMeasurement ProfileMeasurer::measure(const ProfileView& view, bool features) const {
  const std::size_t K = levels_.size(), T = analyzer_.orientation_count(), B = analyzer_.band_count();
  ViewMeasurement m;
  m.lost.assign((K - 1) * T * B, 0.0f);
  m.area.assign((K - 1) * T * B, 0.0f);
  m.offset.assign((K - 1) * T * B, 0.0f);
  m.turn.assign((K - 1) * T * B, 0.0f);
  m.pooled.assign((K - 1) * B, 0.0f);
  m.pooled_area.assign((K - 1) * B, 0.0f);
  const Image reference = render_snapshot(levels_[0].mesh, material_, view, render_);
  if (features) m.features = reddy_features(reference, analysis_);
  const auto prepared = analyzer_.prepare(reference);
  for (std::size_t k = 1; k < K; ++k) {
    const Image image = render_snapshot(levels_[k].mesh, material_, view, render_);
    analyzer_.measure(image, *prepared, &m.lost[(k - 1) * T * B], &m.area[(k - 1) * T * B],
                      &m.offset[(k - 1) * T * B], &m.turn[(k - 1) * T * B], &m.pooled[(k - 1) * B],
                      &m.pooled_area[(k - 1) * B]);
    m.switching.push_back(switching_angle(&m.lost[(k - 1) * T * B], T, analyzer_.bands()));
    if (!features) continue;
    const std::vector<float> f = reddy_features(image, analysis_);
    m.features.insert(m.features.end(), f.begin(), f.end());
  }
  return m;
}

float still_score(const float* lost, std::size_t orientations, const std::vector<float>& bands,
                  double angle) {
  double s = 0;  // a still object's thresholds do not depend on orientation
  for (std::size_t b = 0; b < bands.size(); ++b) {
    float peak = 0;
    for (std::size_t t = 0; t < orientations; ++t) peak = std::max(peak, lost[t * bands.size() + b]);
    s = std::max(s, double(peak) / threshold(double(bands[b]) / angle, 0.0, 0.0));
  }
  return float(s);
}

float switching_angle(const float* lost, std::size_t orientations, const std::vector<float>& bands) {
  auto score = [&](double theta) {  // falls as theta shrinks: thresholds rise with frequency
    return still_score(lost, orientations, bands, theta);
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

std::vector<ProfileView> bound_sample_views() {
  const SphereMesh ico = icosphere(2);
  std::vector<ProfileView> out;
  for (std::size_t v = 0; v < ico.positions.size() / 3; ++v)
    out.push_back(make_view(ico.positions[3 * v], ico.positions[3 * v + 1], ico.positions[3 * v + 2]));
  return out;
}

// Calls visit(t, i) for each orientation i of view `from` whose channel lies within orientation t of
// view `to` (T orientations over 180 deg; the frames differ by a roll about the direction): the one
// or two nearest, or every orientation where `to`'s up lies along `from`'s direction.
template <class Visit>
void in_frame(const ProfileView& from, const ProfileView& to, std::size_t T, Visit visit) {
  const float* d = from.direction;
  const float along = to.up[0] * d[0] + to.up[1] * d[1] + to.up[2] * d[2];
  const float u[3] = {to.up[0] - along * d[0], to.up[1] - along * d[1], to.up[2] - along * d[2]};
  const float* f = from.up;
  const float right[3] = {f[1] * d[2] - f[2] * d[1], f[2] * d[0] - f[0] * d[2],
                          f[0] * d[1] - f[1] * d[0]};  // -direction x up
  const double x = u[0] * right[0] + u[1] * right[1] + u[2] * right[2];
  const double y = u[0] * f[0] + u[1] * f[1] + u[2] * f[2];
  if (x * x + y * y < 1e-6) {  // no common frame: every orientation
    for (std::size_t t = 0; t < T; ++t)
      for (std::size_t i = 0; i < T; ++i) visit(t, i);
    return;
  }
  // `to`'s orientation a [deg] is `from`'s a + delta: `to`'s up (90 deg) lies at atan2(y, x) in `from`.
  const double delta = std::atan2(y, x) * 180.0 / 3.14159265358979 - 90.0, step = 180.0 / double(T);
  for (std::size_t t = 0; t < T; ++t) {
    double p = std::fmod(double(t) + delta / step, double(T));
    if (p < 0) p += double(T);
    const auto i0 = static_cast<std::size_t>(p) % T, i1 = (i0 + 1) % T;
    const double frac = p - std::floor(p);
    if (frac <= 1 - 1e-3) visit(t, i0);
    if (frac >= 1e-3) visit(t, i1);
  }
}

void max_in_frame(const float* lost, const ProfileView& from, const ProfileView& to, std::size_t orientations,
                  std::size_t bands, float* out) {
  const std::size_t B = bands;
  in_frame(from, to, orientations, [&](std::size_t t, std::size_t i) {
    for (std::size_t b = 0; b < B; ++b) out[t * B + b] = std::max(out[t * B + b], lost[i * B + b]);
  });
}

std::size_t nearest_view(const std::vector<ProfileView>& views, const float* d) {
  std::size_t best = 0;
  float best_dot = -2;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const float* w = views[v].direction;
    const float x = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
    if (x > best_dot) {
      best_dot = x;
      best = v;
    }
  }
  return best;
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

// A sample within this angle [rad] of a cell's border counts for both cells: the runtime's lookup
// is nearest-first among candidates tabulated per cube-map cell, close to but not exactly nearest.
constexpr float kBorderMargin = 2.0f * 3.14159265f / 180.0f;

float angle_between(const float* a, const float* b) { return std::acos(std::clamp(dot3(a, b), -1.0f, 1.0f)); }

}  // namespace

std::vector<std::vector<std::size_t>> view_cells(const std::vector<ProfileView>& views,
                                                 const std::vector<std::size_t>& kept) {
  std::vector<std::vector<std::size_t>> out(kept.size());
  std::vector<float> angles(kept.size());
  for (std::size_t s = 0; s < views.size(); ++s) {
    for (std::size_t j = 0; j < kept.size(); ++j)
      angles[j] = angle_between(views[s].direction, views[kept[j]].direction);
    const float nearest_angle = *std::min_element(angles.begin(), angles.end());
    for (std::size_t j = 0; j < kept.size(); ++j)
      if (angles[j] <= nearest_angle + kBorderMargin) out[j].push_back(s);
  }
  return out;
}

namespace {

// The bound of one cell: per level, orientation and band the largest lost contrast over its
// members, in the frame of view `v`.
std::vector<float> cell_bound(const std::vector<ProfileView>& views, const std::vector<ViewMeasurement>& data,
                              std::size_t v, const std::vector<std::size_t>& members, std::size_t T,
                              std::size_t B) {
  std::vector<float> out = data[v].lost;
  const std::size_t levels = out.size() / (T * B);
  for (std::size_t s : members)
    if (s != v)
      for (std::size_t k = 0; k < levels; ++k)
        max_in_frame(&data[s].lost[k * T * B], views[s], views[v], T, B, &out[k * T * B]);
  return out;
}

struct BoundState {
  std::vector<std::vector<std::size_t>> members;  // per kept view
  std::vector<std::vector<float>> lost;           // per kept view: [(K-1) T B]
  std::vector<std::vector<float>> switching;      // per kept view: [K-1]
};

// The Detail entries of kept view v ([(K-1) T B]): without cell bounds its own measurement's area,
// frequency and orientation. With cell bounds the entry's loss L (`bound`) is the largest over the
// cell's members, and its area is the largest loss energy over them (c^2 a: a member's lost contrast
// squared times its extent, each channel in the frame of v as for the loss) over L^2. That pair
// bounds every member under Rovamo's area law, whose squared threshold factor 1 + A_c / A is affine
// in 1 / A: c^2 (1 + x / a) <= L^2 (1 + x / a*) for every x >= 0 when c <= L and c^2 a <= L^2 a*.
// (The largest area over the members, as before, bounds them too but weighs a weak loss's extent
// like the strongest's.) Frequency and orientation are the centres' (offset and turn 0).
std::vector<ProfileDetail> view_detail(const std::vector<ProfileView>& views,
                                       const std::vector<ViewMeasurement>& data, std::size_t v,
                                       const std::vector<std::size_t>* members,
                                       const std::vector<float>* bound, std::size_t T, std::size_t B) {
  const ViewMeasurement& own = data[v];
  std::vector<ProfileDetail> out(own.lost.size());
  if (!members) {
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = encode_detail(own.area[i], own.offset[i], own.turn[i]);
    return out;
  }
  std::vector<double> energy(own.lost.size());  // the largest c^2 a per entry, in v's frame
  for (std::size_t i = 0; i < energy.size(); ++i) energy[i] = double(own.lost[i]) * own.lost[i] * own.area[i];
  for (std::size_t s : *members) {
    if (s == v) continue;
    for (std::size_t k = 0; k < own.lost.size() / (T * B); ++k) {
      const float* lost = &data[s].lost[k * T * B];
      const float* area = &data[s].area[k * T * B];
      double* to = &energy[k * T * B];
      in_frame(views[s], views[v], T, [&](std::size_t t, std::size_t i) {
        for (std::size_t b = 0; b < B; ++b)
          to[t * B + b] =
              std::max(to[t * B + b], double(lost[i * B + b]) * lost[i * B + b] * area[i * B + b]);
      });
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double l = (*bound)[i];
    out[i] = encode_detail(l > 0 ? float(std::min(1.0, energy[i] / (l * l))) : 0.0f, 0.0f, 0.0f);
  }
  return out;
}

// The Pooled entries of kept view v ([(K-1) B]): its own pooled loss and extent, or with cell bounds
// (`members`) the largest pooled loss L over the cell and the largest energy c^2 a over it divided by
// L^2 (pooled over orientations, the loss has no frame: no roll to match). That pair bounds every
// member under the area law, as view_detail()'s does.
std::vector<ProfilePooled> view_pooled(const std::vector<ViewMeasurement>& data, std::size_t v,
                                       const std::vector<std::size_t>* members) {
  const ViewMeasurement& own = data[v];
  std::vector<ProfilePooled> out(own.pooled.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    double top = own.pooled[i], energy = double(own.pooled[i]) * own.pooled[i] * own.pooled_area[i];
    if (members)
      for (std::size_t s : *members) {
        const double l = data[s].pooled[i];
        top = std::max(top, l);
        energy = std::max(energy, l * l * data[s].pooled_area[i]);
      }
    out[i] = encode_pooled(float(top), top > 0 ? float(std::min(1.0, energy / (top * top))) : 0.0f);
  }
  return out;
}

BoundState bound_state(const std::vector<ProfileView>& views, const std::vector<ViewMeasurement>& data,
                       const std::vector<std::size_t>& kept, const std::vector<float>& bands, std::size_t T) {
  const std::size_t B = bands.size();
  BoundState st;
  st.members = view_cells(views, kept);
  for (std::size_t j = 0; j < kept.size(); ++j) {
    st.lost.push_back(cell_bound(views, data, kept[j], st.members[j], T, B));
    std::vector<float> sw;
    for (std::size_t k = 0; k < st.lost[j].size() / (T * B); ++k)
      sw.push_back(switching_angle(&st.lost[j][k * T * B], T, bands));
    st.switching.push_back(std::move(sw));
  }
  return st;
}

// How much earlier [ln of the switching angles' ratio] the bound of cell j switches than member s,
// averaged over the levels.
float pessimism(const BoundState& st, const std::vector<ViewMeasurement>& data, std::size_t j,
                std::size_t s) {
  const std::vector<float>& own = data[s].switching;
  if (own.empty()) return 0;
  double sum = 0;
  for (std::size_t k = 0; k < own.size(); ++k)
    sum += std::max(0.0, std::log(double(own[k]) / st.switching[j][k]));
  return float(sum / double(own.size()));
}

// Mean pessimism over every cell's members (the cost of the bound in decisions).
double total_pessimism(const BoundState& st, const std::vector<ViewMeasurement>& data) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t j = 0; j < st.members.size(); ++j)
    for (std::size_t s : st.members[j]) {
      sum += pessimism(st, data, j, s);
      ++n;
    }
  return n ? sum / double(n) : 0.0;
}

// Adds kept views (from the measured directions) while some cell's mean pessimism exceeds
// `tolerance` [ln] and fewer than `limit` views are kept; each time the direction of the worst cell
// whose addition lowers the total pessimism most.
void refine_cells(const std::vector<ProfileView>& views, const std::vector<ViewMeasurement>& data,
                  std::vector<std::size_t>& kept, const std::vector<float>& bands, std::size_t T,
                  float tolerance, std::size_t limit) {
  while (kept.size() < limit && kept.size() < views.size()) {
    const BoundState st = bound_state(views, data, kept, bands, T);
    std::size_t worst = kept.size();
    float worst_mean = tolerance;
    for (std::size_t j = 0; j < kept.size(); ++j) {
      double sum = 0;
      for (std::size_t s : st.members[j]) sum += pessimism(st, data, j, s);
      const float mean = float(sum / double(st.members[j].size()));
      if (mean > worst_mean) {
        worst_mean = mean;
        worst = j;
      }
    }
    if (worst == kept.size()) return;
    std::size_t best = views.size();
    double best_total = 0;
    for (std::size_t s : st.members[worst]) {
      if (std::find(kept.begin(), kept.end(), s) != kept.end()) continue;
      std::vector<std::size_t> trial = kept;
      trial.push_back(s);
      const double total = total_pessimism(bound_state(views, data, trial, bands, T), data);
      if (best == views.size() || total < best_total) {
        best_total = total;
        best = s;
      }
    }
    if (best == views.size()) return;  // the worst cell holds no other measured direction
    kept.push_back(best);
  }
}
}  // namespace

ProfileData build_profile(const std::vector<LevelInput>& levels, const Material& material,
                          const ProfileSettings& settings, const ProgressFn& progress,
                          ProfileReport* report) {
  const auto start = std::chrono::steady_clock::now();
  const ProfileMeasurer measurer(levels, material, settings);
  const auto limit = thread_limit(settings.jobs);

  std::vector<ProfileView> views;
  std::vector<ViewMeasurement> data;
  std::mutex progress_mutex;
  std::size_t done = 0;
  // Measures views[data.size() ..) in parallel; bounds' samples without Reddy's features.
  auto measure_new = [&](std::size_t total, const char* stage, bool features) {
    const std::size_t first = data.size();
    data.resize(views.size());
    oneapi::tbb::parallel_for(first, views.size(), [&](std::size_t v) {
      data[v] = measurer.measure(views[v], features);
      if (progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress(stage, ++done, total);
      }
    });
  };

  const float tolerance = std::log1p(std::max(0.0f, settings.view_tolerance));  // in log distance
  std::vector<std::size_t> kept;
  if (settings.views > 0) {
    views = fibonacci_views(settings.views);
    measure_new(views.size(), "views", true);
  } else {
    // Nested icosphere vertex sets: 12, 42, 162.
    const SphereMesh ico = icosphere(2);
    std::size_t count = 12;
    while (true) {
      for (std::size_t v = views.size(); v < count; ++v)
        views.push_back(make_view(ico.positions[3 * v], ico.positions[3 * v + 1], ico.positions[3 * v + 2]));
      measure_new(count, "views", true);
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

  const std::size_t measured = views.size();
  const float own_error = prediction_error(views, data, kept, false);

  // Bounds: measure the sample directions not yet measured, refine where cells disagree, and
  // store each cell's maximum.
  const std::size_t T = settings.analysis.orientations;
  const std::vector<float>& bands = measurer.analyzer().bands();
  BoundState bound;
  if (settings.bound_cells) {
    const std::size_t first = views.size();
    for (const ProfileView& s : bound_sample_views()) {
      bool known = false;  // the adaptive sets are the samples' first 12 or 42
      for (std::size_t v = 0; v < first && !known; ++v)
        known = dot3(views[v].direction, s.direction) > 0.99999f;
      if (!known) views.push_back(s);
    }
    done = 0;
    measure_new(views.size() - first, "samples", false);
    const std::size_t view_limit =
        settings.views > 0 ? kept.size() : std::max<std::size_t>(settings.bound_views, kept.size());
    refine_cells(views, data, kept, bands, T, 0.5f * tolerance, view_limit);
    for (std::size_t v : kept)  // samples that became views: their features
      if (data[v].features.empty()) data[v].features = measurer.measure(views[v]).features;
    bound = bound_state(views, data, kept, bands, T);
  }

  ProfileData out;
  std::copy(measurer.sphere(), measurer.sphere() + 4, out.sphere);
  out.snapshot_pixels = settings.render.pixels;
  for (const LevelInput& l : levels)
    out.levels.push_back(
        {l.triangles ? l.triangles : static_cast<std::uint32_t>(l.mesh.index_count / 3), l.geometric_error});
  out.orientations = orientation_angles(settings.analysis);
  out.bands = measurer.analyzer().bands();
  const std::size_t K = levels.size(), B = out.bands.size();
  out.lost.resize((K - 1) * kept.size() * T * B);
  out.features.resize(K * kept.size() * T);
  out.detail.resize(out.lost.size());
  out.pooled.resize((K - 1) * kept.size() * B);
  for (std::size_t j = 0; j < kept.size(); ++j) {
    const ViewMeasurement& m = data[kept[j]];
    const std::vector<float>& lost = settings.bound_cells ? bound.lost[j] : m.lost;
    const std::vector<ProfileDetail> detail =
        view_detail(views, data, kept[j], settings.bound_cells ? &bound.members[j] : nullptr, &lost, T, B);
    const std::vector<ProfilePooled> pooled =
        view_pooled(data, kept[j], settings.bound_cells ? &bound.members[j] : nullptr);
    out.views.push_back(views[kept[j]]);
    for (std::size_t k = 1; k < K; ++k) {
      std::copy_n(&lost[(k - 1) * T * B], T * B, &out.lost[((k - 1) * kept.size() + j) * T * B]);
      std::copy_n(&detail[(k - 1) * T * B], T * B, &out.detail[((k - 1) * kept.size() + j) * T * B]);
      std::copy_n(&pooled[(k - 1) * B], B, &out.pooled[((k - 1) * kept.size() + j) * B]);
    }
    for (std::size_t k = 0; k < K; ++k)
      std::copy_n(&m.features[k * T], T, &out.features[(k * kept.size() + j) * T]);
  }
  if (report) {
    report->views_measured = static_cast<std::uint32_t>(measured);
    report->views_kept = static_cast<std::uint32_t>(kept.size());
    report->prediction_error = std::exp(own_error) - 1.0f;
    report->views_sampled = static_cast<std::uint32_t>(views.size());
    if (settings.bound_cells) {
      std::vector<float> ratios;  // each measured direction against its nearest kept view's bound
      std::vector<ProfileView> kept_views(out.views);
      for (std::size_t s = 0; s < views.size(); ++s) {
        const std::size_t j = nearest_view(kept_views, views[s].direction);
        for (std::size_t k = 0; k < data[s].switching.size(); ++k)
          ratios.push_back(data[s].switching[k] / bound.switching[j][k] - 1.0f);
      }
      if (!ratios.empty()) {
        std::nth_element(ratios.begin(), ratios.begin() + std::ptrdiff_t(ratios.size() / 2), ratios.end());
        report->bound_pessimism = ratios[ratios.size() / 2];
      }
    }
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace acuity::spectra
