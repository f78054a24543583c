// What each group of a cluster hierarchy loses: window snapshots of the finest mesh against the
// mesh with one group drawn coarse. See acuity/spectra/cluster_loss.hpp.
#include "acuity/spectra/cluster_loss.hpp"
#include "thread_limit.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>

namespace acuity::spectra {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("cluster loss: ") + what);
}

// The image axes of `view` (render_snapshot's): right = -direction x up, and up.
void axes(const ProfileView& view, float right[3], float up[3]) {
  const float* d = view.direction;
  const float* u = view.up;
  right[0] = -(d[1] * u[2] - d[2] * u[1]);
  right[1] = -(d[2] * u[0] - d[0] * u[2]);
  right[2] = -(d[0] * u[1] - d[1] * u[0]);
  std::copy_n(u, 3, up);
}

float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

ClusterLossMeasurer::ClusterLossMeasurer(const ClusterMesh& mesh, const Material& material,
                                         const ClusterLossSettings& settings)
    : mesh_(mesh),
      material_(material),
      render_(settings.render),
      analyzer_(settings.render.pixels, settings.analysis) {
  const std::uint32_t p = settings.render.pixels;
  require(p >= 16 && p <= 4096 && (p & (p - 1)) == 0, "window pixels must be a power of two in 16 .. 4096");
  const float bpo = settings.analysis.bands_per_octave;
  require(bpo >= 1 && bpo <= 4 && bpo == std::floor(bpo), "bands_per_octave must be an integer in 1 .. 4");
  require(settings.views == 12 || settings.views == 42 || settings.views == 162,
          "views must be 12, 42 or 162");
  require(settings.margin >= 1 && std::isfinite(settings.margin), "margin must be >= 1");
  require(!mesh.groups.empty(), "the hierarchy has no groups");
  require(analyzer_.band_count() >= 1, "no band fits the window (lowest_band above pixels / 4)");
  per_octave_ = static_cast<std::uint32_t>(bpo);

  // The object's sphere: level 0's (the finest clusters' vertices), as the profile's Meta.
  std::size_t finest_triangles = 0;
  for (const Cluster& c : mesh.clusters) {
    if (c.refined != kNoGroup) break;  // the finest come first
    finest_.push_back(static_cast<std::uint32_t>(&c - mesh.clusters.data()));
    finest_triangles += c.triangle_count;
  }
  MeshView finest = mesh.mesh;
  finest.indices = mesh.indices.data();
  finest.index_count = 3 * finest_triangles;
  bounding_sphere(finest, render_.sphere);
  require(render_.sphere[3] > 0 && std::isfinite(render_.sphere[3]), "the finest mesh has no extent");

  // Each cluster's bounding sphere (box centre, farthest vertex).
  cluster_sphere_.assign(4 * mesh.clusters.size(), 0.0f);
  for (std::size_t c = 0; c < mesh.clusters.size(); ++c) {
    MeshView one = mesh.mesh;
    const Cluster& k = mesh.clusters[c];
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t i = 3 * std::size_t(k.first_triangle);
         i < 3 * std::size_t(k.first_triangle + k.triangle_count); ++i)
      for (int a = 0; a < 3; ++a) {
        const float x = one.positions[3 * std::size_t(mesh.indices[i]) + a];
        lo[a] = std::min(lo[a], x);
        hi[a] = std::max(hi[a], x);
      }
    float* s = &cluster_sphere_[4 * c];
    for (int a = 0; a < 3; ++a) s[a] = 0.5f * (lo[a] + hi[a]);
    float r2 = 0;
    for (std::size_t i = 3 * std::size_t(k.first_triangle);
         i < 3 * std::size_t(k.first_triangle + k.triangle_count); ++i) {
      const float* v = &one.positions[3 * std::size_t(mesh.indices[i])];
      const float d[3] = {v[0] - s[0], v[1] - s[1], v[2] - s[2]};
      r2 = std::max(r2, dot3(d, d));
    }
    s[3] = std::sqrt(r2) * 1.0001f;
  }

  // Regions (finest clusters each group replaces) and made clusters, in group order (a group comes
  // after every group that made one of its members).
  const std::size_t G = mesh.groups.size();
  region_.resize(G);
  made_.resize(G);
  for (std::size_t c = 0; c < mesh.clusters.size(); ++c)
    if (mesh.clusters[c].refined != kNoGroup) made_[mesh.clusters[c].refined].push_back(std::uint32_t(c));
  for (std::size_t g = 0; g < G; ++g) {
    const ClusterGroup& group = mesh.groups[g];
    std::vector<std::uint32_t>& r = region_[g];
    for (std::uint32_t m = group.first_member; m < group.first_member + group.member_count; ++m) {
      const std::uint32_t from = mesh.clusters[m].refined;
      if (from == kNoGroup)
        r.push_back(m);
      else
        r.insert(r.end(), region_[from].begin(), region_[from].end());
    }
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }

  // Window levels: the largest n with object radius / 2^n >= margin x the group's, within the band grid.
  const std::uint32_t Bw = analyzer_.band_count();
  const std::uint32_t n_cap = (kMaxBands - Bw) / per_octave_;
  std::uint32_t n_max = 0;
  level_.resize(G);
  for (std::size_t g = 0; g < G; ++g) {
    const double ratio =
        double(render_.sphere[3]) / (double(settings.margin) * double(mesh.groups[g].radius));
    const double n = ratio >= 1 ? std::floor(std::log2(ratio)) : 0.0;  // a radius of 0: the cap
    level_[g] = static_cast<std::uint32_t>(std::min<double>(n, n_cap));
    n_max = std::max(n_max, level_[g]);
  }
  const std::uint32_t Bc = n_max * per_octave_ + Bw;
  const float step = std::exp2(1.0f / float(per_octave_));
  for (std::uint32_t j = 0; j < Bc; ++j)
    bands_.push_back(settings.analysis.lowest_band * std::pow(step, float(j)));
}

ClusterLossMeasurer::~ClusterLossMeasurer() = default;

void ClusterLossMeasurer::window(std::uint32_t g, float sphere[4], std::uint32_t level) const {
  std::copy_n(mesh_.groups[g].center, 3, sphere);
  sphere[3] = std::ldexp(render_.sphere[3], -int(level == kOwnLevel ? level_[g] : level));
}

std::vector<std::uint32_t> ClusterLossMeasurer::coarse_indices(std::uint32_t g) const {
  std::vector<std::uint32_t> out;
  const std::vector<std::uint32_t>& region = region_[g];
  for (std::uint32_t c : finest_)
    if (!std::binary_search(region.begin(), region.end(), c)) append_cluster(out, c);
  for (std::uint32_t c : made_[g]) append_cluster(out, c);
  return out;
}

std::span<const std::uint32_t> ClusterLossMeasurer::finest_indices() const {
  std::size_t n = 0;
  for (std::uint32_t c : finest_) n += 3 * std::size_t(mesh_.clusters[c].triangle_count);
  return mesh_.indices.first(n);
}

void ClusterLossMeasurer::append_cluster(std::vector<std::uint32_t>& out, std::uint32_t c) const {
  const Cluster& k = mesh_.clusters[c];
  const std::uint32_t* first = mesh_.indices.data() + 3 * std::size_t(k.first_triangle);
  out.insert(out.end(), first, first + 3 * std::size_t(k.triangle_count));
}

std::vector<float> ClusterLossMeasurer::measure(std::uint32_t g, const ProfileView& view,
                                                std::uint32_t level) const {
  RenderSettings r = render_;
  window(g, r.sphere, level);
  float right[3], up[3];
  axes(view, right, up);
  // Clusters that can reach the window's square (occluders in front included: orthographic, no
  // near plane), as sphere against square in the image plane.
  const auto reaches = [&](std::uint32_t c) {
    const float* s = &cluster_sphere_[4 * std::size_t(c)];
    const float d[3] = {s[0] - r.sphere[0], s[1] - r.sphere[1], s[2] - r.sphere[2]};
    const float reach = r.sphere[3] + s[3];
    return std::abs(dot3(d, right)) <= reach && std::abs(dot3(d, up)) <= reach;
  };
  std::vector<std::uint32_t> reference, coarse;
  const std::vector<std::uint32_t>& region = region_[g];
  for (std::uint32_t c : finest_) {
    if (!reaches(c)) continue;
    append_cluster(reference, c);
    if (!std::binary_search(region.begin(), region.end(), c)) append_cluster(coarse, c);
  }
  for (std::uint32_t c : made_[g]) append_cluster(coarse, c);

  MeshView a = mesh_.mesh, b = mesh_.mesh;
  a.indices = reference.data();
  a.index_count = reference.size();
  b.indices = coarse.data();
  b.index_count = coarse.size();
  const Image ref = render_snapshot(a, material_, view, r);
  const Image coarse_image = render_snapshot(b, material_, view, r);
  std::vector<float> out(std::size_t(analyzer_.orientation_count()) * analyzer_.band_count(), 0.0f);
  if (ref.pixels == coarse_image.pixels) return out;  // g is hidden from this view
  analyzer_.measure(coarse_image, *analyzer_.prepare(ref), out.data());
  return out;
}

ProfileClusterData measure_cluster_loss(const ClusterMesh& mesh, const Material& material,
                                        const ClusterLossSettings& settings, const ProgressFn& progress,
                                        ClusterLossReport* report) {
  const auto start = std::chrono::steady_clock::now();
  const ClusterLossMeasurer m(mesh, material, settings);
  const auto limit = thread_limit(settings.jobs);

  const SphereMesh ico = icosphere(2);
  std::vector<ProfileView> views;
  for (std::uint32_t v = 0; v < settings.views; ++v)
    views.push_back(make_view(ico.positions[3 * v], ico.positions[3 * v + 1], ico.positions[3 * v + 2]));
  const std::size_t G = mesh.groups.size(), V = views.size(), T = m.orientations(), Bw = m.window_bands();
  const std::size_t Bc = m.bands().size();
  // The cells: the first kClusterCells directions (the icosahedron's vertices), each bounding the
  // measured directions in or near it.
  std::vector<std::size_t> cell_views(kClusterCells);
  for (std::size_t j = 0; j < kClusterCells; ++j) cell_views[j] = j;
  const std::vector<std::vector<std::size_t>> cells = view_cells(views, cell_views);
  const std::size_t C = cells.size();

  // own[(g V + v) Bw + i]: the largest over orientations in g's window band i from direction v.
  std::vector<float> own(G * V * Bw, 0.0f);
  std::vector<std::uint8_t> hidden(G * V, 0);
  std::mutex mutex;
  std::size_t done = 0;
  oneapi::tbb::parallel_for(std::size_t(0), G * V, [&](std::size_t job) {
    const std::size_t g = job / V, v = job % V;
    const std::vector<float> lost = m.measure(std::uint32_t(g), views[v]);
    hidden[job] = std::all_of(lost.begin(), lost.end(), [](float x) { return x == 0.0f; });
    for (std::size_t t = 0; t < T; ++t)
      for (std::size_t i = 0; i < Bw; ++i) own[job * Bw + i] = std::max(own[job * Bw + i], lost[t * Bw + i]);
    std::lock_guard<std::mutex> lock(mutex);
    if (progress) progress("windows", ++done, G * V);
  });

  // Per cell, onto the stored band grid, in group order (the groups that made a group's members
  // come first); the Clusters section's row is the largest over the cells.
  ProfileClusterData out;
  out.bands = m.bands();
  out.lost.assign(G * Bc, 0.0f);
  out.view_lost.assign(G * C * Bc, 0.0f);
  std::vector<float> mine(Bw);
  for (std::size_t g = 0; g < G; ++g) {
    const std::size_t first = m.first_band(std::uint32_t(g));
    const ClusterGroup& group = mesh.groups[g];
    for (std::size_t c = 0; c < C; ++c) {
      float* row = &out.view_lost[(g * C + c) * Bc];
      std::fill(mine.begin(), mine.end(), 0.0f);
      for (std::size_t v : cells[c])
        for (std::size_t i = 0; i < Bw; ++i) mine[i] = std::max(mine[i], own[(g * V + v) * Bw + i]);
      for (std::size_t j = 0; j < Bc; ++j) {
        if (j < first)  // coarser than the window: its lowest band's value falling as f^2
          row[j] = mine[0] * (out.bands[j] / out.bands[first]) * (out.bands[j] / out.bands[first]);
        else if (j < first + Bw)
          row[j] = mine[j - first];
        else
          row[j] = mine[Bw - 1];  // finer than the window: flat beyond its finest band ...
      }
      for (std::uint32_t k = group.first_member; k < group.first_member + group.member_count; ++k) {
        const std::uint32_t from = mesh.clusters[k].refined;  // ... or what finer windows measured there
        if (from == kNoGroup) continue;
        for (std::size_t j = first + Bw; j < Bc; ++j)
          row[j] = std::max(row[j], out.view_lost[(from * C + c) * Bc + j]);
      }
      for (std::size_t j = 0; j < Bc; ++j) out.lost[g * Bc + j] = std::max(out.lost[g * Bc + j], row[j]);
    }
  }
  if (settings.views >= kMinCellSamples || settings.view_cells) {
    for (std::size_t c = 0; c < C; ++c)
      out.view_directions.insert(out.view_directions.end(), views[c].direction, views[c].direction + 3);
    out.view_samples = std::uint32_t(V);
  } else {  // the cut would not read them (kMinCellSamples): no ClusterViews section
    out.view_lost = {};
  }
  out.window_pixels = settings.render.pixels;
  out.view_count = settings.views;
  out.hierarchy_hash = cluster_hierarchy_hash(mesh.clusters, mesh.groups);
  if (report) {
    report->groups = std::uint32_t(G);
    report->views = std::uint32_t(V);
    report->hidden = std::uint32_t(std::count(hidden.begin(), hidden.end(), 1));
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace acuity::spectra
