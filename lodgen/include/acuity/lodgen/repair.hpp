#pragma once
// acuity/lodgen/repair.hpp — what is wrong with a mesh, and the safe repairs.
#include <cstddef>
#include <string>
#include <vector>

#include "acuity/lodgen/mesh.hpp"

namespace acuity::lodgen {

struct MeshReport {
  std::size_t vertices = 0, triangles = 0;
  std::size_t nonfinite_vertices = 0;     // NaN or infinite coordinates
  std::size_t bad_indices = 0;            // indices >= vertex count
  std::size_t degenerate_triangles = 0;   // repeated vertex or zero area
  std::size_t duplicate_vertices = 0;     // same position as an earlier vertex
  std::size_t border_edges = 0;           // used by one triangle
  std::size_t non_manifold_edges = 0;     // used by three or more triangles
  std::size_t non_manifold_vertices = 0;  // whose triangles form more than one fan
  std::size_t misoriented_edges = 0;      // used twice in the same direction
  bool clean() const {
    return nonfinite_vertices + bad_indices + degenerate_triangles + duplicate_vertices + non_manifold_edges +
                   non_manifold_vertices + misoriented_edges ==
               0 &&
           triangles > 0;
  }
  std::string summary() const;  // "3 degenerate triangles, 12 duplicate vertices" or "clean"
};

MeshReport validate(const Mesh& mesh);

// Drops triangles with bad indices, non-finite or degenerate geometry; merges duplicate vertices;
// makes orientation consistent and splits non-manifold vertices (CGAL Polygon Mesh Processing,
// polygon-soup repair and orientation). Normals and texture coordinates of kept vertices are kept.
// Throws InputError (naming `where`) when nothing usable is left.
Mesh repair(const Mesh& mesh, const std::string& where, MeshReport* before = nullptr);

}  // namespace acuity::lodgen
