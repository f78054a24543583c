#pragma once
// acuity/clusters.hpp — detail that follows the gaze inside one object: the records of a cluster
// hierarchy (the one definition; lodgen builds and checks them, acuity/lodgen/cluster_hierarchy.hpp)
// and what the runtime's cut reads (Scheduler::select_cut, acuity/scheduler.hpp). Standard library
// only. docs/design.md section 6 ("Cluster cuts") and docs/lodgen.md ("Cluster hierarchies").
//
// The hierarchy (Nanite's DAG): the finest mesh is cut into clusters of at most kMaxClusterTriangles
// triangles; neighbouring clusters form a group, simplified to about half with its outer border
// locked and cut into coarser clusters; those form groups in turn, up to the roots (clusters in no
// group). A cut draws a cluster when the group that made it (`refined`; none for a finest cluster)
// is invisible and the group it belongs to (`group`; none for a root) is visible.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "acuity/profile.hpp"

namespace acuity {

inline constexpr std::uint32_t kNoGroup =
    0xFFFFFFFFu;  // Cluster::group of a root, ::refined of a finest cluster
inline constexpr std::uint32_t kMaxClusterTriangles = 128;  // per cluster

// One cluster: a contiguous run of the hierarchy's index array. Stored as four little-endian uint32
// (16 bytes) in lodgen's glTF extension ACUITY_cluster_hierarchy (docs/lodgen.md).
struct Cluster {
  std::uint32_t first_triangle = 0;  // into the hierarchy's indices (triangle t: indices 3t .. 3t+2)
  std::uint32_t triangle_count = 0;  // [Limit: 1 .. kMaxClusterTriangles]
  std::uint32_t group = kNoGroup;    // the group it is a member of (its parent), or kNoGroup: a root
  std::uint32_t refined = kNoGroup;  // the group whose simplification made it, or kNoGroup: finest
};

// A group of clusters, simplified together. Stored as five little-endian float32 then three uint32
// (32 bytes).
struct ClusterGroup {
  float center[3] = {0, 0, 0};     // bounding sphere of its members and of the spheres of the groups
  float radius = 0;                // that made them [object units] [Limit: >= 0, finite]
  float error = 0;                 // of the clusters it made [object units]: >= the error of every group
                                   // that made a member [Limit: >= 0, finite]
  std::uint32_t first_member = 0;  // its members: clusters[first_member, first_member + member_count)
  std::uint32_t member_count = 0;  // [Limit: >= 1]
  std::uint32_t level = 0;         // simplifications behind its members: 0 when they are finest, else
                                   // 1 + the largest level of the groups that made them
};
static_assert(sizeof(Cluster) == 16 && sizeof(ClusterGroup) == 32 && offsetof(ClusterGroup, error) == 16 &&
                  offsetof(ClusterGroup, first_member) == 20 && offsetof(ClusterGroup, level) == 28,
              "the records of ACUITY_cluster_hierarchy (docs/lodgen.md)");

// A hierarchy as the cut reads it: borrowed arrays (they must outlive every call that reads them),
// laid out as acuity/lodgen/cluster_hierarchy.hpp's ClusterHierarchy is (finest clusters first;
// a group after every group that made one of its members) and checked by
// lodgen::check_cluster_hierarchy. select_cut trusts that layout (the reader checks it at load).
struct ClusterView {
  std::span<const Cluster> clusters;
  std::span<const ClusterGroup> groups;
  std::span<const std::uint32_t> roots;  // the clusters in no group, as cluster_roots() lists them
  // Optional (a cut under a triangle budget needs it): the clusters each group made, as
  // cluster_made_index() lists them.
  std::span<const std::uint32_t> made = {};
};

// "" when `clusters` and `groups` are laid out as ClusterView requires (and lodgen writes), else the
// first fault found, naming the cluster or group: a cluster empty or over kMaxClusterTriangles,
// clusters overlapping or leaving a gap (each starts where the previous one ends) or not covering
// exactly `triangles` triangles, group or member references out of range or pointing the wrong way
// (a member whose `group` is not the group, a group made after the group it feeds, a cluster outside
// its group's members), finest clusters after coarser ones, a non-finite centre, a non-finite or
// negative radius or error, errors that decrease up the hierarchy, a sphere not containing those of
// the groups that made its members, a wrong level or one reaching `max_levels`. What select_cut
// trusts, checked once at load (lodgen::check_cluster_hierarchy adds the index array's checks; the
// C ABI's acuity_hierarchy_create runs it). Linear; allocates only the message.
std::string check_cluster_records(std::span<const Cluster> clusters, std::span<const ClusterGroup> groups,
                                  std::uint64_t triangles, std::uint32_t max_levels = 64);

// The clusters with group == kNoGroup, in order (once per hierarchy, at load; allocates).
std::vector<std::uint32_t> cluster_roots(std::span<const Cluster> clusters);

// The clusters each group made (Cluster::refined), grouped by their maker (once per hierarchy, at
// load; allocates): G + 1 offsets, then the ids; group g made the clusters out[G + 1 + out[g]] ..
// out[G + 1 + out[g + 1] - 1], in increasing order. ClusterView::made. Clusters naming a maker of
// group_count or more are left out (check_cluster_records rejects them).
std::vector<std::uint32_t> cluster_made_index(std::span<const Cluster> clusters, std::size_t group_count);

// What each group's simplification loses, per band: lost[g * bands.size() + b] is the largest
// local band contrast (docs/design.md section 3) that group g's clusters lose against the finest
// mesh, over every view and orientation, in the band of centre bands_cpod[b] cycles per `diameter`.
// Measured per group by `acuity profile` of a cluster hierarchy's glTF (the profile's Clusters
// section, measured_group_loss()); for a chain profile, provisional_group_loss() derives it. A NaN
// entry counts as visible (the group is refined).
struct ClusterLoss {
  std::span<const float>
      bands_cpod;               // band centres [cycles per diameter], increasing [Size: B, 1 .. kMaxBands]
  float diameter = 0;           // the length the bands are per [object units] [Limit: > 0, finite]
  std::span<const float> lost;  // [Size: groups x B] [Unit: contrast]
  // Optional (both empty, or both sized): the loss per view cell (the profile's ClusterViews
  // section). view_lost[(g * V + v) * B + b] is what group g loses in band b seen from within the
  // cell of view_directions[3v .. 3v+2] (a unit vector from the object towards the eye, object
  // space; a cell is the directions nearer to it than to any other); the cut reads the cell the eye
  // is in from each group's centre. Each value is at most lost's of its group and band.
  std::span<const float> view_directions = {};  // [Size: V x 3, V 0 .. kMaxClusterViews]
  std::span<const float> view_lost = {};        // [Size: groups x V x B] [Unit: contrast]
  // Optional: the natural logs of lost and of view_lost (each empty, or of its size: loss_logs() makes
  // them once at load), which the cut reads instead of taking a log per band of every group it
  // evaluates each frame (most of its arithmetic). The same cut either way.
  std::span<const float> ln_lost = {};
  std::span<const float> ln_view_lost = {};
};

// The directions a ClusterViews section must have measured per group for measured_group_loss to read
// its cells: with fewer (42 over 12 cells) a cell's row bounds only 0.90 of what a group loses from
// directions within the cell (tests/test_cluster_loss.cpp), too optimistic for the cut.
inline constexpr std::uint32_t kMinCellSamples = 162;

// ln of each value (std::log: 0 gives -inf, NaN stays NaN): ClusterLoss::ln_lost and ln_view_lost,
// made once when a hierarchy's loss is loaded. Allocates.
std::vector<float> loss_logs(std::span<const float> values);

// FNV-1a 64 over a hierarchy's records as stored (the clusters' bytes, then the groups'): the name a
// profile's Clusters section gives the hierarchy it measured. Linear; no allocation.
std::uint64_t cluster_hierarchy_hash(std::span<const Cluster> clusters, std::span<const ClusterGroup> groups);

enum class GroupLossStatus : std::uint8_t {
  Measured,        // *loss reads the profile's Clusters section
  NoSection,       // the profile has none (a chain's profile): provisional_group_loss() is the fallback
  OtherHierarchy,  // its group count or hierarchy hash differ: it measured another hierarchy
};
const char* to_string(GroupLossStatus status);

// The per-group loss a profile's Clusters section measured for this hierarchy (issue 48 item 2;
// acuity/spectra/cluster_loss.hpp measures it): sets *loss to read the profile's bytes in place
// (its cluster bands, Meta's sphere's diameter, its lost values, and the ClusterViews section's cells
// when it has one measured from at least kMinCellSamples directions, else none), which must outlive
// it. On any
// other status *loss is unchanged. No allocation.
GroupLossStatus measured_group_loss(const Profile& profile, std::span<const Cluster> clusters,
                                    std::span<const ClusterGroup> groups, ClusterLoss* loss);

// The documented FALLBACK for a profile without a Clusters section: per-group loss derived from the
// object's ordinary chain profile (`acuity profile` of `acuity lodgen MESH`'s chain of the same mesh
// as `acuity lodgen MESH --clusters`). It gives every group the whole chain level's loss in bands
// per object diameter, which keeps large objects fine everywhere (docs/lodgen.md). For a group of
// error e [object units], e / the profile's bounding-sphere diameter in object diameters (the unit
// of the chain's geometric errors):
//   - per band, the loss (max over views and orientations) of the finest chain level whose
//     geometric error is >= e, made non-decreasing along the chain by a running maximum over the
//     finer levels, so that loss grows with error; a group of error 0 loses nothing;
//   - beyond the coarsest level (error e_K): that level's loss x e / e_K, capped at 1; a chain of one
//     level (or a coarsest error of 0) gives 1, which is visible wherever anything is.
// Sets *loss's bands and diameter to the profile's (bands_cpod points into the profile, whose bytes
// must outlive it) and its lost to the returned array (which it must outlive). Allocates; at load.
std::vector<float> provisional_group_loss(const Profile& profile, std::span<const ClusterGroup> groups,
                                          ClusterLoss* loss);

// What select_cut did (Scheduler::select_cut).
enum class CutStatus : std::uint8_t {
  Ok,              // the perceptual cut (under a budget: coarsened to meet it, as far as it can be)
  InvalidInput,    // non-finite or non-unit transform, scale <= 0, non-finite velocity, or no valid
                   // eye: the finest cut (kFlagInvalidInput)
  BadHierarchy,    // loss or hierarchy arrays of mismatched sizes (lost != groups x bands, no band,
                   // over kMaxBands, a diameter <= 0, scratch smaller than the groups, no clusters,
                   // view_lost != groups x views x bands, logs of other sizes than their values;
                   // with a budget, CutBudget::scratch smaller than the groups or ClusterView::made
                   // not of cluster_made_index()'s size):
                   // the finest cut
  BufferTooSmall,  // `drawn` could not hold the cut: `clusters` says how many it needs, nothing usable written
};
const char* to_string(CutStatus status);

struct CutResult {
  CutStatus status = CutStatus::Ok;
  std::uint8_t flags = 0;       // ObjectFlag bits: kFlagInvalidInput, kFlagEyeInside, kFlagNoGaze, kFlagHeld,
                                // kFlagBudgetForced
  std::uint32_t clusters = 0;   // drawn (or needed, BufferTooSmall)
  std::uint64_t triangles = 0;  // drawn
  std::uint32_t groups_evaluated = 0;  // groups whose thresholds were evaluated (the walk's work)
  std::uint32_t held = 0;  // groups kept visible by hysteresis or saccade gating (with memory; kFlagHeld)
  std::uint32_t budget_coarsened = 0;  // visible groups the triangle budget coarsened (CutBudget)
  std::uint32_t budget_forced = 0;     // ... of them with a score > 1: a visible loss (kFlagBudgetForced)
};

// One entry of a budgeted cut's scratch (CutBudget::scratch): storage the caller gives, one per
// group; what it holds between the calls is not read (each call starts afresh). 8 bytes.
struct CutCandidate {
  float harm = 0;
  std::uint32_t group = 0;
};
static_assert(sizeof(CutCandidate) == 8, "CutCandidate's layout (the C ABI's cut memory)");

// A triangle budget for one cut (Scheduler::select_cut with a budget): when the perceptual cut draws
// more than `triangles`, coarsen the visible groups whose loss is least visible first.
struct CutBudget {
  std::uint64_t triangles = 0;           // the most the cut should draw; 0: no budget
  std::span<CutCandidate> scratch = {};  // the caller's, at least one per group when triangles > 0
};

// What a cut remembers of one group from one frame to the next (Scheduler::select_cut with memory),
// as the object rule remembers an object's wait to coarsen: the caller's, one per group and object,
// zero-initialised (nothing remembered: the next cut takes each group's decision at once, as a new
// object takes its level). Written only by select_cut. 12 bytes, no padding (the C ABI passes it as
// bytes: ACUITY_CUT_MEMORY_BYTES_PER_GROUP).
struct CutGroupMemory {
  float calm = 0;           // how long the group has been wanted invisible, this frame included [s of dt, or
                            // frames: SchedulerConfig's timing]
  float wait = 0;           // how long it has since waited for a saccade [same unit]
  std::uint32_t state = 0;  // kCutKnown | kCutVisible as the last cut left it
};
inline constexpr std::uint32_t kCutKnown = 1;    // CutGroupMemory::state: a cut has decided the group
inline constexpr std::uint32_t kCutVisible = 2;  // ... and it was visible (its members, or finer, drawn)
static_assert(sizeof(CutGroupMemory) == 12, "CutGroupMemory's layout (the C ABI's bytes per group)");

// Why a group is visible or not (Scheduler::explain_cut): its score and what limits it.
struct GroupExplain {
  float score = 0;             // max over eyes and bands of lost / (q CT); <= 1 invisible; +inf for an
                               // eye inside its sphere or a NaN loss
  std::uint8_t band = 0;       // the limiting band (index into ClusterLoss::bands_cpod)
  std::uint8_t eye = 0;        // the limiting eye (0 or 1)
  std::uint8_t flags = 0;      // kFlagEyeInside, kFlagNoGaze
  std::uint8_t visible = 0;    // 1: the cut this frame (explain_cut's own walk, no memory) refines it
  float frequency_cpd = 0;     // that band's frequency at the group's nearest point [cpd]
  float threshold = 0;         // CT there (at quality 1)
  float distance_m = 0;        // from the limiting eye to the nearest point of the group's sphere [m]
  float eccentricity_deg = 0;  // of that point from the gaze, less the gaze uncertainty [deg]
};

}  // namespace acuity
