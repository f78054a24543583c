#pragma once
// acuity/bake/scene.hpp — a glTF scene as the scheduler sees it: distinct LOD chains (assets) with
// their profiles, and the instances placing them in the world. Shared by `simulate`, `explain`,
// `demo`, the OSG loader and `profile`.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "acuity/file.hpp"
#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/cluster_hierarchy.hpp"
#include "acuity/lodgen/mesh.hpp"
#include "acuity/scheduler.hpp"
#include "acuity/spectra/cluster_loss.hpp"
#include "acuity/spectra/profile_builder.hpp"

namespace acuity::bake {

// The renderer's material for scene material `index` (-1 or out of range: default); points into the scene.
spectra::Material spectra_material(const lodgen::Scene& scene, int index);

// A mesh as the renderer reads it (borrowed arrays: the mesh must outlive the view).
spectra::MeshView spectra_mesh(const lodgen::Mesh& mesh);
// A mesh and its cluster hierarchy as spectra::measure_cluster_loss reads them (borrowed likewise).
spectra::ClusterMesh cluster_mesh(const lodgen::Mesh& mesh, const lodgen::ClusterHierarchy& hierarchy);

// A chain's levels as spectra inputs (the arrays are borrowed: the chain must outlive the result);
// each level's geometric error is its Level::hausdorff [object diameters].
std::vector<spectra::LevelInput> spectra_levels(const lodgen::Chain& chain);

struct Asset {
  std::string name;  // file-safe, unique in the scene
  lodgen::Chain chain;
  spectra::Material material;  // points into SceneAssets::scene
  Blob blob;                   // the profile's bytes
  Profile profile{};
};

struct Instance {
  std::string name;
  int asset = 0;
  ObjectTransform transform;  // position, rotation, the largest axis scale of the world matrix
  double radius = 0;          // world bounding-sphere radius [m]
};

struct SceneAssets {
  lodgen::Scene scene;
  std::vector<Asset> assets;
  std::vector<Instance> instances;
};

struct AssetOptions {
  std::string asset_root;  // lodgen::LoadOptions::asset_root: where the glTF's uris may reach
  std::string profiles;    // directory of <asset>.acuity: used when they match, else built and saved
  std::uint32_t profile_pixels = 256;
  std::uint32_t lod_levels = 5;  // for meshes without MSFT_lod levels (built by lodgen)
  bool bound_cells = true;       // profiles built: each view's loss bounded over its cell (docs/spectra.md)
  bool quiet = false;
};

// Loads the scene, builds LOD chains for plain meshes and profiles where none match. Throws
// lodgen::InputError or std::runtime_error naming the file.
std::unique_ptr<SceneAssets> load_scene_assets(const std::string& path, const AssetOptions& options);

// "armadillo.1" -> "armadillo_1": letters, digits, '-' and '_' kept, anything else '_'; "" -> "object".
std::string file_safe(const std::string& name);

}  // namespace acuity::bake
