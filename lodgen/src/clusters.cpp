// A mesh's cluster hierarchy (acuity/lodgen/clusters.hpp): meshlets, METIS groups, locked-border
// simplification, level after level. The scheme is Nanite's (Karis et al., "Nanite: a deep dive",
// SIGGRAPH 2021) as meshoptimizer's demo/clusterlod.h shows it; the code is lodgen's own.
#include "acuity/lodgen/clusters.hpp"

#include <meshoptimizer.h>
#include <metis.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace acuity::lodgen {
namespace {

// A cluster while the hierarchy is built: its triangles (mesh vertex ids) and where it came from.
struct Work {
  std::vector<std::uint32_t> indices;
  std::uint32_t refined = kNoGroup;
  std::uint32_t group = kNoGroup;
};

// One id per distinct position (exact float equality; -0 and 0 are one position): what decides
// which clusters touch and where a cut could open.
std::vector<std::uint32_t> weld(const Mesh& mesh) {
  struct Key {
    std::uint32_t bits[3];
    bool operator==(const Key& o) const { return std::memcmp(bits, o.bits, sizeof bits) == 0; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return (std::size_t(k.bits[0]) * 73856093u) ^ (std::size_t(k.bits[1]) * 19349663u) ^
             (std::size_t(k.bits[2]) * 83492791u);
    }
  };
  std::unordered_map<Key, std::uint32_t, Hash> ids;
  ids.reserve(mesh.vertex_count());
  std::vector<std::uint32_t> out(mesh.vertex_count());
  for (std::size_t v = 0; v < out.size(); ++v) {
    Key k{};
    for (int c = 0; c < 3; ++c) {
      const float x = mesh.positions[3 * v + std::size_t(c)] + 0.0f;  // -0 becomes 0
      std::memcpy(&k.bits[c], &x, 4);
    }
    out[v] = ids.emplace(k, std::uint32_t(ids.size())).first->second;
  }
  return out;
}

// The mesh's vertices an index list uses, numbered from 0 (what meshoptimizer sees, so that its
// work and memory follow the group's size, not the mesh's).
struct Local {
  std::vector<std::uint32_t> vertices;  // local -> mesh vertex
  std::vector<std::uint32_t> indices;   // the triangles in local ids
  std::vector<float> positions;         // xyz per local vertex
};
Local localise(const Mesh& mesh, const std::vector<std::uint32_t>& indices,
               std::vector<std::uint32_t>& scratch) {
  Local l;
  l.indices.reserve(indices.size());
  for (std::uint32_t v : indices) {
    if (scratch[v] == kNoGroup) {
      scratch[v] = std::uint32_t(l.vertices.size());
      l.vertices.push_back(v);
      l.positions.insert(l.positions.end(), &mesh.positions[3 * std::size_t(v)],
                         &mesh.positions[3 * std::size_t(v)] + 3);
    }
    l.indices.push_back(scratch[v]);
  }
  for (std::uint32_t v : l.vertices) scratch[v] = kNoGroup;  // ready for the next call
  return l;
}

// meshopt_buildMeshlets over `local`'s triangles: clusters of at most max_triangles, in mesh ids.
std::vector<Work> split(const Local& local, std::size_t max_triangles, std::uint32_t refined) {
  const std::size_t max_vertices = 255;  // meshoptimizer 0.18's limit: the triangle count binds first
  const std::size_t bound = meshopt_buildMeshletsBound(local.indices.size(), max_vertices, max_triangles);
  std::vector<meshopt_Meshlet> meshlets(bound);
  std::vector<unsigned int> vertices(bound * max_vertices);
  std::vector<unsigned char> triangles(bound * max_triangles * 3);
  meshlets.resize(meshopt_buildMeshlets(
      meshlets.data(), vertices.data(), triangles.data(), local.indices.data(), local.indices.size(),
      local.positions.data(), local.vertices.size(), 3 * sizeof(float), max_vertices, max_triangles, 0.0f));
  std::vector<Work> out(meshlets.size());
  for (std::size_t m = 0; m < meshlets.size(); ++m) {
    const meshopt_Meshlet& ml = meshlets[m];
    out[m].refined = refined;
    for (std::size_t i = 0; i < std::size_t(ml.triangle_count) * 3; ++i)
      out[m].indices.push_back(
          local.vertices[vertices[ml.vertex_offset + triangles[ml.triangle_offset + i]]]);
  }
  return out;
}

// Clusters into parts of about `group_size` that share many edges: METIS k-way partitioning of the
// graph whose nodes are clusters and whose edges, weighted by their count, are the welded mesh
// edges two clusters share.
std::vector<std::vector<std::uint32_t>> partition(const std::vector<Work>& clusters,
                                                  const std::vector<std::uint32_t>& position_id,
                                                  std::size_t group_size) {
  const std::size_t n = clusters.size();
  const std::size_t parts = (n + group_size - 1) / group_size;
  if (parts <= 1) {
    std::vector<std::uint32_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = std::uint32_t(i);
    return {all};
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // (welded edge, cluster)
  for (std::size_t c = 0; c < n; ++c) {
    const std::vector<std::uint32_t>& ix = clusters[c].indices;
    for (std::size_t t = 0; t < ix.size(); t += 3)
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t a = position_id[ix[t + std::size_t(k)]],
                            b = position_id[ix[t + std::size_t((k + 1) % 3)]];
        edges.push_back({std::min(a, b) << 32 | std::max(a, b), std::uint32_t(c)});
      }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::pair<std::uint64_t, idx_t>> links;  // (cluster a << 32 | cluster b, weight 1 each)
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    for (std::size_t a = i; a < j; ++a)
      for (std::size_t b = i; b < j; ++b)
        if (edges[a].second != edges[b].second)
          links.push_back({std::uint64_t(edges[a].second) << 32 | edges[b].second, 1});
    i = j;
  }
  std::sort(links.begin(), links.end());
  std::vector<idx_t> xadj(n + 1, 0), adjncy, adjwgt;
  for (std::size_t i = 0; i < links.size();) {
    std::size_t j = i;
    while (j < links.size() && links[j].first == links[i].first) ++j;
    const std::size_t from = std::size_t(links[i].first >> 32);
    adjncy.push_back(idx_t(links[i].first & 0xFFFFFFFFu));
    adjwgt.push_back(idx_t(j - i));
    ++xadj[from + 1];
    i = j;
  }
  for (std::size_t c = 0; c < n; ++c) xadj[c + 1] += xadj[c];
  idx_t nvtxs = idx_t(n), ncon = 1, nparts = idx_t(parts), objval = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 1;  // the same hierarchy every run
  std::vector<idx_t> part(n, 0);
  idx_t dummy = 0;  // METIS wants non-null arrays even for a graph without edges
  if (METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adjncy.empty() ? &dummy : adjncy.data(), nullptr,
                          nullptr, adjwgt.empty() ? &dummy : adjwgt.data(), &nparts, nullptr, nullptr,
                          options, &objval, part.data()) != METIS_OK)
    throw std::runtime_error("METIS cannot partition " + std::to_string(n) + " clusters");
  std::vector<std::vector<std::uint32_t>> out(parts);
  for (std::size_t c = 0; c < n; ++c) out[std::size_t(part[c])].push_back(std::uint32_t(c));
  out.erase(std::remove_if(out.begin(), out.end(), [](const auto& p) { return p.empty(); }), out.end());
  return out;
}

// The sphere around `local`'s vertices (box centre, farthest vertex), grown to contain every sphere
// of `children`; stored as floats whose radius still contains them when checked in double
// arithmetic (check_cluster_hierarchy).
ClusterGroup bounding_sphere(const Local& local, const std::vector<const ClusterGroup*>& children) {
  double lo[3] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                  std::numeric_limits<double>::max()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  for (std::size_t i = 0; i < local.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], double(local.positions[i]));
    hi[i % 3] = std::max(hi[i % 3], double(local.positions[i]));
  }
  double c[3] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2}, r = 0;
  for (std::size_t i = 0; i < local.positions.size(); i += 3)
    r = std::max(r, std::hypot(local.positions[i] - c[0], local.positions[i + 1] - c[1],
                               local.positions[i + 2] - c[2]));
  for (const ClusterGroup* g : children) {  // grow to hold the child sphere
    const double d = std::hypot(g->center[0] - c[0], g->center[1] - c[1], g->center[2] - c[2]);
    if (d + g->radius <= r) continue;
    const double grown = (d + r + g->radius) / 2;
    if (d > 0)
      for (int k = 0; k < 3; ++k) c[k] += (g->center[k] - c[k]) * (grown - r) / d;
    r = std::max(grown, double(g->radius));
  }
  ClusterGroup out;
  for (int k = 0; k < 3; ++k) out.center[k] = float(c[k]);
  out.radius = std::nextafter(float(r), std::numeric_limits<float>::infinity());
  auto holds = [&](const ClusterGroup& child) {
    const double d =
        std::hypot(double(out.center[0]) - child.center[0], double(out.center[1]) - child.center[1],
                   double(out.center[2]) - child.center[2]);
    return d + double(child.radius) <= double(out.radius);
  };
  for (const ClusterGroup* g : children)
    while (!holds(*g)) out.radius = std::nextafter(out.radius, std::numeric_limits<float>::infinity());
  return out;
}

void check(const ClusterOptions& o) {
  if (o.max_triangles < 4 || o.max_triangles > kMaxClusterTriangles || o.max_triangles % 4)
    throw std::invalid_argument("clusters: max_triangles must be a multiple of 4 in 4 .. 128");
  if (o.group_size < 2) throw std::invalid_argument("clusters: group_size must be >= 2");
  if (!(o.ratio > 0 && o.ratio < 1)) throw std::invalid_argument("clusters: ratio must lie in (0, 1)");
  if (!(o.max_kept > o.ratio && o.max_kept <= 1))
    throw std::invalid_argument("clusters: max_kept must lie in (ratio, 1]");
}

}  // namespace

ClusterHierarchy build_clusters(const Mesh& mesh, const std::string& where, const ClusterOptions& o,
                                ClusterStats* stats) {
  check(o);
  const auto start = std::chrono::steady_clock::now();
  if (mesh.triangle_count() == 0) throw InputError(where + ": no triangles to cluster");
  for (std::uint32_t v : mesh.indices)
    if (v >= mesh.vertex_count())
      throw InputError(where + ": index " + std::to_string(v) + " is out of range");
  const std::vector<std::uint32_t> position_id = weld(mesh);
  std::vector<std::uint32_t> scratch(mesh.vertex_count(), kNoGroup);

  ClusterHierarchy h;
  std::vector<std::vector<Work>> levels = {
      split(localise(mesh, mesh.indices, scratch), o.max_triangles, kNoGroup)};
  ClusterStats s;
  for (std::size_t level = 0; level < levels.size(); ++level) {
    std::vector<Work>& pending = levels[level];
    // One cluster left, or the level limit a reader enforces: these are the roots.
    if (pending.size() <= 1 || level + 1 >= ClusterLimits{}.max_levels) break;
    std::vector<Work> next;
    std::vector<bool> carried(pending.size(), false);
    for (const std::vector<std::uint32_t>& part : partition(pending, position_id, o.group_size)) {
      std::vector<std::uint32_t> indices;
      std::vector<const ClusterGroup*> children;
      double child_error = 0;
      for (std::uint32_t c : part) {
        indices.insert(indices.end(), pending[c].indices.begin(), pending[c].indices.end());
        if (pending[c].refined != kNoGroup) {
          children.push_back(&h.groups[pending[c].refined]);
          child_error = std::max(child_error, double(h.groups[pending[c].refined].error));
        }
      }
      Local local = localise(mesh, indices, scratch);
      const std::size_t target = std::size_t(double(local.indices.size() / 3) * o.ratio) * 3;
      std::vector<std::uint32_t> simplified(local.indices.size());
      float error = 0;
      simplified.resize(meshopt_simplify(simplified.data(), local.indices.data(), local.indices.size(),
                                         local.positions.data(), local.vertices.size(), 3 * sizeof(float),
                                         target, std::numeric_limits<float>::max(),
                                         meshopt_SimplifyLockBorder, &error));
      if (simplified.empty() || double(simplified.size()) > o.max_kept * double(local.indices.size())) {
        // Stuck (its border leaves too little to remove): coarser members try again at the next
        // level, grouped with other neighbours; finest ones stay roots (the finest mesh comes first).
        ++s.stuck_groups;
        for (std::uint32_t c : part) carried[c] = pending[c].refined != kNoGroup;
        continue;
      }
      ClusterGroup g = bounding_sphere(local, children);
      // meshoptimizer's error is relative to the group's extent and measured against the group's
      // own (already simplified) triangles: the distance to the finest mesh is at most that plus
      // the largest error behind them.
      g.error = float(double(error) * meshopt_simplifyScale(local.positions.data(), local.vertices.size(),
                                                            3 * sizeof(float)) +
                      child_error);
      for (const ClusterGroup* child : children) g.level = std::max(g.level, child->level + 1);
      const std::uint32_t id = std::uint32_t(h.groups.size());
      h.groups.push_back(g);
      for (std::uint32_t c : part) pending[c].group = id;
      local.indices = std::move(simplified);
      for (Work& w : split(local, o.max_triangles, id)) next.push_back(std::move(w));
    }
    if (next.empty()) break;  // no group simplified: what is left are the roots
    std::vector<Work> kept;
    for (std::size_t c = 0; c < pending.size(); ++c)
      (carried[c] ? next : kept).push_back(std::move(pending[c]));
    pending = std::move(kept);
    levels.push_back(std::move(next));
  }
  // Lay out: level by level (the finest first), each level's members group by group, then its roots.
  for (std::vector<Work>& level : levels) {
    std::stable_sort(level.begin(), level.end(),
                     [](const Work& a, const Work& b) { return a.group < b.group; });
    for (const Work& w : level) {
      if (w.group != kNoGroup && h.groups[w.group].member_count == 0)
        h.groups[w.group].first_member = std::uint32_t(h.clusters.size());
      if (w.group != kNoGroup) ++h.groups[w.group].member_count;
      h.clusters.push_back(
          {std::uint32_t(h.indices.size() / 3), std::uint32_t(w.indices.size() / 3), w.group, w.refined});
      h.indices.insert(h.indices.end(), w.indices.begin(), w.indices.end());
    }
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = s;
  return h;
}

}  // namespace acuity::lodgen
