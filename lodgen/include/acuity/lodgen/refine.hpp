#pragma once
// acuity/lodgen/refine.hpp — finer levels from a coarse cage with OpenSubdiv.
#include <cstdint>
#include <string>
#include <vector>

#include "acuity/lodgen/mesh.hpp"

namespace acuity::lodgen {

// A polygon mesh (faces of any size), as a cage for subdivision.
struct PolygonMesh {
  std::vector<float> positions;           // xyz per vertex
  std::vector<std::uint32_t> face_sizes;  // vertices per face
  std::vector<std::uint32_t> indices;     // concatenated face vertex lists
};

// Reads OFF, OBJ, PLY or STL keeping polygons (OpenMesh). Throws InputError.
PolygonMesh load_polygon_mesh(const std::string& path);
PolygonMesh to_polygons(const Mesh& mesh);
Mesh triangulate(const PolygonMesh& mesh);  // fans; normals computed

// Uniform refinement, `levels` times: Loop when every face is a triangle, Catmull-Clark otherwise.
// Returns levels + 1 meshes, finest first, the cage (triangulated) last.
std::vector<Mesh> refine(const PolygonMesh& cage, int levels);

}  // namespace acuity::lodgen
