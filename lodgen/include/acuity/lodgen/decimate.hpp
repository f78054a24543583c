#pragma once
// acuity/lodgen/decimate.hpp — edge-collapse decimation and the geometric error it causes.
#include <cstddef>
#include <string>

#include "acuity/lodgen/mesh.hpp"

namespace acuity::lodgen {

// The default is CGAL Garland-Heckbert: in bench/bench_lodgen it has the lowest Hausdorff error
// most often and is 2-5x faster than OpenMesh's guarded decimater (docs/lodgen.md).
enum class Backend {
  OpenMesh,             // OpenMesh Decimater: quadric error, normal-flip and aspect-ratio guards
  CgalGarlandHeckbert,  // CGAL edge collapse, Garland-Heckbert plane quadrics (default)
  CgalLindstromTurk,    // CGAL edge collapse, Lindstrom-Turk cost and placement
};
bool parse_backend(const std::string& name, Backend* out);  // "openmesh", "cgal" (= GH), "cgal-lt"
const char* to_string(Backend backend);

struct DecimateOptions {
  Backend backend = Backend::CgalGarlandHeckbert;
  bool lock_border = false;  // border vertices and edges stay where they are
};

// A copy of `mesh` with about `target_triangles` triangles (never more than it had). Vertex normals
// are recomputed; texture coordinates follow the surviving vertices.
Mesh decimate(const Mesh& mesh, std::size_t target_triangles, const DecimateOptions& options = {});

// Symmetric Hausdorff distance between two triangle meshes [their units], estimated from every
// vertex, points along edges and a grid on each face at `spacing` (CGAL
// approximate_symmetric_Hausdorff_distance; deterministic). A lower bound that converges as the
// spacing shrinks: the largest gap between samples is about spacing / sqrt(2).
double hausdorff(const Mesh& a, const Mesh& b, double spacing);

// Area-weighted vertex normals.
void compute_normals(Mesh& mesh);

}  // namespace acuity::lodgen
