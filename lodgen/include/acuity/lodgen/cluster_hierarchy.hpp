#pragma once
// acuity/lodgen/cluster_hierarchy.hpp — a mesh's cluster hierarchy as flat arrays, and the checks a
// loaded one must pass. Standard library only (no lodgen type, no exception); the records are the
// runtime's (acuity/clusters.hpp).
//
// The hierarchy (Nanite's DAG; meshoptimizer's demo/clusterlod.h): the finest mesh is cut into
// clusters of at most kMaxClusterTriangles triangles; neighbouring clusters form a group; the group
// is simplified to about half with its outer border locked and cut into new, coarser clusters; those
// form groups in turn, up to the roots (clusters in no group). Every cluster has
//   - its own error: the error of the group whose simplification made it (`refined`), 0 for a
//     finest cluster, and
//   - its parent's error: the error of the group it belongs to (`group`), infinite for a root.
// A cut draws a cluster when its own error is invisible and its parent's is visible. Since a
// group's error is at least the errors of the groups that made its members and its sphere contains
// theirs (check_cluster_hierarchy rejects anything else), any error test that grows with the error
// and shrinks with the distance from the sphere (projected error: error / (distance to the centre -
// radius)) picks, for every group, all its members or all the clusters it made, never a mix: the
// cut has no crack. Errors and spheres are in the mesh's object units.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "acuity/clusters.hpp"

namespace acuity::lodgen {

// The records (Cluster, ClusterGroup) and their constants have one definition, the runtime's
// (acuity/clusters.hpp, which Scheduler::select_cut reads); lodgen names them here.
using acuity::Cluster;
using acuity::ClusterGroup;
using acuity::kMaxClusterTriangles;
using acuity::kNoGroup;

// The whole hierarchy of one mesh; vertices are the mesh's own (a glTF primitive's attributes).
// Layout (what check_cluster_hierarchy requires): clusters cover `indices` in order, each starting
// where the previous one ends; the finest clusters come first, so the finest mesh is the first
// finest_triangles() triangles; groups list their members as consecutive clusters, in the order
// of the groups; a group comes after every group that made one of its members.
struct ClusterHierarchy {
  std::vector<std::uint32_t> indices;  // three per triangle, into the mesh's vertices
  std::vector<Cluster> clusters;
  std::vector<ClusterGroup> groups;

  bool empty() const { return clusters.empty(); }
  std::size_t finest_triangles() const;  // triangles of the clusters with refined == kNoGroup
  std::size_t levels() const;            // 1 + the largest group level, 0 without groups
};

// What a hierarchy from an untrusted file may hold; checked before the per-element work.
struct ClusterLimits {
  std::uint64_t max_clusters = 1u << 22;
  std::uint64_t max_groups = 1u << 22;
  std::uint32_t max_levels = 64;  // group levels (each level halves the triangles)
};

// "" when `h` is a valid hierarchy over `vertex_count` vertices, else the first fault found, naming
// the cluster or group: counts past `limits`, a cluster empty or over kMaxClusterTriangles, clusters
// overlapping or leaving a gap (first_triangle not where the previous one ends), triangles past the
// index array or indices past the vertices, offsets whose sum overflows, group or member references
// out of range or pointing the wrong way (a member whose `group` is not the group, a group made after
// the group it feeds), a non-finite or negative error or radius, errors that are not monotone (a
// group's error below that of a group that made one of its members), a sphere that does not contain
// such a group's sphere, finest clusters after coarser ones, a wrong level or one past
// limits.max_levels. Linear in the hierarchy's size; allocates only the message.
std::string check_cluster_hierarchy(const ClusterHierarchy& h, std::size_t vertex_count,
                                    const ClusterLimits& limits = {});

}  // namespace acuity::lodgen
