// The demo's large object (acuity/sim/large_object.hpp): the object rule against the cluster cut on
// one object spanning the gaze, both judged.
#include "acuity/sim/large_object.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "acuity/bake/chains.hpp"
#include "acuity/bake/library.hpp"
#include "acuity/bake/scene.hpp"
#include "acuity/clusters.hpp"
#include "acuity/file.hpp"
#include "acuity/lodgen/clusters.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "exact_view.hpp"
#include "geometry.hpp"
#include "text.hpp"

namespace acuity::sim {
namespace {

namespace fs = std::filesystem;

// The hierarchy's profile: the cached one when it measured this hierarchy at these snapshot pixels,
// else made and written.
struct HierarchyProfile {
  Blob blob;
  Profile profile{};
  ClusterLoss loss;
  std::vector<float> ln_lost;
};
void profile_hierarchy(const Asset& a, const lodgen::ClusterHierarchy& h, const std::string& path,
                       std::uint32_t pixels, const std::function<void(const std::string&)>& progress,
                       HierarchyProfile* out) {
  const auto measured = [&] {
    return open_profile(out->blob.data(), out->blob.size, &out->profile) == ProfileStatus::Ok &&
           out->profile.meta.snapshot_pixels == pixels &&
           measured_group_loss(out->profile, h.clusters, h.groups, &out->loss) == GroupLossStatus::Measured;
  };
  if (fs::exists(path)) {
    out->blob = io::read_file(path);
    if (measured()) return;
  }
  bake::BakeOptions settings;
  settings.pixels = pixels;
  spectra::ClusterLossReport report;
  const spectra::ProfileData data = bake::profile_clusters(
      bake::cluster_mesh(a.chain.levels[0].mesh, h), a.material, bake::profile_settings(settings, 0),
      bake::cluster_loss_settings(settings, 0), {}, nullptr, &report);
  spectra::write_profile(path, data);
  if (progress) {
    std::string line;
    appendf(&line, "  %s: %u groups x %u directions profiled in %.1f s, %s\n",
            fs::path(path).filename().c_str(), report.groups, report.views, report.seconds, path.c_str());
    progress(line);
  }
  out->blob = io::read_file(path);
  if (!measured()) throw std::runtime_error(path + ": the profile just written does not read back");
}

// The run's frame with the head held still at the origin looking down -Z (its eyes apart by their
// distance in the run); the gaze, its confidence and velocity, and dt as the run's.
Frame still_head(const Frame& run) {
  Frame f;
  f.eye_count = run.eye_count;
  f.dt = run.dt;
  for (std::uint32_t e = 0; e < 2; ++e) {
    f.eyes[e] = run.eyes[e];
    const double half = run.eye_count == 2
                            ? 0.5 * glm::length(glm::dvec3(run.eyes[1].position[0] - run.eyes[0].position[0],
                                                           run.eyes[1].position[1] - run.eyes[0].position[1],
                                                           run.eyes[1].position[2] - run.eyes[0].position[2]))
                            : 0.0;
    f.eyes[e].position[0] = e == 0 ? -half : half;
    f.eyes[e].position[1] = f.eyes[e].position[2] = 0;
    const float identity[4] = {0, 0, 0, 1};
    std::copy_n(identity, 4, f.eyes[e].orientation);
    std::fill_n(f.eyes[e].velocity, 3, 0.0f);
    std::fill_n(f.eyes[e].angular_velocity, 3, 0.0f);
    f.gaze[e] = run.gaze[e];
  }
  return f;
}

}  // namespace

namespace {

// One span: the run's frames through the object rule and the cut, some of them judged.
LargeObjectRun::Span run_span(const Simulation& sim, int asset, const lodgen::ClusterHierarchy& h,
                              const HierarchyProfile& hp, const LargeObjectOptions& o, double deg) {
  const SceneAssets& scene = sim.scene();
  const Asset& a = scene.assets[std::size_t(asset)];
  const std::vector<std::uint32_t> roots = cluster_roots(h.clusters);
  const ClusterView view{h.clusters, h.groups, roots};
  // The object: its sphere (level 0's, as the chain's profile frames it) spanning deg, centred
  // o.distance ahead.
  const float* sphere = a.profile.meta.sphere;
  const double radius = o.distance * std::sin(0.5 * deg / kDeg);
  ObjectTransform t;
  t.scale = float(radius / double(sphere[3]));
  for (int k = 0; k < 3; ++k) t.position[k] = -double(t.scale) * double(sphere[k]);
  t.position[2] -= o.distance;

  SchedulerConfig c = sim.rule("perceptual").scheduler->config();
  c.max_objects = 1;
  c.max_profiles = 1;
  Scheduler s(c);
  const ObjectId id = s.add_object(s.add_profile(a.profile), t);
  std::vector<CutGroupMemory> memory(h.groups.size());
  std::vector<std::uint8_t> scratch(h.groups.size());
  std::vector<std::uint32_t> drawn(h.clusters.size());
  LargeObjectRun::Span out;
  out.deg = deg;
  const std::size_t frames = sim.frame_count(), judged = std::min<std::size_t>(o.judged, frames);
  // The judged frames' views: the object rule's when it drew a coarser level than the finest, the
  // cut's when it drew a coarser cluster (else the same triangles as the finest mesh: score 0).
  std::vector<Frame> kept(judged);
  std::vector<ExactView> object_views, cut_views;
  std::vector<std::size_t> object_of, cut_of;  // the judged entry of each view
  std::vector<std::uint8_t> levels;
  std::vector<std::vector<std::uint32_t>> cuts;
  for (std::size_t f = 0; f < frames; ++f) {
    const Frame frame = still_head(sim.frame(f));
    s.begin_frame(frame);
    s.update(0, 1);
    s.end_frame();
    const std::uint8_t level = s.level(id);
    const CutResult r = s.select_cut(view, hp.loss, t, nullptr, memory, scratch, drawn);
    if (r.status != CutStatus::Ok)
      throw std::runtime_error(std::string("large object: ") + to_string(r.status));
    out.object_rule += double(a.profile.levels[level].triangles);
    out.cut += double(r.triangles);
    const std::size_t j = out.judged.size();
    if (j == judged || f != (2 * j + 1) * frames / (2 * judged)) continue;  // the middle of each stretch
    kept[j] = frame;
    out.judged.push_back({std::uint32_t(f), a.profile.levels[level].triangles, r.triangles, 0, 0});
    const ExactView v{asset, t, glm::dvec3(0.0), radius, &kept[j]};
    if (level > 0) {
      object_views.push_back(v);
      object_of.push_back(j);
      levels.push_back(level);
    }
    std::vector<std::uint32_t> indices;
    bool coarser = false;
    for (std::uint32_t k = 0; k < r.clusters; ++k) {
      const Cluster& cl = h.clusters[drawn[k]];
      coarser |= cl.refined != kNoGroup;
      indices.insert(indices.end(), h.indices.begin() + 3 * std::ptrdiff_t(cl.first_triangle),
                     h.indices.begin() + 3 * std::ptrdiff_t(cl.first_triangle + cl.triangle_count));
    }
    if (coarser) {
      cut_views.push_back(v);
      cut_of.push_back(j);
      cuts.push_back(std::move(indices));
    }
  }
  out.object_rule /= double(std::max<std::size_t>(frames, 1));
  out.cut /= double(std::max<std::size_t>(frames, 1));

  // The judge at the display's pixels per degree (its centre's), as the run's decisions.
  const SimulationOptions& so = sim.options();
  const double ppd = double(so.viewport) / (2 * std::tan(0.5 * double(so.fov_deg) / kDeg)) / kDeg;
  const std::vector<ExactScores> object_scores = judge_exact_views(scene, object_views, c, ppd);
  for (std::size_t i = 0; i < object_views.size(); ++i)
    out.judged[object_of[i]].object_score = object_scores[i].scores[levels[i]];
  const std::vector<float> cut_scores = judge_exact_triangles(scene, cut_views, cuts, c, ppd);
  for (std::size_t i = 0; i < cut_views.size(); ++i) out.judged[cut_of[i]].cut_score = cut_scores[i];
  return out;
}

}  // namespace

std::size_t large_object_asset(const SceneAssets& scene, const std::string& asset, const std::string& what) {
  std::string names;
  for (std::size_t a = 0; a < scene.assets.size(); ++a) {
    if (scene.assets[a].name == asset) return a;
    names += (names.empty() ? "" : ", ") + scene.assets[a].name;
  }
  throw std::runtime_error(what + ": the scene has no asset '" + asset + "' (it has " + names + ")");
}

LargeObjectRun run_large_object(const Simulation& sim, const LargeObjectOptions& o,
                                const std::function<void(const std::string&)>& progress) {
  const SceneAssets& scene = sim.scene();
  const std::size_t asset = large_object_asset(scene, o.asset, "large object");
  const Asset& a = scene.assets[asset];
  const lodgen::ClusterHierarchy h = lodgen::build_clusters(a.chain.levels[0].mesh, o.asset);
  HierarchyProfile hp;
  profile_hierarchy(a, h, (fs::path(o.profiles) / (o.asset + "-clusters.acuity")).string(), o.pixels,
                    progress, &hp);
  hp.ln_lost = loss_logs(hp.loss.lost);
  hp.loss.ln_lost = hp.ln_lost;
  LargeObjectRun run;
  run.asset = o.asset;
  run.finest = h.finest_triangles();
  run.clusters = std::uint32_t(h.clusters.size());
  run.groups = std::uint32_t(h.groups.size());
  run.bands = std::uint32_t(hp.loss.bands_cpod.size());
  run.frames = sim.frame_count();
  for (double deg : o.spans_deg) run.spans.push_back(run_span(sim, int(asset), h, hp, o, deg));
  return run;
}

std::string large_object_text(const LargeObjectRun& run, const LargeObjectOptions& o) {
  std::string out;
  appendf(
      &out,
      "\nA large object spanning the gaze (issue 48): %s, %llu triangles as %u clusters in %u groups "
      "(lodgen --clusters, its loss profiled in %u bands), %.0f m in front of a still head, the run's gaze "
      "over it for %zu frames:\n",
      run.asset.c_str(), (unsigned long long)run.finest, run.clusters, run.groups, run.bands, o.distance,
      run.frames);
  appendf(&out,
          "across    rule                     triangles/frame  of finest   visible losses  worst judged "
          "score\n");
  std::size_t n = 0;
  for (const LargeObjectRun::Span& span : run.spans) {
    std::uint32_t object_visible = 0, cut_visible = 0;
    float object_worst = 0, cut_worst = 0;
    for (const LargeObjectRun::Judged& j : span.judged) {
      object_visible += j.object_score > 1.0f;
      cut_visible += j.cut_score > 1.0f;
      object_worst = std::max(object_worst, j.object_score);
      cut_worst = std::max(cut_worst, j.cut_score);
    }
    n = span.judged.size();
    appendf(&out, "%4.0f deg  object rule (one level)  %15.0f  %8.1f%%   %5u of %-4zu   %18.2f\n", span.deg,
            span.object_rule, 100.0 * span.object_rule / double(run.finest), object_visible, n, object_worst);
    appendf(&out, "          cluster cut (per group)  %15.0f  %8.1f%%   %5u of %-4zu   %18.2f\n", span.cut,
            100.0 * span.cut / double(run.finest), cut_visible, n, cut_worst);
  }
  appendf(&out,
          "(both the perceptual rule's configuration, hysteresis and saccade gating; judged at %zu frames "
          "each by the detection model against the finest mesh, a cut rendered as its triangles, the finest "
          "mesh scoring 0)\n",
          n);
  return out;
}

}  // namespace acuity::sim
