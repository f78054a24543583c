// The layout checks of a cluster hierarchy's records (acuity/clusters.hpp, check_cluster_records): the
// one place they live (lodgen's check_cluster_hierarchy adds the index array's; the C ABI's
// acuity_hierarchy_create runs these alone). At load, never per frame: allocates only the message.
// Every sum is taken in 64 bits from 32-bit fields, so no check can overflow.
#include <algorithm>
#include <cmath>
#include <string>

#include "acuity/clusters.hpp"

namespace acuity {
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

std::string check_clusters(std::span<const Cluster> clusters, std::size_t group_count,
                           std::uint64_t triangles) {
  std::uint64_t end = 0;  // where the previous cluster ended [triangles]
  bool coarse_seen = false;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    const Cluster& k = clusters[c];
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
    if (k.group != kNoGroup && k.group >= group_count)
      return at + " names group " + std::to_string(k.group) + ", which does not exist";
    if (k.refined != kNoGroup && k.refined >= group_count)
      return at + " was made by group " + std::to_string(k.refined) + ", which does not exist";
    if (k.refined != kNoGroup && k.group != kNoGroup && k.refined >= k.group)
      return at + " was made by group " + std::to_string(k.refined) + " but belongs to group " +
             std::to_string(k.group) + ", which is not made after it";
    if (k.refined != kNoGroup)
      coarse_seen = true;
    else if (coarse_seen)
      return at + " is a finest cluster after coarser ones (the finest mesh must come first)";
  }
  if (end != triangles)
    return "the clusters cover " + std::to_string(end) + " of the index array's " +
           std::to_string(triangles) + " triangles";
  return {};
}

std::string check_groups(std::span<const Cluster> clusters, std::span<const ClusterGroup> groups,
                         std::uint32_t max_levels) {
  std::uint64_t end = 0, members = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const ClusterGroup& p = groups[g];
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
    if (end > clusters.size())
      return at + ": members " + std::to_string(p.first_member) + " .. " + std::to_string(end - 1) +
             " leave the " + std::to_string(clusters.size()) + " clusters";
    members += p.member_count;
    std::uint32_t level = 0;
    for (std::size_t c = p.first_member; c < end; ++c) {
      const Cluster& k = clusters[c];
      if (k.group != g)
        return at + " lists " + cluster_name(c) + ", which names group " + std::to_string(k.group);
      if (k.refined == kNoGroup) continue;
      const ClusterGroup& child = groups[k.refined];  // k.refined < g: checked with the clusters
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
    if (p.level >= max_levels)
      return at + ": level " + std::to_string(p.level) + " reaches the limit max_levels (" +
             std::to_string(max_levels) + ")";
  }
  std::uint64_t grouped = 0;
  for (const Cluster& k : clusters) grouped += k.group != kNoGroup;
  if (grouped != members)
    return std::to_string(grouped) + " clusters name a group, but the groups list " +
           std::to_string(members) + " members (a cluster lies outside its group's members)";
  return {};
}

}  // namespace

std::string check_cluster_records(std::span<const Cluster> clusters, std::span<const ClusterGroup> groups,
                                  std::uint64_t triangles, std::uint32_t max_levels) {
  if (std::string e = check_clusters(clusters, groups.size(), triangles); !e.empty()) return e;
  return check_groups(clusters, groups, max_levels);
}

}  // namespace acuity
