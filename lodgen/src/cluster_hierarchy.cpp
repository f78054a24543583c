// The checks a cluster hierarchy passes before anything uses it (acuity/lodgen/cluster_hierarchy.hpp):
// the records' layout is the runtime's check (acuity::check_cluster_records), the index array's here.
// Standard library only, like the header.
#include "acuity/lodgen/cluster_hierarchy.hpp"

#include <algorithm>
#include <cmath>

namespace acuity::lodgen {
std::size_t ClusterHierarchy::finest_triangles() const {
  std::size_t n = 0;
  for (const Cluster& c : clusters)
    if (c.refined == kNoGroup) n += c.triangle_count;
  return n;
}

std::size_t ClusterHierarchy::levels() const {
  std::size_t n = 0;
  for (const ClusterGroup& g : groups) n = std::max<std::size_t>(n, g.level + 1);
  return n;
}

std::string check_cluster_hierarchy(const ClusterHierarchy& h, std::size_t vertex_count,
                                    const ClusterLimits& limits) {
  if (h.clusters.size() > limits.max_clusters)
    return std::to_string(h.clusters.size()) + " clusters, more than the limit max_clusters (" +
           std::to_string(limits.max_clusters) + ")";
  if (h.groups.size() > limits.max_groups)
    return std::to_string(h.groups.size()) + " groups, more than the limit max_groups (" +
           std::to_string(limits.max_groups) + ")";
  if (h.clusters.empty() && !h.indices.empty()) return "indices but no clusters";
  if (h.indices.size() % 3) return std::to_string(h.indices.size()) + " indices, not whole triangles";
  if (std::string e = check_cluster_records(h.clusters, h.groups, h.indices.size() / 3, limits.max_levels);
      !e.empty())
    return e;
  // The clusters cover the index array exactly (checked above): each index within the vertices.
  for (std::size_t c = 0; c < h.clusters.size(); ++c) {
    const Cluster& k = h.clusters[c];
    const std::uint64_t end = 3 * (std::uint64_t(k.first_triangle) + k.triangle_count);
    for (std::uint64_t i = 3 * std::uint64_t(k.first_triangle); i < end; ++i)
      if (h.indices[std::size_t(i)] >= vertex_count)
        return "cluster " + std::to_string(c) + ": index " + std::to_string(h.indices[std::size_t(i)]) +
               " (element " + std::to_string(i) + ") leaves the " + std::to_string(vertex_count) +
               " vertices";
  }
  return {};
}

}  // namespace acuity::lodgen
