#pragma once
// acuity/lodgen/gltf.hpp — glTF 2.0 input and LOD output with MSFT_lod (KhronosGroup glTF,
// extensions/2.0/Vendor/MSFT_lod): the finest level's node lists the coarser levels' nodes in
// extensions.MSFT_lod.ids; extras.MSFT_screencoverage gives, per level, the smallest screen
// coverage it is drawn at. acuity's coverage is the bounding sphere's projected diameter over the
// screen height; level k takes over from level k-1 where its geometric error e_k (fraction of the
// diameter) covers one pixel at the reference height: coverage = 1 / (e_k x height). Since the
// coverage depends on that height and is clamped, lodgen also writes the errors themselves as
// extras.acuity_geometric_error on the same node, and the shading error beside it as
// extras.acuity_normal_deviation (per level, degrees; lodgen::Level::normal_deviation).
#include <string>
#include <vector>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/mesh.hpp"

namespace acuity::lodgen {

// One object: its chain (levels finest first; Level::hausdorff is the geometric error written to
// the file [object diameters]), placed at `matrix`.
struct LodObject {
  std::string name;
  Chain chain;
  std::array<double, 16> matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  int material = -1;  // into the materials passed to write_lod_gltf
  // The cluster hierarchy of chain.levels[0].mesh (build_clusters), or empty. When set, level 0's
  // primitive is written with its indices in the hierarchy's order (its finest clusters) and the
  // hierarchy as the primitive's ACUITY_cluster_hierarchy extension (docs/lodgen.md).
  ClusterHierarchy clusters;
};

// One placement of objects[object]: a node group of its own (the finest level's node with MSFT_lod,
// one node per coarser level) referring to the object's meshes, which instances share.
struct LodInstance {
  int object = 0;
  std::string name;
  std::array<double, 16> matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // world, column-major
};

struct GltfWriteOptions {
  double reference_height = 1080;  // pixels, for MSFT_screencoverage
  bool binary = true;              // .glb; false writes .gltf with the buffer embedded as a data URI
};

// Screen coverages for write_lod_gltf: one per level, non-increasing, the last 0.
std::vector<double> screen_coverage(const std::vector<double>& geometric_error, double reference_height);

// The geometric errors [object diameters] of the `levels` levels an MSFT_lod node holds: as lodgen
// recorded them, else inverted from MSFT_screencoverage at the default reference height (other
// writers); 0 where neither says.
std::vector<double> lod_geometric_errors(const Node& top, std::size_t levels);

// The chain a node with MSFT_lod holds (the node itself, then its lods), as write_lod_gltf wrote
// it: each level's mesh, target_triangles = its triangle count, hausdorff = lod_geometric_errors,
// diameter of level 0; seconds 0. The inverse of write_lod_gltf for one object.
Chain chain_of_node(const Scene& scene, const Node& top);

// The file write_lod_gltf writes, as bytes (.glb when options.binary, else .gltf text).
std::string encode_lod_gltf(const std::vector<LodObject>& objects, const std::vector<Material>& materials,
                            const GltfWriteOptions& options = {},
                            const std::vector<LodInstance>& instances = {});

// Writes the objects as one scene, atomically (a temporary renamed into place): each object once at
// its own matrix, or, when instances are given, each instance. Throws std::runtime_error naming the
// path on failure; nothing is left behind.
void write_lod_gltf(const std::string& path, const std::vector<LodObject>& objects,
                    const std::vector<Material>& materials, const GltfWriteOptions& options = {},
                    const std::vector<LodInstance>& instances = {});

}  // namespace acuity::lodgen
