#pragma once
// acuity/lodgen/mesh.hpp — the flat triangle mesh every offline part exchanges.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace acuity::lodgen {

// Indexed triangle mesh in object space. Units are the asset's own (metres in glTF).
struct Mesh {
  std::vector<float> positions;       // xyz per vertex [Size: 3 * vertex_count]
  std::vector<float> normals;         // xyz per vertex, unit length, or empty
  std::vector<float> texcoords;       // uv per vertex, or empty
  std::vector<std::uint32_t> indices; // three per triangle, each < vertex_count

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t triangle_count() const { return indices.size() / 3; }
};

// Bad input: says what is wrong and where (file, mesh, element).
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads an OFF, OBJ, PLY or STL file (by extension) through OpenMesh and triangulates it.
// Throws InputError naming the file when it cannot be read, has no triangles, or holds
// non-finite coordinates.
Mesh load_mesh(const std::string& path);

}  // namespace acuity::lodgen
