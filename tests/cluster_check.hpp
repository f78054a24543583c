#pragma once
// The crack check of cluster cuts, shared by tests/test_clusters.cpp (cuts by projected error) and
// tests/test_cluster_cut.cpp (the runtime's perceptual cuts): positions welded exactly, each
// cluster's edges, and the first drawn cluster with an edge the cut uses once but the finest mesh
// does not (an opening the finest mesh lacks).
#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/cluster_hierarchy.hpp"
#include "acuity/lodgen/clusters.hpp"
#include "acuity/lodgen/mesh.hpp"

namespace acuity::testing {
using lodgen::Cluster;
using lodgen::ClusterHierarchy;
using lodgen::kNoGroup;
using lodgen::Mesh;

// Level 0 of the mesh file at `path` as `acuity lodgen` makes it (repaired, split at 45° creases), and
// its hierarchy (`acuity lodgen --clusters`).
struct BuiltHierarchy {
  Mesh mesh;
  ClusterHierarchy h;
};
inline BuiltHierarchy built_hierarchy(const std::string& path) {
  lodgen::ChainOptions o;
  o.levels = 1;
  BuiltHierarchy b;
  b.mesh = lodgen::build_chain(lodgen::load_mesh(path), path, o).levels[0].mesh;
  b.h = lodgen::build_clusters(b.mesh, path);
  return b;
}

// One id per exact position, as build_clusters welds them.
inline std::vector<std::uint32_t> welded(const Mesh& m) {
  std::map<std::array<float, 3>, std::uint32_t> ids;
  std::vector<std::uint32_t> out(m.vertex_count());
  for (std::size_t v = 0; v < out.size(); ++v) {
    const std::array<float, 3> p = {m.positions[3 * v] + 0.0f, m.positions[3 * v + 1] + 0.0f,
                                    m.positions[3 * v + 2] + 0.0f};
    out[v] = ids.emplace(p, std::uint32_t(ids.size())).first->second;
  }
  return out;
}

inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return std::uint64_t(std::min(a, b)) << 32 | std::max(a, b);
}

// A triangle as welded positions, rotated to start at its smallest (orientation kept).
inline std::array<std::uint32_t, 3> welded_triangle(const std::vector<std::uint32_t>& id,
                                                    const std::uint32_t* t) {
  std::array<std::uint32_t, 3> p = {id[t[0]], id[t[1]], id[t[2]]};
  std::rotate(p.begin(), std::min_element(p.begin(), p.end()), p.end());
  return p;
}

// Edges (welded, undirected) of each cluster as dense ids, and how many times the finest mesh uses
// each: a cut is crack-free when every edge it uses once is one the finest mesh uses once too.
struct Edges {
  std::vector<std::vector<std::uint32_t>> of_cluster;
  std::vector<std::uint8_t> finest_count;
};
inline Edges edges(const Mesh& mesh, const ClusterHierarchy& h) {
  const std::vector<std::uint32_t> id = welded(mesh);
  std::unordered_map<std::uint64_t, std::uint32_t> dense;
  Edges e;
  for (const Cluster& c : h.clusters) {
    e.of_cluster.emplace_back();
    for (std::size_t t = c.first_triangle; t < std::size_t(c.first_triangle) + c.triangle_count; ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = id[h.indices[3 * t + std::size_t(k)]],
                            b = id[h.indices[3 * t + std::size_t((k + 1) % 3)]];
        if (a == b) continue;  // a collapsed corner draws no edge
        const auto it = dense.emplace(edge_key(a, b), std::uint32_t(dense.size())).first;
        e.of_cluster.back().push_back(it->second);
      }
  }
  e.finest_count.assign(dense.size(), 0);
  for (std::size_t c = 0; c < h.clusters.size(); ++c)
    if (h.clusters[c].refined == kNoGroup)
      for (std::uint32_t x : e.of_cluster[c])
        e.finest_count[x] = std::uint8_t(std::min(255, e.finest_count[x] + 1));
  return e;
}

// The first drawn cluster with an edge the cut uses once but the finest mesh does not, or UINT32_MAX.
// (Edges used more than twice are no sign of overlap: meshoptimizer 0.18 now and then leaves a
// coincident pair of triangles in a group's output; overlap is checked on the groups instead.)
class CrackCheck {
 public:
  explicit CrackCheck(const Edges& e) : e_(e), count_(e.finest_count.size(), 0) {}
  template <class Ids>
  std::uint32_t first(const Ids& drawn) {
    std::uint32_t found = UINT32_MAX;
    for (std::uint32_t c : drawn)
      for (std::uint32_t x : e_.of_cluster[c]) ++count_[x];
    for (std::uint32_t c : drawn)
      for (std::uint32_t x : e_.of_cluster[c])
        if (found == UINT32_MAX && count_[x] == 1 && e_.finest_count[x] != 1) found = c;
    for (std::uint32_t c : drawn)
      for (std::uint32_t x : e_.of_cluster[c]) count_[x] = 0;
    return found;
  }

 private:
  const Edges& e_;
  std::vector<std::uint32_t> count_;
};

}  // namespace acuity::testing
