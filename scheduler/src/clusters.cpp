// Cluster cuts (acuity/clusters.hpp, Scheduler::select_cut): a hierarchy's groups tested with the
// perceptual rule's thresholds, top down; the measured per-group loss of a profile's Clusters
// section, and the provisional one from a chain profile (the fallback).
#include <algorithm>
#include <limits>

#include "fnv1a.hpp"
#include "geometry.hpp"

namespace acuity {

std::vector<std::uint32_t> cluster_roots(std::span<const Cluster> clusters) {
  std::vector<std::uint32_t> out;
  for (std::size_t c = 0; c < clusters.size(); ++c)
    if (clusters[c].group == kNoGroup) out.push_back(std::uint32_t(c));
  return out;
}

std::vector<std::uint32_t> cluster_made_index(std::span<const Cluster> clusters, std::size_t group_count) {
  const std::size_t G = group_count;
  std::vector<std::uint32_t> out(G + 1, 0);
  for (const Cluster& k : clusters)
    if (k.refined < G) ++out[k.refined + 1];
  for (std::size_t g = 0; g < G; ++g) out[g + 1] += out[g];
  out.resize(G + 1 + out[G]);
  std::vector<std::uint32_t> next(out.begin(), out.begin() + std::ptrdiff_t(G));
  for (std::size_t c = 0; c < clusters.size(); ++c)
    if (clusters[c].refined < G) out[G + 1 + next[clusters[c].refined]++] = std::uint32_t(c);
  return out;
}

namespace {

// select_cut's state of each group (its scratch byte): the walk's marks, and the budget's.
constexpr std::uint8_t kNeeded = 1, kBlocked = 2, kVisible = 4;
constexpr std::uint8_t kQueued = 8;    // the budget: a candidate already (or an eye inside it)
constexpr std::uint8_t kOverOne = 16;  // ... its score is above 1: coarsening it is a visible loss

// Calls f(c) for every cluster the cut of this state draws: the members of visible groups whose
// maker is invisible (or that are finest), then the roots likewise.
template <class F>
void for_each_drawn(const ClusterView& h, const std::uint8_t* state, F&& f) {
  const Cluster* const clusters = h.clusters.data();  // locals: f's stores may alias the spans
  const ClusterGroup* const groups = h.groups.data();
  const auto drawn = [&](std::uint32_t c) {
    const std::uint32_t maker = clusters[c].refined;
    return maker == kNoGroup || !(state[maker] & kVisible);
  };
  for (std::size_t g = 0, G = h.groups.size(); g < G; ++g) {
    if (!(state[g] & kVisible)) continue;
    for (std::uint32_t m = groups[g].first_member, end = m + groups[g].member_count; m < end; ++m)
      if (drawn(m)) f(m);
  }
  for (std::uint32_t r : h.roots)
    if (drawn(r)) f(r);
}

// The triangles group g's members hold less those of the clusters it made (h.made): what coarsening
// it saves.
std::int64_t triangles_saved(const ClusterView& h, std::uint32_t g) {
  const ClusterGroup& group = h.groups[g];
  std::int64_t saved = 0;
  for (std::uint32_t m = group.first_member; m < group.first_member + group.member_count; ++m)
    saved += h.clusters[m].triangle_count;
  const std::uint32_t* made = h.made.data() + h.groups.size() + 1;
  for (std::uint32_t k = h.made[g]; k < h.made[g + 1]; ++k) saved -= h.clusters[made[k]].triangle_count;
  return saved;
}

// The budget's candidates in its scratch (CutBudget::scratch, one entry per group): a binary heap of
// group ids in the `group` fields of entry[0 .. n-1], ordered by each group's harm in its own entry
// (entry[g].harm), the least on top, ties to the lower group. (Any heap pops the same sequence: the
// order is total.)
struct CandidateHeap {
  CutCandidate* entry;
  std::size_t n = 0;
  bool later(std::uint32_t a, std::uint32_t b) const {
    return entry[a].harm != entry[b].harm ? entry[a].harm > entry[b].harm : a > b;
  }
  void push(std::uint32_t g) {
    std::size_t k = n++;
    for (; k > 0 && later(entry[(k - 1) / 2].group, g); k = (k - 1) / 2)
      entry[k].group = entry[(k - 1) / 2].group;
    entry[k].group = g;
  }
  std::uint32_t pop() {
    const std::uint32_t top = entry[0].group, last = entry[--n].group;
    std::size_t k = 0;
    for (std::size_t c = 1; c < n; c = 2 * k + 1) {
      if (c + 1 < n && later(entry[c].group, entry[c + 1].group)) ++c;
      if (!later(last, entry[c].group)) break;
      entry[k].group = entry[c].group;
      k = c;
    }
    if (n > 0) entry[k].group = last;
    return top;
  }
};

}  // namespace

const char* to_string(CutStatus status) {
  switch (status) {
    case CutStatus::Ok:
      return "ok";
    case CutStatus::InvalidInput:
      return "invalid input (non-finite or non-unit transform, scale <= 0, non-finite velocity, or no "
             "valid eye): the finest cut";
    case CutStatus::BadHierarchy:
      return "hierarchy, loss or scratch arrays of mismatched sizes: the finest cut";
    case CutStatus::BufferTooSmall:
      return "the output buffer cannot hold the cut";
  }
  return "unknown";
}

std::uint64_t cluster_hierarchy_hash(std::span<const Cluster> clusters,
                                     std::span<const ClusterGroup> groups) {
  return internal::fnv1a(internal::fnv1a(internal::kFnv1aBasis, clusters.data(), clusters.size_bytes()),
                         groups.data(), groups.size_bytes());
}

std::vector<float> loss_logs(std::span<const float> values) {
  std::vector<float> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = std::log(values[i]);
  return out;
}

const char* to_string(GroupLossStatus status) {
  switch (status) {
    case GroupLossStatus::Measured:
      return "measured";
    case GroupLossStatus::NoSection:
      return "the profile has no Clusters section (profile the hierarchy's glTF: acuity profile OUT.glb)";
    case GroupLossStatus::OtherHierarchy:
      return "the profile's Clusters section measured another hierarchy (group count or hash differ)";
  }
  return "unknown";
}

GroupLossStatus measured_group_loss(const Profile& p, std::span<const Cluster> clusters,
                                    std::span<const ClusterGroup> groups, ClusterLoss* loss) {
  if (!p.cluster_lost) return GroupLossStatus::NoSection;
  if (p.clusters.group_count != groups.size() ||
      p.clusters.hierarchy_hash != cluster_hierarchy_hash(clusters, groups))
    return GroupLossStatus::OtherHierarchy;
  const std::size_t B = p.clusters.band_count;
  loss->bands_cpod = std::span<const float>(p.cluster_bands, B);
  loss->diameter = 2.0f * p.meta.sphere[3];
  loss->lost = std::span<const float>(p.cluster_lost, groups.size() * B);
  const std::size_t V =
      p.cluster_view_lost && p.cluster_views.sample_count >= kMinCellSamples ? p.cluster_views.view_count : 0;
  loss->view_directions = std::span<const float>(p.cluster_view_directions, 3 * V);
  loss->view_lost = std::span<const float>(p.cluster_view_lost, groups.size() * V * B);
  loss->ln_lost = loss->ln_view_lost = {};
  return GroupLossStatus::Measured;
}

// The FALLBACK for a chain profile (no Clusters section); the one place this derivation lives.
std::vector<float> provisional_group_loss(const Profile& p, std::span<const ClusterGroup> groups,
                                          ClusterLoss* loss) {
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count;
  // Per level, per band: the largest loss over views and orientations, then a running maximum over
  // the finer levels (level 0 loses nothing).
  std::vector<float> level_loss(std::size_t(K) * B, 0.0f);
  for (std::uint32_t k = 1; k < K; ++k)
    for (std::uint32_t b = 0; b < B; ++b) {
      float m = level_loss[std::size_t(k - 1) * B + b];
      for (std::uint32_t v = 0; v < V; ++v)
        for (std::uint32_t t = 0; t < T; ++t) m = std::max(m, p.lost_contrast(k, v, t, b));
      level_loss[std::size_t(k) * B + b] = m;
    }
  const double diameter = 2.0 * double(p.meta.sphere[3]);
  const double coarsest = K > 1 ? double(p.levels[K - 1].geometric_error) : 0.0;
  std::vector<float> out(groups.size() * B);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const double e = double(groups[g].error) / diameter;  // [object diameters], as the chain's errors
    float* row = &out[g * B];
    std::uint32_t k = 0;
    while (k < K && !(double(p.levels[k].geometric_error) >= e)) ++k;
    if (k < K) {
      std::copy_n(&level_loss[std::size_t(k) * B], B, row);
      continue;
    }
    for (std::uint32_t b = 0; b < B; ++b)
      row[b] = coarsest > 0
                   ? float(std::min(1.0, double(level_loss[std::size_t(K - 1) * B + b]) * e / coarsest))
                   : 1.0f;
  }
  loss->bands_cpod = std::span<const float>(p.bands, B);
  loss->diameter = float(diameter);
  loss->lost = out;
  loss->view_directions = loss->view_lost = loss->ln_lost = loss->ln_view_lost = {};
  return out;
}

// One object as the cut sees it from each eye.
struct Scheduler::Impl::CutObject {
  Vec3 origin[2];             // the object's origin relative to each eye [m]
  Vec3 gaze[2];               // each eye's gaze direction, or its forward without a gaze (world)
  float gaze_offset[2];       // the gaze's uncertainty, or the no-gaze radius [deg]
  float half_focal[2];        // nyquist_cpd's half_focal of each eye
  float q[4];                 // object to world
  float q_inv[4];             // world to object
  const float* lost;          // [G B], the largest over the view cells
  const float* view_dirs;     // the loss's view cells [V 3], object space, or null
  const float* view_lost;     // [G V B]
  const float* ln_lost;       // ln of lost, or null (taken per band)
  const float* ln_view_lost;  // ln of view_lost, or null
  std::uint32_t V;
  float scale;
  float size;      // loss.diameter x scale [m]
  bool moving[2];  // its image moves on the retina of each eye
  const float* bands;
  float top_band;  // the largest of bands
  float ln_band[kMaxBands];
  std::uint32_t B;
  float ln_q;
  std::uint8_t flags;  // kFlagEyeInside, kFlagNoGaze found so far
};

// The geometry group_score() reads, for a run of up to kRun consecutive groups from one eye. Each
// entry is what the scalar expressions give (the same IEEE operations, no contraction), so a run's
// entries are the same bits whether the loop vectorises or not.
struct Scheduler::Impl::GroupSights {
  static constexpr std::size_t kRun = 16;
  float x[kRun], y[kRun], z[kRun];      // the sphere's centre relative to the eye, over its distance
  float nearest[kRun];                  // to the sphere's nearest point [m]: <= 0 with the eye inside
  float e[kRun];                        // its nearest point's eccentricity [deg]
  float diameter_deg[kRun];             // the angle one object diameter subtends at that point [deg]
  float off_axis[kRun];                 // the angle of its point farthest off the view axis [deg], <= 90
  std::size_t first = std::size_t(-1);  // the run's first group; -1 before the first run
};

// Groups [first, first + count) (count <= kRun) seen from eye i: their spheres' direction, distance
// to the nearest point, that point's eccentricity, the angle one object diameter subtends at the nearest point and
// the angle farthest off the view axis. Entries of an eye inside a sphere are not used.
ACUITY_SIMD_CLONES void Scheduler::Impl::group_sights(std::uint32_t i, const CutObject& o,
                                                      const ClusterGroup* groups, std::size_t first,
                                                      std::size_t count, GroupSights* out) const {
  constexpr std::size_t kRun = GroupSights::kRun;
  float cx[kRun], cy[kRun], cz[kRun], radius[kRun];
  for (std::size_t j = 0; j < kRun; ++j) {  // a short run repeats its last group (not read)
    const ClusterGroup& g = groups[first + std::min(j, count - 1)];
    cx[j] = g.center[0];
    cy[j] = g.center[1];
    cz[j] = g.center[2];
    radius[j] = g.radius;
  }
  const EyeCache& eye = eyes_[i];
  const Vec3 origin = o.origin[i], gaze = o.gaze[i], forward = eye.forward;
  const float scale = o.scale, offset = o.gaze_offset[i], size_deg = kDeg * o.size;
  GroupSights& s = *out;
  ACUITY_NO_ALIAS
  for (std::size_t j = 0; j < kRun; ++j) {
    const Vec3 c = origin + rotate(o.q, scale * Vec3{cx[j], cy[j], cz[j]});
    const float d = length(c), r = scale * radius[j];
    const float nearest = d - r;
    const Vec3 u = (1.0f / d) * c;
    const float radius_deg = angular_radius_deg(d, r);
    s.x[j] = u.x;
    s.y[j] = u.y;
    s.z[j] = u.z;
    s.nearest[j] = nearest;
    s.e[j] = nearest_eccentricity(angle_deg(u, gaze), radius_deg, offset);
    s.diameter_deg[j] = size_deg / nearest;
    s.off_axis[j] = std::min(angle_deg(u, forward) + radius_deg, 90.0f);
  }
  s.first = first;
}

// One eye's score of one group: ln(lost / (q CT)), the largest over bands (without explain, the
// first one above 0: the group is visible whatever the rest); +inf where the eye is inside (or on)
// the sphere or a loss is NaN. Explain (nullable): filled when this eye's score exceeds its score so far.
[[gnu::always_inline]] inline float Scheduler::Impl::group_score(std::uint32_t i, const CutObject& o,
                                                                 const GroupSights& s, std::uint32_t j,
                                                                 std::size_t index, GroupExplain* explain,
                                                                 bool every_band, bool* inside) const {
  const EyeCache& eye = eyes_[i];
  const float nearest = s.nearest[j];
  if (inside) *inside = !(nearest > 0.0f);  // as !(d > r): a difference of floats is 0 only when equal
  if (!(nearest > 0.0f)) {                  // the eye is inside (or on) the sphere
    if (explain && !(explain->score >= kInf))
      *explain = GroupExplain{kInf, 0, std::uint8_t(i), kFlagEyeInside};
    return kInf;
  }
  const Vec3 u{s.x[j], s.y[j], s.z[j]};
  // The loss seen from the eye's view cell: the cell whose direction (from the group towards the
  // eye, object space) is nearest to the eye's.
  std::size_t row = index * o.B;  // into lost (or view_lost) and their logs
  if (o.view_dirs) {
    const Vec3 to_eye = rotate(o.q_inv, -1.0f * u);
    std::uint32_t best = 0;
    float best_dot = -2.0f;
    for (std::uint32_t v = 0; v < o.V; ++v) {
      const float x = dot(to_eye, load(o.view_dirs + 3 * v));
      if (x > best_dot) {
        best_dot = x;
        best = v;
      }
    }
    row = (index * o.V + best) * o.B;
  }
  const float* lost = (o.view_dirs ? o.view_lost : o.lost) + row;
  const float* ln_lost = o.view_dirs ? o.ln_view_lost : o.ln_lost;  // given, or taken here
  if (ln_lost) ln_lost += row;
  const float e = s.e[j];
  // The angle one object diameter subtends at the sphere's nearest point [deg].
  const float diameter_deg = s.diameter_deg[j];
  const float inv_diam = 1.0f / diameter_deg;
  // The Nyquist limit at the sphere's point farthest off the view axis: the largest over the sphere,
  // so a containing sphere never cuts a band a contained one shows. It is at least half_focal (its
  // value on the axis), so when no band's frequency (bands[b] x inv_diam, at most top_band x
  // inv_diam) is above that, no band is cut and it need not be found (+inf cuts none either).
  const float half_focal = o.half_focal[i];
  float nyquist = kInf;
  if (!(o.top_band * inv_diam <= half_focal))
    nyquist = nyquist_cpd(half_focal, std::cos(s.off_axis[j] * kRad));
  const bool moving = o.moving[i];
  float ln_ct[kMaxBands];
  band_thresholds(o.bands, o.ln_band, o.B, inv_diam, std::log(diameter_deg), nyquist, e, pre_->ecc_slope * e,
                  pre_->floor_velocity, moving, ln_ct);
  float score = -kInf;
  std::uint32_t limit = 0;
  for (std::uint32_t b = 0; b < o.B; ++b) {
    const float x = (ln_lost ? ln_lost[b] : std::log(lost[b])) - ln_ct[b] - o.ln_q;
    if (!(x <= score)) {  // NaN counts as visible
      score = x == x ? x : kInf;
      limit = b;
      if (score > 0.0f && !explain && !every_band) break;  // visible: the walk needs no more
    }
  }
  if (explain && (i == 0 || score > std::log(explain->score))) {
    explain->score = std::exp(score);
    explain->band = std::uint8_t(limit);
    explain->eye = std::uint8_t(i);
    explain->flags = eye.gaze ? 0 : kFlagNoGaze;
    explain->frequency_cpd = o.bands[limit] / diameter_deg;
    explain->threshold = std::exp(ln_ct[limit]);
    explain->distance_m = nearest;
    explain->eccentricity_deg = e;
  }
  return score;
}

// The object rule's hysteresis and gating, for one group the walk reached with this score (ln
// lost / (q CT)): visible applies at once; a group the memory holds visible coarsens once its score
// <= 1 - margin has waited as an object's would, and is held visible meanwhile (counted in *held); a
// score in (1 - margin, 1] keeps it. Returns whether the group is visible and remembers it.
bool Scheduler::Impl::remember_group(CutGroupMemory& m, bool visible, float score,
                                     const CoarsenTiming& timing, float ln_margin, std::uint32_t* held) {
  const bool was_visible = (m.state & (kCutKnown | kCutVisible)) == (kCutKnown | kCutVisible);
  CutGroupMemory next{0, 0, 0};
  if (!visible && was_visible) {
    if (score <= ln_margin) {
      const CoarsenTiming::Step wanted = timing.step(m.calm, m.wait);
      if (!wanted.ready) {
        next.calm = wanted.calm;
        next.wait = wanted.wait;
        ++*held;
        visible = true;
      }
    } else {
      visible = true;  // not low enough to want coarsening: it stays
    }
  }
  next.state = kCutKnown | (visible ? kCutVisible : 0);
  m = next;
  return visible;
}

// Funkhouser & Sequin over groups, as apply_budget() over objects: while over budget, coarsen the
// candidate of least harm (its score per triangle saved; ties to the lower group). A candidate is a
// visible group none of whose members' makers is visible, so coarsening it replaces exactly its
// members by the clusters it made and visibility stays monotone up the hierarchy (crack-free);
// coarsening it may make the groups holding those clusters candidates. Each group is offered at
// most once per maker it has and queued at most once: the heap never outgrows the groups. Every
// visible group's score is the walk's (budget.scratch[g].harm, over every eye and band), which its
// harm replaces when it is queued.
void Scheduler::Impl::spend_cut_budget(const ClusterView& h, const CutBudget& budget, std::uint64_t triangles,
                                       std::uint8_t* state, std::span<CutGroupMemory> memory,
                                       CutResult* res) const {
  CandidateHeap heap{budget.scratch.data()};
  const auto offer = [&](std::uint32_t g) {
    if ((state[g] & (kVisible | kQueued)) != kVisible) return;
    const ClusterGroup& group = h.groups[g];
    for (std::uint32_t m = group.first_member; m < group.first_member + group.member_count; ++m) {
      const std::uint32_t maker = h.clusters[m].refined;
      if (maker != kNoGroup && (state[maker] & kVisible)) return;
    }
    state[g] |= kQueued;
    CutCandidate& entry = heap.entry[g];
    const float score = entry.harm;
    if (!(score < kInf)) return;  // an eye inside it, or a NaN loss: never coarsened
    if (score > 0.0f) state[g] |= kOverOne;
    entry.harm = std::exp(score) / float(std::max<std::int64_t>(triangles_saved(h, g), 1));
    heap.push(g);
  };
  for (std::uint32_t g = 0; g < h.groups.size(); ++g) offer(g);
  std::int64_t total = std::int64_t(triangles);
  const std::int64_t most =
      std::int64_t(std::min<std::uint64_t>(budget.triangles, std::numeric_limits<std::int64_t>::max()));
  const std::uint32_t* made = h.made.data() + h.groups.size() + 1;
  while (total > most && heap.n > 0) {
    const std::uint32_t g = heap.pop();
    total -= triangles_saved(h, g);
    state[g] = std::uint8_t(state[g] & ~kVisible);
    ++res->budget_coarsened;
    res->budget_forced += (state[g] & kOverOne) != 0;
    if (!memory.empty()) memory[g] = CutGroupMemory{0, 0, kCutKnown};
    for (std::uint32_t k = h.made[g]; k < h.made[g + 1]; ++k)
      if (h.clusters[made[k]].group != kNoGroup) offer(h.clusters[made[k]].group);
  }
}

// The object as select_cut() reads it (CutObject): its pose, scale, bands and each eye's origin,
// motion, gaze and focal length. False where the pose, velocity or an eye is not usable.
bool Scheduler::Impl::cut_object(const ClusterLoss& loss, const ObjectTransform& t, const float velocity[3],
                                 CutObject* o) const {
  const std::size_t B = loss.bands_cpod.size();
  const Vec3 v = velocity ? load(velocity) : Vec3{0, 0, 0};
  const float qn = quaternion_length(t.rotation);
  bool valid = eye_count_ > 0 && finite(v) && unit_length(qn) && t.scale > 0.0f && std::isfinite(t.scale) &&
               std::isfinite(loss.diameter * t.scale);
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const EyeCache& eye = eyes_[i];
    o->origin[i] = Vec3{float(t.position[0] - eye.position[0]), float(t.position[1] - eye.position[1]),
                        float(t.position[2] - eye.position[2])};
    valid = valid && eye.valid && finite(o->origin[i]);
    const Vec3 rel = v - eye.velocity;
    o->moving[i] = rel.x != 0.0f || rel.y != 0.0f || rel.z != 0.0f || eye.omega.x != 0.0f ||
                   eye.omega.y != 0.0f || eye.omega.z != 0.0f || eye.gaze_moving;
  }
  if (!valid) return false;
  for (int k = 0; k < 4; ++k) o->q[k] = t.rotation[k] / qn;
  for (int k = 0; k < 4; ++k) o->q_inv[k] = k < 3 ? -o->q[k] : o->q[k];
  o->lost = loss.lost.data();
  o->V = std::uint32_t(loss.view_directions.size() / 3);
  o->view_dirs = o->V ? loss.view_directions.data() : nullptr;
  o->view_lost = loss.view_lost.data();
  o->ln_lost = loss.ln_lost.empty() ? nullptr : loss.ln_lost.data();
  o->ln_view_lost = loss.ln_view_lost.empty() ? nullptr : loss.ln_view_lost.data();
  o->scale = t.scale;
  o->size = loss.diameter * t.scale;
  o->bands = loss.bands_cpod.data();
  o->B = std::uint32_t(B);
  o->top_band = o->bands[0];
  for (std::size_t b = 0; b < B; ++b) {
    o->ln_band[b] = std::log(o->bands[b]);
    o->top_band = std::max(o->top_band, o->bands[b]);
  }
  o->ln_q = pre_->ln_quality;
  o->flags = 0;
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const EyeCache& eye = eyes_[i];
    if (!eye.gaze) o->flags |= kFlagNoGaze;
    o->gaze[i] = eye.gaze ? eye.gaze_dir : eye.forward;
    o->gaze_offset[i] = eye.gaze ? config_.gaze_uncertainty_deg : config_.no_gaze_radius_deg;
    o->half_focal[i] = 0.5f * eye.focal_px * kRad;
  }
  return true;
}

CutResult Scheduler::Impl::select_cut(const ClusterView& h, const ClusterLoss& loss, const ObjectTransform& t,
                                      const float velocity[3], std::span<CutGroupMemory> memory,
                                      std::span<std::uint8_t> scratch, std::span<std::uint32_t> drawn,
                                      GroupExplain* explain, const CutBudget* budget) const {
  CutResult res;
  std::uint32_t n = 0;
  const auto emit = [&](std::uint32_t c) {
    if (n < drawn.size()) drawn[n] = c;
    ++n;
    res.triangles += h.clusters[c].triangle_count;
  };
  const auto finish = [&](CutStatus status) {
    res.clusters = n;
    res.status = n > drawn.size() && !explain ? CutStatus::BufferTooSmall : status;  // explain draws none
    return res;
  };
  const auto finest = [&](CutStatus status, std::uint8_t flags) {
    for (std::uint32_t c = 0; c < h.clusters.size() && h.clusters[c].refined == kNoGroup; ++c) emit(c);
    res.flags = flags;
    return finish(status);
  };
  const std::size_t G = h.groups.size(), B = loss.bands_cpod.size();
  if (h.clusters.empty() || B == 0 || B > kMaxBands || loss.lost.size() != G * B || !(loss.diameter > 0.0f) ||
      !std::isfinite(loss.diameter) || scratch.size() < G || (!memory.empty() && memory.size() < G) ||
      loss.view_directions.size() % 3 != 0 ||
      loss.view_lost.size() != G * B * (loss.view_directions.size() / 3) ||
      (!loss.ln_lost.empty() && loss.ln_lost.size() != loss.lost.size()) ||
      (!loss.ln_view_lost.empty() && loss.ln_view_lost.size() != loss.view_lost.size()))
    return finest(CutStatus::BadHierarchy, 0);
  const bool budgeted = budget && budget->triangles > 0 && !explain;
  if (budgeted && (budget->scratch.size() < G || h.made.size() < G + 1 || h.made.size() != G + 1 + h.made[G]))
    return finest(CutStatus::BadHierarchy, 0);

  CutObject o;
  if (!cut_object(loss, t, velocity, &o)) {  // the finest cut, every group remembered visible
    for (CutGroupMemory& m : memory.first(memory.empty() ? 0 : G))
      m = CutGroupMemory{0, 0, kCutKnown | kCutVisible};
    return finest(CutStatus::InvalidInput, kFlagInvalidInput);
  }
  const CoarsenTiming timing = coarsen_timing();

  // Top down: a group is evaluated when some group holding a cluster it made is visible (or such a
  // cluster is a root) and none is invisible; either way its makers learn which it is.
  std::uint8_t* state = scratch.data();
  const Cluster* const clusters = h.clusters.data();
  std::fill_n(state, G, std::uint8_t(0));
  for (std::uint32_t r : h.roots)
    if (h.clusters[r].refined != kNoGroup) state[h.clusters[r].refined] |= kNeeded;
  // Each eye's sights of the run holding g, computed when the walk first scores one of its groups.
  GroupSights sights[2];
  const auto sight = [&](std::uint32_t i, std::size_t g) -> const GroupSights& {
    const std::size_t first = g / GroupSights::kRun * GroupSights::kRun;
    if (sights[i].first != first)
      group_sights(i, o, h.groups.data(), first, std::min(GroupSights::kRun, G - first), &sights[i]);
    return sights[i];
  };
  for (std::size_t g = G; g-- > 0;) {
    const ClusterGroup& group = h.groups[g];
    const auto j = static_cast<std::uint32_t>(g % GroupSights::kRun);
    bool visible = false;
    if (explain) {
      explain[g] = GroupExplain{};
      for (std::uint32_t i = 0; i < eye_count_; ++i) group_score(i, o, sight(i, g), j, g, &explain[g]);
    }
    if (state[g] == kNeeded) {
      ++res.groups_evaluated;
      // Under a budget, every eye and band: the budget's harm is the largest score, kept.
      float score = -kInf;
      std::uint32_t scored = 0;  // the eyes scored, which say whether they are inside
      bool inside = false;
      for (; scored < eye_count_ && (budgeted || !(score > 0.0f)); ++scored) {
        bool in = false;
        score = std::max(score, group_score(scored, o, sight(scored, g), j, g, nullptr, budgeted, &in));
        inside |= in;
      }
      if (budgeted) budget->scratch[g].harm = score;
      visible = score > 0.0f;
      if (!memory.empty())
        visible = remember_group(memory[g], visible, score, timing, pre_->ln_margin, &res.held);
      if (visible) {
        state[g] |= kVisible;
        for (std::uint32_t i = scored; i < eye_count_ && !inside; ++i)  // the eyes not scored
          inside = !(sight(i, g).nearest[j] > 0.0f);
        if (inside) o.flags |= kFlagEyeInside;
      }
    } else if (!memory.empty()) {
      memory[g] = CutGroupMemory{0, 0, kCutKnown};  // below an invisible group: not drawn finer
    }
    if (explain) explain[g].visible = visible;
    // Locals: the stores through state (bytes) may alias anything the loop would read again.
    const std::uint8_t mark = visible ? kNeeded : kBlocked;
    const Cluster* const members = clusters + group.first_member;
    for (std::uint32_t m = 0, count = group.member_count; m < count; ++m) {
      const std::uint32_t maker = members[m].refined;
      if (maker != kNoGroup) state[maker] |= mark;
    }
  }
  if (budgeted) {
    std::uint64_t total = 0;
    for_each_drawn(h, state, [&](std::uint32_t c) { total += h.clusters[c].triangle_count; });
    if (total > budget->triangles) spend_cut_budget(h, *budget, total, state, memory, &res);
  }
  for_each_drawn(h, state, emit);
  res.flags =
      std::uint8_t(o.flags | (res.held ? kFlagHeld : 0) | (res.budget_forced ? kFlagBudgetForced : 0));
  return finish(CutStatus::Ok);
}

}  // namespace acuity
