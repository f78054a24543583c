#pragma once
// The back-ends' entry points (decimate() picks one). The CGAL-based pieces are kept in one
// translation unit (cgal.cpp) because CGAL's templates are
// heavy to compile.
#include <array>
#include <cstddef>
#include <vector>

#include "acuity/lodgen/decimate.hpp"

namespace acuity::lodgen::detail {

// Polygon-soup repair and orientation; returns false when the soup could not be made a mesh.
// `origin[i]` is the input vertex each output vertex came from (for attributes).
bool repair_soup(std::vector<std::array<double, 3>>& points,
                 std::vector<std::array<std::size_t, 3>>& triangles, std::vector<std::size_t>& origin);

Mesh decimate_cgal(const Mesh& mesh, std::size_t target_triangles, bool lindstrom_turk, bool lock_border);
Mesh decimate_openmesh(const Mesh& mesh, std::size_t target_triangles, bool lock_border);
Mesh decimate_meshopt(const Mesh& mesh, std::size_t target_triangles, bool lock_border,
                      double crease_degrees);
// decimate_meshopt's first try alone: `mesh` decimated keeping its seams into `*out`; false (and
// `*out` unspecified) when that result is rejected (over 1% flipped triangles, or stuck more than
// 5% above the target), where decimate_meshopt goes on to the welded mesh.
bool decimate_meshopt_keeping_seams(const Mesh& mesh, std::size_t target_triangles, bool lock_border,
                                    Mesh* out);
// The mesh with one vertex per position (seams closed), without normals; each keeps the texture
// coordinates of its first vertex.
Mesh weld_positions(const Mesh& mesh);
// A welded mesh (weld_positions) decimated by meshoptimizer, its unused vertices dropped; no normals.
Mesh decimate_welded(const Mesh& welded, std::size_t target_triangles, bool lock_border);

}  // namespace acuity::lodgen::detail
