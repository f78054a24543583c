// The checks a cluster hierarchy passes before anything uses it (acuity/lodgen/cluster_hierarchy.hpp).
// Standard library only, like the header. Every sum is taken in 64 bits from 32-bit fields, so no
// check can overflow.
#include "acuity/lodgen/cluster_hierarchy.hpp"

#include <algorithm>
#include <cmath>

namespace acuity::lodgen {
namespace {

std::string cluster_name(std::size_t c) { return "cluster " + std::to_string(c); }
std::string group_name(std::size_t g) { return "group " + std::to_string(g); }

bool finite_nonnegative(float x) { return std::isfinite(x) && x >= 0; }

// Whether sphere `outer` contains sphere `inner`, in double arithmetic on the stored floats.
bool contains(const ClusterGroup& outer, const ClusterGroup& inner) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = double(outer.center[k]) - double(inner.center[k]);
    d2 += d * d;
  }
  return std::sqrt(d2) + double(inner.radius) <= double(outer.radius);
}

std::string check_clusters(const ClusterHierarchy& h, std::size_t vertex_count) {
  const std::uint64_t triangles = h.indices.size() / 3;
  std::uint64_t end = 0;  // where the previous cluster ended [triangles]
  bool coarse_seen = false;
  for (std::size_t c = 0; c < h.clusters.size(); ++c) {
    const Cluster& k = h.clusters[c];
    const std::string at = cluster_name(c);
    if (k.triangle_count == 0 || k.triangle_count > kMaxClusterTriangles)
      return at + ": " + std::to_string(k.triangle_count) + " triangles, not 1 .. " +
             std::to_string(kMaxClusterTriangles);
    if (k.first_triangle < end)
      return at + " overlaps the cluster before it: it starts at triangle " +
             std::to_string(k.first_triangle) + ", which that one holds (it ends at " + std::to_string(end) +
             ")";
    if (k.first_triangle > end)
      return at + " leaves a gap: it starts at triangle " + std::to_string(k.first_triangle) +
             ", the cluster before it ends at " + std::to_string(end);
    end = std::uint64_t(k.first_triangle) + k.triangle_count;
    if (end > triangles)
      return at + ": triangles " + std::to_string(k.first_triangle) + " .. " + std::to_string(end - 1) +
             " leave the index array of " + std::to_string(triangles) + " triangles";
    for (std::uint64_t i = 3 * std::uint64_t(k.first_triangle); i < 3 * end; ++i)
      if (h.indices[std::size_t(i)] >= vertex_count)
        return at + ": index " + std::to_string(h.indices[std::size_t(i)]) + " (element " +
               std::to_string(i) + ") leaves the " + std::to_string(vertex_count) + " vertices";
    if (k.group != kNoGroup && k.group >= h.groups.size())
      return at + " names group " + std::to_string(k.group) + ", which does not exist";
    if (k.refined != kNoGroup && k.refined >= h.groups.size())
      return at + " was made by group " + std::to_string(k.refined) + ", which does not exist";
    if (k.refined != kNoGroup && k.group != kNoGroup && k.refined >= k.group)
      return at + " was made by group " + std::to_string(k.refined) + " but belongs to group " +
             std::to_string(k.group) + ", which is not made after it";
    if (k.refined != kNoGroup)
      coarse_seen = true;
    else if (coarse_seen)
      return at + " is a finest cluster after coarser ones (the finest mesh must come first)";
  }
  if (end != triangles || h.indices.size() % 3)
    return "the clusters cover " + std::to_string(end) + " of the " + std::to_string(h.indices.size()) +
           " indices' triangles";
  return {};
}

std::string check_groups(const ClusterHierarchy& h, const ClusterLimits& limits) {
  std::uint64_t end = 0, members = 0;
  for (std::size_t g = 0; g < h.groups.size(); ++g) {
    const ClusterGroup& p = h.groups[g];
    const std::string at = group_name(g);
    for (float x : p.center)
      if (!std::isfinite(x)) return at + ": its centre is not finite";
    if (!finite_nonnegative(p.radius))
      return at + ": radius " + std::to_string(p.radius) + " is not finite, >= 0";
    if (!finite_nonnegative(p.error))
      return at + ": error " + std::to_string(p.error) + " is not finite, >= 0";
    if (p.member_count == 0) return at + " has no members";
    if (p.first_member < end)
      return at + "'s members (from cluster " + std::to_string(p.first_member) +
             ") overlap the previous group's (up to cluster " + std::to_string(end) + ")";
    end = std::uint64_t(p.first_member) + p.member_count;
    if (end > h.clusters.size())
      return at + ": members " + std::to_string(p.first_member) + " .. " + std::to_string(end - 1) +
             " leave the " + std::to_string(h.clusters.size()) + " clusters";
    members += p.member_count;
    std::uint32_t level = 0;
    for (std::size_t c = p.first_member; c < end; ++c) {
      const Cluster& k = h.clusters[c];
      if (k.group != g)
        return at + " lists " + cluster_name(c) + ", which names group " + std::to_string(k.group);
      if (k.refined == kNoGroup) continue;
      const ClusterGroup& child = h.groups[k.refined];  // k.refined < g: checked with the clusters
      if (!(p.error >= child.error))
        return at + ": error " + std::to_string(p.error) + " is below the error " +
               std::to_string(child.error) + " of group " + std::to_string(k.refined) +
               ", which made its member " + cluster_name(c) + " (errors must not decrease up the hierarchy)";
      if (!contains(p, child))
        return at + "'s bounding sphere does not contain the sphere of group " + std::to_string(k.refined) +
               ", which made its member " + cluster_name(c);
      level = std::max(level, child.level + 1);  // child.level <= max_levels: checked before
    }
    if (p.level != level)
      return at + ": level " + std::to_string(p.level) + ", but its members make it " + std::to_string(level);
    if (p.level >= limits.max_levels)
      return at + ": level " + std::to_string(p.level) + " reaches the limit max_levels (" +
             std::to_string(limits.max_levels) + ")";
  }
  std::uint64_t grouped = 0;
  for (const Cluster& k : h.clusters) grouped += k.group != kNoGroup;
  if (grouped != members)
    return std::to_string(grouped) + " clusters name a group, but the groups list " +
           std::to_string(members) + " members (a cluster lies outside its group's members)";
  return {};
}

}  // namespace

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
  if (std::string e = check_clusters(h, vertex_count); !e.empty()) return e;
  return check_groups(h, limits);
}

}  // namespace acuity::lodgen
