#pragma once
// acuity/lodgen/mesh.hpp — the flat meshes and scenes every offline part exchanges.
#include <array>
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
  int material = -1;                  // index into Scene::materials, or -1

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t triangle_count() const { return indices.size() / 3; }
};

struct Material {
  std::string name;
  float base_color[4] = {1, 1, 1, 1};  // linear RGBA (glTF baseColorFactor)
  std::vector<std::uint8_t> pixels;    // base colour texture: RGBA8, sRGB, row 0 at the top; or empty
  int width = 0, height = 0;
};

struct Node {
  std::string name;
  int mesh = -1;                       // index into Scene::meshes, or -1
  std::array<double, 16> matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // local, column-major
  std::vector<int> children;
  std::vector<int> lods;               // MSFT_lod: coarser levels' node indices (read back from glTF)
  std::vector<double> screen_coverage; // MSFT_screencoverage, when present
  std::vector<double> geometric_error; // extras.acuity_geometric_error (per level, object diameters), when present
};

// A scene: meshes are shared by the nodes that instance them.
struct Scene {
  std::vector<Mesh> meshes;
  std::vector<std::string> mesh_names;
  std::vector<Material> materials;
  std::vector<Node> nodes;
  std::vector<int> roots;
};

// Bad input: says what is wrong and where (file, mesh, element).
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads an OFF, OBJ, PLY or STL file (by extension) through OpenMesh and triangulates it.
// Throws InputError naming the file when it cannot be read, has no triangles, or holds
// non-finite coordinates.
Mesh load_mesh(const std::string& path);

// Reads a glTF 2.0 file (.gltf with its .bin, or .glb) or, by extension, any format load_mesh
// reads (as one node). Throws InputError naming the file and the element at fault.
Scene load_scene(const std::string& path);

// Bounding-sphere diameter used to express errors as fractions of the object (bounding box
// centre, farthest vertex).
double diameter(const Mesh& mesh);

}  // namespace acuity::lodgen
