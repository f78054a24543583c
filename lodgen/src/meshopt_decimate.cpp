// meshoptimizer edge collapse: vertices stay where they are and keep their attributes; vertices
// sharing a position (crease splits, UV seams) are seams that collapse only along themselves.
#include <meshoptimizer.h>

#include <limits>

#include "cgal_bridge.hpp"

namespace acuity::lodgen::detail {

Mesh decimate_meshopt(const Mesh& in, std::size_t target, bool lock_border) {
  std::vector<std::uint32_t> kept(in.indices.size());
  // target_error 1 = the whole extent: only the triangle count stops it.
  const std::size_t n = meshopt_simplify(kept.data(), in.indices.data(), in.indices.size(), in.positions.data(),
                                         in.vertex_count(), 3 * sizeof(float), 3 * target, 1.0f,
                                         lock_border ? unsigned(meshopt_SimplifyLockBorder) : 0u, nullptr);
  kept.resize(n);
  // Compact: the surviving vertices, in their original order, with their attributes.
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> remap(in.vertex_count(), kUnused);
  for (std::uint32_t v : kept) remap[v] = 0;
  Mesh out;
  out.material = in.material;
  const bool normals = in.normals.size() == in.positions.size(), uv = in.texcoords.size() == 2 * in.vertex_count();
  for (std::size_t v = 0; v < remap.size(); ++v) {
    if (remap[v] == kUnused) continue;
    remap[v] = std::uint32_t(out.vertex_count());
    out.positions.insert(out.positions.end(), in.positions.begin() + 3 * v, in.positions.begin() + 3 * v + 3);
    if (normals) out.normals.insert(out.normals.end(), in.normals.begin() + 3 * v, in.normals.begin() + 3 * v + 3);
    if (uv) out.texcoords.insert(out.texcoords.end(), in.texcoords.begin() + 2 * v, in.texcoords.begin() + 2 * v + 2);
  }
  out.indices.reserve(kept.size());
  for (std::uint32_t v : kept) out.indices.push_back(remap[v]);
  if (!normals) compute_normals(out);
  return out;
}

}  // namespace acuity::lodgen::detail
