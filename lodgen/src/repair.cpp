#include "acuity/lodgen/repair.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <unordered_map>

#include "acuity/lodgen/decimate.hpp"
#include "cgal_bridge.hpp"

namespace acuity::lodgen {
namespace {

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

bool finite_vertex(const Mesh& m, std::size_t v) {
  return std::isfinite(m.positions[3 * v]) && std::isfinite(m.positions[3 * v + 1]) &&
         std::isfinite(m.positions[3 * v + 2]);
}

bool degenerate(const Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (a == b || b == c || a == c) return true;
  double e1[3], e2[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = double(m.positions[3 * b + k]) - m.positions[3 * a + k];
    e2[k] = double(m.positions[3 * c + k]) - m.positions[3 * a + k];
  }
  const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
  return n[0] == 0 && n[1] == 0 && n[2] == 0;
}

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

}  // namespace

std::string MeshReport::summary() const {
  std::string s;
  auto add = [&](std::size_t n, const char* what) {
    if (!n) return;
    s += (s.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  };
  add(nonfinite_vertices, "non-finite vertices");
  add(bad_indices, "out-of-range indices");
  add(degenerate_triangles, "degenerate triangles");
  add(duplicate_vertices, "duplicate vertices");
  add(non_manifold_edges, "non-manifold edges");
  add(non_manifold_vertices, "non-manifold vertices");
  add(misoriented_edges, "inconsistently oriented edges");
  if (triangles == 0) s += (s.empty() ? "" : ", ") + std::string("no triangles");
  return s.empty() ? "clean" : s;
}

MeshReport validate(const Mesh& m) {
  MeshReport r;
  r.vertices = m.vertex_count();
  r.triangles = m.triangle_count();
  std::vector<bool> finite(r.vertices);
  for (std::size_t v = 0; v < r.vertices; ++v) r.nonfinite_vertices += !(finite[v] = finite_vertex(m, v));
  {
    std::map<std::array<float, 3>, std::size_t> seen;
    for (std::size_t v = 0; v < r.vertices; ++v)
      if (finite[v] && !seen.emplace(std::array<float, 3>{m.positions[3 * v], m.positions[3 * v + 1],
                                                          m.positions[3 * v + 2]},
                                     v)
                            .second)
        ++r.duplicate_vertices;
  }
  std::unordered_map<std::uint64_t, std::uint32_t> directed, undirected;
  std::vector<std::size_t> good;  // triangles whose indices and vertices are usable
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
    if (a >= r.vertices || b >= r.vertices || c >= r.vertices) {
      ++r.bad_indices;
      continue;
    }
    if (!finite[a] || !finite[b] || !finite[c]) continue;
    if (degenerate(m, a, b, c)) {
      ++r.degenerate_triangles;
      continue;
    }
    good.push_back(t);
    for (auto [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
      ++directed[edge_key(x, y)];
      ++undirected[edge_key(std::min(x, y), std::max(x, y))];
    }
  }
  for (const auto& [key, n] : undirected) {
    if (n == 1) ++r.border_edges;
    if (n > 2) ++r.non_manifold_edges;
  }
  for (const auto& [key, n] : directed) r.misoriented_edges += n > 1;
  // Non-manifold vertices: a vertex whose triangles fall into more than one edge-connected fan.
  std::vector<std::vector<std::size_t>> around(r.vertices);
  for (std::size_t i = 0; i < good.size(); ++i)
    for (int k = 0; k < 3; ++k) around[m.indices[good[i] + k]].push_back(i);
  for (std::size_t v = 0; v < r.vertices; ++v) {
    const auto& fs = around[v];
    if (fs.size() < 2) continue;
    UnionFind uf(fs.size());
    std::map<std::uint32_t, std::size_t> by_neighbour;  // other vertex of an edge at v -> a fan member
    for (std::size_t j = 0; j < fs.size(); ++j)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t w = m.indices[good[fs[j]] + k];
        if (w == v) continue;
        auto [it, fresh] = by_neighbour.emplace(w, j);
        if (!fresh) uf.join(j, it->second);
      }
    std::size_t fans = 0;
    for (std::size_t j = 0; j < fs.size(); ++j) fans += uf.find(j) == j;
    r.non_manifold_vertices += fans > 1;
  }
  return r;
}

Mesh repair(const Mesh& m, const std::string& where, MeshReport* before) {
  const MeshReport report = validate(m);
  if (before) *before = report;
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::size_t, 3>> triangles;
  for (std::size_t v = 0; v < m.vertex_count(); ++v)
    points.push_back({m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]});
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
    if (a >= m.vertex_count() || b >= m.vertex_count() || c >= m.vertex_count()) continue;
    if (!finite_vertex(m, a) || !finite_vertex(m, b) || !finite_vertex(m, c) || degenerate(m, a, b, c))
      continue;
    triangles.push_back({a, b, c});
  }
  if (triangles.empty()) throw InputError(where + ": nothing usable is left (" + report.summary() + ")");
  // Keep only the points triangles use, so CGAL never sees a non-finite one.
  std::vector<std::size_t> remap(points.size(), SIZE_MAX), kept;
  std::vector<std::array<double, 3>> used;
  for (auto& t : triangles)
    for (auto& i : t) {
      if (remap[i] == SIZE_MAX) {
        remap[i] = used.size();
        used.push_back(points[i]);
        kept.push_back(i);
      }
      i = remap[i];
    }
  std::vector<std::size_t> origin;
  if (!detail::repair_soup(used, triangles, origin))
    throw InputError(where + ": cannot be repaired into a mesh (" + report.summary() + ")");
  Mesh out;
  out.material = m.material;
  for (std::size_t i = 0; i < used.size(); ++i) {
    for (double x : used[i]) out.positions.push_back(float(x));
    const std::size_t o = kept[origin[i]];
    if (!m.texcoords.empty())
      out.texcoords.insert(out.texcoords.end(), {m.texcoords[2 * o], m.texcoords[2 * o + 1]});
  }
  for (const auto& t : triangles)
    for (std::size_t i : t) out.indices.push_back(std::uint32_t(i));
  compute_normals(out);
  return out;
}

}  // namespace acuity::lodgen
