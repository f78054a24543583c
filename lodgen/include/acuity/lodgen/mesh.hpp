#pragma once
// acuity/lodgen/mesh.hpp — the flat meshes and scenes every offline part exchanges.
#include <array>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "acuity/lodgen/cluster_hierarchy.hpp"

namespace acuity::lodgen {

// Indexed triangle mesh in object space. Units are the asset's own (metres in glTF).
struct Mesh {
  std::vector<float> positions;        // xyz per vertex [Size: 3 * vertex_count]
  std::vector<float> normals;          // xyz per vertex, unit length, or empty
  std::vector<float> texcoords;        // uv per vertex, or empty
  std::vector<std::uint32_t> indices;  // three per triangle, each < vertex_count
  int material = -1;                   // index into Scene::materials, or -1

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
  int mesh = -1;  // index into Scene::meshes, or -1
  std::array<double, 16> matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // local, column-major
  std::vector<int> children;
  std::vector<int> lods;                // MSFT_lod: coarser levels' node indices (read back from glTF)
  std::vector<double> screen_coverage;  // MSFT_screencoverage, when present
  std::vector<double>
      geometric_error;  // extras.acuity_geometric_error (per level, object diameters), when present
};

// A scene: meshes are shared by the nodes that instance them.
struct Scene {
  std::vector<Mesh> meshes;
  std::vector<std::string> mesh_names;
  std::vector<Material> materials;
  std::vector<Node> nodes;
  std::vector<int> roots;
  // clusters[m]: mesh m's cluster hierarchy (a glTF primitive's ACUITY_cluster_hierarchy, checked
  // by check_cluster_hierarchy, its finest clusters being the mesh's own indices), empty when it has
  // none; meshes past the vector's end have none.
  std::vector<ClusterHierarchy> clusters;
};

// Bad input: says what is wrong and where (file, mesh, element).
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads an OFF, OBJ, PLY or STL file (by extension) through OpenMesh, in the calling process,
// and triangulates it. Throws io::Error (acuity/file.hpp) when the path is missing or not a regular
// file, and InputError naming the file when OpenMesh cannot read it, it has no
// triangles, holds non-finite coordinates, or its OFF/PLY header declares more elements than its
// size can hold. For trusted files only: OpenMesh's readers abort (a library assert) or loop
// forever on some malformed files (found by fuzzing), which no exception can report; untrusted
// files go through load_mesh_isolated().
Mesh load_mesh(const std::string& path);

// load_mesh() in a child process (fork(), POSIX only) with a time limit of 3 s plus 1 s per 4 MB of
// file; the mesh comes back through a pipe. An abort, a crash or a hang of the reader becomes an
// InputError naming the file, and the child is killed. The child is a copy of the calling process:
// call it where fork() is safe (not while another thread of the caller holds a lock the reader
// needs). Throws std::runtime_error when no child process can be made (no pipe, no fork, or a
// system without fork()); it never falls back to reading in the caller.
Mesh load_mesh_isolated(const std::string& path);

// What an untrusted glTF may make the reader do. Each limit is checked before the work it bounds;
// exceeding one throws InputError naming the limit. docs/security.md lists them with the reasons.
struct LoadLimits {
  std::uint64_t max_file_bytes = 1ull << 30;   // the file itself (any format) and each file a uri names
  std::uint64_t max_total_bytes = 2ull << 30;  // files read + pixels decoded + vertex/index data decoded
  std::uint32_t max_json_depth = 64;           // nesting of JSON arrays and objects (scanned before parsing)
  std::uint32_t max_nodes = 100000;
  std::uint32_t max_node_depth = 256;               // root to deepest node
  std::uint32_t max_children = 10000;               // per node
  std::uint32_t max_levels = 32;                    // per MSFT_lod node: itself + its ids (kMaxLevels)
  std::uint64_t max_image_pixels = 8192ull * 8192;  // per image, read from its header before decoding
  ClusterLimits clusters;  // per ACUITY_cluster_hierarchy: counts checked before its records are read
};

struct LoadOptions {
  // Folder a glTF's buffer and image uris may name files in (after resolving "..", "." and
  // symbolic links); empty: the folder holding the glTF. Widen it (`--asset-root DIR`) for assets
  // that keep buffers in a sibling folder. Absolute paths, schemes (file:, http:) and %-escapes
  // are never followed; data: URIs always work.
  std::string asset_root;
  LoadLimits limits;
  // OFF, OBJ, PLY and STL files: true reads them with load_mesh_isolated() (a child process with a
  // time limit, for untrusted files: what the acuity command, Python and the fuzzers rely on);
  // false with load_mesh(), in the calling process (trusted files, or a host where fork() is
  // unwelcome). glTF is always read in the calling process (tinygltf behind lodgen's own checks,
  // bounded by `limits`).
  bool isolate_mesh_reader = true;
  // When set, receives the canonical path of every file a uri named that was read (buffers,
  // images), in reading order: what a content hash of the asset must cover besides the file itself.
  std::vector<std::string>* files_read = nullptr;
};

// Reads a file in any format of input_formats() (acuity/lodgen/formats.hpp), picked by its
// extension: a glTF 2.0 file (.gltf with its .bin, or .glb), or a mesh file (as one node; in a
// child process unless options.isolate_mesh_reader is false). Every file is read through
// acuity::io (regular files only, within limits.max_file_bytes; a glTF's uris confined to
// asset_root). The glTF must be a strict tree (no node with two parents or listed twice, no cycle;
// scene roots have no parent); only the images a material uses as base colour are decoded. Throws
// io::Error for a file that cannot be read as a regular file within the limits (the path and why),
// InputError naming the file and the element at fault for anything else.
Scene load_scene(const std::string& path, const LoadOptions& options = {});

// A node reached from the scene's roots and its world matrix (column-major, parents' matrices
// times its own).
struct PlacedNode {
  int node = -1;
  std::array<double, 16> world{};
};

// Every node reached from scene.roots in depth-first order (roots, then children, each in order),
// without recursion. `skip(node)` true leaves a node and its subtree out. Throws InputError when a
// node is reached twice (a cycle, or a node with two parents) or an index is out of range. The one
// walk lodgen and the simulation share.
std::vector<PlacedNode> world_matrices(const Scene& scene, const std::function<bool(int)>& skip = {});

// Bounding-sphere diameter used to express errors as fractions of the object (bounding box
// centre, farthest vertex).
double diameter(const Mesh& mesh);

}  // namespace acuity::lodgen
