#pragma once
// acuity/bake/chains.hpp — a scene file to measured LOD chains and back: the one path `acuity
// lodgen`, `acuity profile`, `acuity bake`, the demo and Python's acuity.lodgen.build share.
#include <string>
#include <vector>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/clusters.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "acuity/lodgen/mesh.hpp"
#include "acuity/spectra/cluster_loss.hpp"
#include "acuity/spectra/profile_builder.hpp"
#include "acuity/spectra/render.hpp"

namespace acuity::bake {

// The default time budget for measuring the errors of all of a scene's meshes [s]. Each measured
// side of a coarser level gets an equal part of what is left; a measurement cut short is a lower
// bound, with a warning (lodgen::DeviationOptions::max_seconds).
inline constexpr double kMeasureSeconds = 40;

struct ChainRequest {
  std::string input;                         // OFF, OBJ, PLY, STL, glTF or GLB
  std::string asset_root;                    // lodgen::LoadOptions::asset_root ("" : the glTF's folder)
  lodgen::ChainOptions chain;                // decimation (ignored when refine > 0)
  int refine = 0;                            // > 0: the input is a cage refined this many times (OpenSubdiv)
  double measure_seconds = kMeasureSeconds;  // error-measurement budget for all the scene's meshes [s]
  // Instead of a chain: level 0 only (repaired, split at creases) with its cluster hierarchy
  // (lodgen::build_clusters; `acuity lodgen --clusters`). Not with refine.
  bool clusters = false;
};

struct SceneChains {
  lodgen::Scene scene;                              // as loaded (a cage: one node, identity matrix)
  std::vector<lodgen::Chain> chains;                // one per scene mesh; instances share it
  std::vector<lodgen::LodObject> objects;           // one per node drawing a mesh, at its world matrix
  std::vector<lodgen::ClusterHierarchy> clusters;   // one per scene mesh when asked for (else empty)
  std::vector<lodgen::ClusterStats> cluster_stats;  // likewise
};

// Loads `request.input` and builds every mesh's chain; one object per node that draws a mesh
// (lodgen::world_matrices order, named by the node, else its mesh). Throws lodgen::InputError naming
// the file for bad input, and when the scene draws no mesh.
SceneChains build_scene_chains(const ChainRequest& request, const lodgen::ChainProgress& progress = {});
// The same from a scene already loaded from `where` (decimation only).
// With `clusters`, as ChainRequest::clusters says.
SceneChains chains_of_scene(lodgen::Scene scene, const std::string& where, lodgen::ChainOptions options,
                            const lodgen::ChainProgress& progress = {},
                            double measure_seconds = kMeasureSeconds, bool clusters = false);

// What `acuity lodgen` reports of the chains it built: a table (one row per mesh and level: target and
// result triangles, Hausdorff error in diameters, 99th-percentile normal deviation in degrees,
// seconds; with cluster hierarchies, one more row per mesh: clusters, groups, levels, root clusters
// and their triangles, the root error in diameters, seconds), and the same as the JSON it writes
// beside its output ({input, output, backend, seconds, meshes: [{name, diameter, warnings,
// levels: [...], clusters: {...} when built}]}).
std::string chains_table(const SceneChains& chains);
std::string chains_json(const SceneChains& chains, const std::string& input, const std::string& output,
                        const std::string& backend, double seconds);

// `acuity lodgen`'s job, also Python's acuity.lodgen.build: the chains of `request.input`, written
// to `output` (.gltf: text, else binary glTF with MSFT_lod, MSFT_screencoverage at
// `reference_height` px) unless it is empty; the output is checked (io::check_output, one of
// lodgen::chain_output_extensions()) before any work. Returns the chains and chains_json() of them, `backend` naming the back-end used.
struct WrittenChains {
  SceneChains chains;
  std::string json;
  double seconds = 0;  // the whole job
};
WrittenChains write_scene_chains(const ChainRequest& request, const std::string& output,
                                 double reference_height, const std::string& backend,
                                 const lodgen::ChainProgress& progress = {});

// A chain file (glTF from write_lod_gltf or any MSFT_lod writer): its first node with MSFT_lod
// levels, read back as a chain. `material` points into `scene` (keep them together).
struct ChainFile {
  lodgen::Scene scene;
  lodgen::Chain chain;
  spectra::Material material;
};
// Throws lodgen::InputError naming the file when it has no node with MSFT_lod levels.
ChainFile read_chain_file(const std::string& path, const std::string& asset_root = {});
// The same from a scene already loaded from `path`.
ChainFile chain_file(lodgen::Scene scene, const std::string& path);

// A cluster file (`acuity lodgen MESH --clusters`'s glTF, or any with ACUITY_cluster_hierarchy):
// its first mesh with a hierarchy. `material` points into `scene` (keep them together).
struct ClusterFile {
  lodgen::Scene scene;
  std::size_t mesh = 0;  // index into scene.meshes and scene.clusters; scene.clusters.size(): none
  spectra::Material material;
  bool found() const { return mesh < scene.clusters.size(); }
  // The mesh and its hierarchy as the measurement reads them (borrowed from scene); when found().
  spectra::ClusterMesh view() const;
};
// The scene at `path` and its first mesh with a hierarchy, if any (found()). Throws io::Error or
// lodgen::InputError for a file lodgen::load_scene refuses.
ClusterFile read_cluster_file(const std::string& path, const std::string& asset_root = {});

// The profile of a mesh with a cluster hierarchy: its finest mesh as a one-level chain (views,
// Reddy's features: what the object rule reads, which then always draws it whole) and the Clusters
// section, what each group loses (spectra::measure_cluster_loss). `acuity profile OUT.glb` of a
// cluster file and `acuity bake` with clusters. Throws std::invalid_argument as the builders do.
spectra::ProfileData profile_clusters(const spectra::ClusterMesh& mesh, const spectra::Material& material,
                                      const spectra::ProfileSettings& settings,
                                      const spectra::ClusterLossSettings& clusters,
                                      const spectra::ProgressFn& progress = {},
                                      spectra::ProfileReport* report = nullptr,
                                      spectra::ClusterLossReport* cluster_report = nullptr);

// The chain of the mesh file `mesh` built with `options`, written to `cache_glb`; or, when
// `cache_glb` exists, the chain read back from it (*cached set true: the caller keeps the cache true
// to its options, refresh_cache). The object is unnamed and at the origin.
lodgen::LodObject cached_chain(const std::string& mesh, const std::string& cache_glb,
                               const lodgen::ChainOptions& options, bool* cached);

// Keeps a folder of cached chains (<dir>/<name>.glb, as cached_chain writes them) and profiles
// (<dir>/profiles/<name>.acuity) true to the code and settings that made them: its stamp
// <dir>/cache-stamp names the bake cache format, the tool version and `settings`; when the stamp is
// missing or differs, those files of each of `names` are removed (nothing else) and the stamp is
// rewritten. Returns true when the cached files were kept. Throws io::Error when the stamp cannot
// be written.
bool refresh_cache(const std::string& dir, const std::vector<std::string>& names,
                   const std::string& settings);

}  // namespace acuity::bake
