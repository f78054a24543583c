// meshoptimizer edge collapse: vertices stay where they are and keep their attributes; vertices
// sharing a position (crease splits, UV seams) are seams that collapse only along themselves.
#include <meshoptimizer.h>

#include <limits>

#include "cgal_bridge.hpp"

namespace acuity::lodgen::detail {

namespace {
std::vector<std::uint32_t> simplify(const Mesh& in, const std::vector<std::uint32_t>& indices,
                                    std::size_t target, bool lock_border) {
  std::vector<std::uint32_t> kept(indices.size());
  // target_error 1 = the whole extent: only the triangle count stops it.
  kept.resize(meshopt_simplify(kept.data(), indices.data(), indices.size(), in.positions.data(),
                               in.vertex_count(), 3 * sizeof(float), 3 * target, 1.0f,
                               lock_border ? unsigned(meshopt_SimplifyLockBorder) : 0u, nullptr));
  return kept;
}

// How many triangles face against the sum of their vertex normals (flipped).
std::size_t flips(const Mesh& m) {
  std::size_t flipped = 0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const float* p[3];
    double n[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i) {
      p[i] = &m.positions[3 * m.indices[t + std::size_t(i)]];
      for (int k = 0; k < 3; ++k) n[k] += m.normals[3 * m.indices[t + std::size_t(i)] + std::size_t(k)];
    }
    const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    const double f[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                         e1[0] * e2[1] - e1[1] * e2[0]};
    flipped += f[0] * n[0] + f[1] * n[1] + f[2] * n[2] < 0;
  }
  return flipped;
}

// The vertices `kept` uses, in their original order with their attributes, and `kept` renumbered.
Mesh compact(const Mesh& in, const std::vector<std::uint32_t>& kept) {
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> remap(in.vertex_count(), kUnused);
  for (std::uint32_t v : kept) remap[v] = 0;
  Mesh out;
  out.material = in.material;
  const bool normals = in.normals.size() == in.positions.size(),
             uv = in.texcoords.size() == 2 * in.vertex_count();
  for (std::size_t v = 0; v < remap.size(); ++v) {
    if (remap[v] == kUnused) continue;
    remap[v] = std::uint32_t(out.vertex_count());
    out.positions.insert(out.positions.end(), in.positions.begin() + 3 * v, in.positions.begin() + 3 * v + 3);
    if (normals)
      out.normals.insert(out.normals.end(), in.normals.begin() + 3 * v, in.normals.begin() + 3 * v + 3);
    if (uv)
      out.texcoords.insert(out.texcoords.end(), in.texcoords.begin() + 2 * v,
                           in.texcoords.begin() + 2 * v + 2);
  }
  out.indices.reserve(kept.size());
  for (std::uint32_t v : kept) out.indices.push_back(remap[v]);
  return out;
}
}  // namespace

bool decimate_meshopt_keeping_seams(const Mesh& in, std::size_t target, bool lock_border, Mesh* out) {
  const std::vector<std::uint32_t> kept = simplify(in, in.indices, target, lock_border);
  if (kept.size() / 3 > target + target / 20 + 2) return false;
  *out = compact(in, kept);
  if (out->normals.empty()) {
    compute_normals(*out);
    return true;
  }
  return flips(*out) * 100 <= out->triangle_count();
}

// meshoptimizer sees any two vertices at one position as a seam, used or not.
Mesh weld_positions(const Mesh& in) {
  std::vector<std::uint32_t> shadow(in.indices.size());
  meshopt_generateShadowIndexBuffer(shadow.data(), in.indices.data(), in.indices.size(), in.positions.data(),
                                    in.vertex_count(), 3 * sizeof(float), 3 * sizeof(float));
  Mesh out;
  out.material = in.material;
  std::vector<std::uint32_t> remap(in.vertex_count(), std::numeric_limits<std::uint32_t>::max());
  for (std::uint32_t v : shadow) {
    if (remap[v] == std::numeric_limits<std::uint32_t>::max()) {
      remap[v] = std::uint32_t(out.vertex_count());
      out.positions.insert(out.positions.end(), in.positions.begin() + 3 * v,
                           in.positions.begin() + 3 * v + 3);
      if (in.texcoords.size() == 2 * in.vertex_count())
        out.texcoords.insert(out.texcoords.end(), in.texcoords.begin() + 2 * v,
                             in.texcoords.begin() + 2 * v + 2);
    }
    out.indices.push_back(remap[v]);
  }
  return out;
}

Mesh decimate_welded(const Mesh& welded, std::size_t target, bool lock_border) {
  return compact(welded, simplify(welded, welded.indices, target, lock_border));
}

Mesh decimate_meshopt(const Mesh& in, std::size_t target, bool lock_border, double crease_degrees) {
  Mesh out;
  if (decimate_meshopt_keeping_seams(in, target, lock_border, &out)) return out;
  // Over 1% of the triangles flipped (meshoptimizer 0.18 checks one side of a seam), or seams everywhere (a
  // coarse organic mesh split at many creases) left too few collapses: decimate the welded mesh and
  // split its creases afresh (UV seams close there).
  return split_creases(decimate_welded(weld_positions(in), target, lock_border), crease_degrees);
}

}  // namespace acuity::lodgen::detail
