#pragma once
// acuity/lodgen/clusters.hpp — building a mesh's cluster hierarchy (`acuity lodgen --clusters`).
// The result's layout and the cut it supports: acuity/lodgen/cluster_hierarchy.hpp; how it is
// stored in glTF: docs/lodgen.md (ACUITY_cluster_hierarchy).
#include <cstddef>

#include "acuity/lodgen/cluster_hierarchy.hpp"
#include "acuity/lodgen/mesh.hpp"

namespace acuity::lodgen {

struct ClusterOptions {
  std::size_t max_triangles = kMaxClusterTriangles;  // per cluster [Limit: 4 .. 128, a multiple of 4]
  std::size_t group_size = 8;  // clusters per group (METIS parts of about this many) [Limit: >= 2]
  double ratio = 0.5;          // a group's simplification aims at this share of its triangles [Limit: (0, 1)]
  // A group whose simplification keeps more than this share of its triangles (its locked border
  // leaves too little to remove) is not recorded: its members join the next level's clusters, to be
  // grouped with other neighbours, or become roots when they are finest clusters or no group of
  // their level simplified. [Limit: (ratio, 1]]
  double max_kept = 0.85;
};

struct ClusterStats {
  std::size_t stuck_groups = 0;  // groups not recorded by max_kept
  double seconds = 0;            // the whole build
};

// The hierarchy of `mesh` (lodgen's level 0: repaired and split at creases as build_chain makes
// it; one material). Its indices point into mesh's own vertices, which it neither moves nor adds
// to: the finest clusters hold exactly mesh's triangles (in another order); coarser clusters are
// made by meshoptimizer's simplifier (0.18, meshopt_SimplifyLockBorder) on a group's triangles with
// vertices kept in place, so crease and texture seams (vertices at one position with different
// normals or texture coordinates) collapse only along themselves, as in lodgen's chains, and the
// group's outer border (its edges used by one of its triangles) stays exactly as it was.
// Clusters come from meshopt_buildMeshlets; groups are METIS parts of the graph of clusters sharing
// edges (positions welded exactly). A group's error is meshoptimizer's error estimate of its
// simplification in object units, raised to the largest error of the groups that made its members;
// its sphere bounds its members' vertices and those groups' spheres. Levels continue until one
// cluster is left, or no group of a level simplifies (ClusterOptions::max_kept), or the level limit
// a reader enforces (ClusterLimits::max_levels) is reached.
// Throws InputError naming `where` for a mesh with no triangles or indices out of range, and
// std::invalid_argument for options out of their limits.
ClusterHierarchy build_clusters(const Mesh& mesh, const std::string& where,
                                const ClusterOptions& options = {}, ClusterStats* stats = nullptr);

}  // namespace acuity::lodgen
