#pragma once
// acuity/lodgen/decimate.hpp — edge-collapse decimation and the geometric error it causes.
#include <cstddef>
#include <string>

#include "acuity/lodgen/mesh.hpp"

namespace acuity::lodgen {

// The default is meshoptimizer's edge collapse on the crease-split mesh (see decimate()): figures
// against plain meshoptimizer and the others in docs/lodgen.md (bench/bench_lodgen); the CGAL
// back-ends stay available for lower geometric error at 10-50x the time.
enum class Backend {
  OpenMesh,             // OpenMesh Decimater: quadric error, normal-flip and aspect-ratio guards
  CgalGarlandHeckbert,  // CGAL edge collapse, Garland-Heckbert plane quadrics
  CgalLindstromTurk,    // CGAL edge collapse, Lindstrom-Turk cost and placement
  Meshopt,              // meshoptimizer edge collapse, quadric error, vertices kept in place (default)
};
// "openmesh", "cgal" (= GH), "cgal-lt", "meshopt"
bool parse_backend(const std::string& name, Backend* out);
const char* to_string(Backend backend);

struct DecimateOptions {
  Backend backend = Backend::Meshopt;
  bool lock_border = false;    // border vertices and edges stay where they are
  double crease_degrees = 45;  // meshopt: for the welded fallback's normals (split_creases)
};

// A copy of `mesh` with about `target_triangles` triangles (never more than it had).
// Meshopt: `mesh` is taken as the renderer sees it — vertices at one position with different
// normals or texture coordinates (a crease split by split_creases, a UV seam) form a seam that
// collapses only along itself, so creases and seams stay in place; surviving vertices keep their
// normals and texture coordinates (no vertex moves). meshoptimizer 0.18 neither checks a seam's far
// side for flipped triangles nor always finds collapses past many seams: when over 1% of the
// result's triangles face against their vertex normals, or it stops more than 5% above the
// target, the welded mesh is decimated instead (seams close) and split at crease_degrees.
// OpenMesh and CGAL: `mesh` must be welded (one vertex per position; seams would open as holes);
// vertex normals are recomputed smooth, texture coordinates follow the surviving vertices.
Mesh decimate(const Mesh& mesh, std::size_t target_triangles, const DecimateOptions& options = {});

// The mesh with vertex normals a renderer shows: an edge is a crease when its two triangles' normals
// differ by more than `crease_degrees` (or it has one or three and more triangles); each vertex is
// split into one copy per fan of triangles around it not separated by creases, with the fan's
// area-weighted normal and the vertex's texture coordinates. crease_degrees >= 180 gives smooth
// normals everywhere (compute_normals). Triangles and their order are unchanged.
Mesh split_creases(const Mesh& mesh, double crease_degrees);

// How far `approx` strays from `reference`, both ways, measured on sample points: every vertex and
// a grid of points on each triangle (spacing `spacing` along its edges, at least one point per
// triangle), then the closest point on the other mesh (CGAL AABB tree). Bounded: when the samples
// on one side would exceed max_samples the spacing grows to fit (so the time does not depend on
// the model's units or how finely it is tessellated), and sampling stops at `max_seconds` per
// side with `complete` false. Deterministic unless the time cap is hit.
struct DeviationOptions {
  double spacing = 0;               // [mesh units]; <= 0: diameter(reference) / 250
  std::size_t max_samples = 60000;  // per side: up to half vertices (strided past it), half face points
  double max_seconds = 20;          // per side
};
struct Deviation {
  double hausdorff = 0;           // symmetric Hausdorff distance estimate [mesh units]; a lower bound
  double normal_degrees = 0;      // largest angle between the shading normal (vertex normals
                                  // interpolated barycentrically) at a sample and at its closest
                                  // point on the other mesh [degrees]; 0 when either has no normals
  double normal_p99_degrees = 0;  // 99th percentile of that angle over the samples [degrees]
  std::size_t samples = 0;        // both sides
  bool complete = true;           // false: the time cap cut sampling short
};
Deviation deviation(const Mesh& reference, const Mesh& approx, const DeviationOptions& options = {});

// Symmetric Hausdorff distance [mesh units]: deviation() at `spacing` with the default caps.
double hausdorff(const Mesh& a, const Mesh& b, double spacing);

// Area-weighted vertex normals.
void compute_normals(Mesh& mesh);

}  // namespace acuity::lodgen
