#include "acuity/bake/chains.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "acuity/bake/library.hpp"
#include "acuity/bake/scene.hpp"
#include "acuity/file.hpp"
#include "acuity/lodgen/formats.hpp"
#include "acuity/lodgen/refine.hpp"

namespace acuity::bake {
namespace {

// One object per node that draws a mesh, at its world matrix, with its mesh's chain.
void place_objects(SceneChains& out, const std::string& where) {
  std::vector<lodgen::PlacedNode> placed;
  try {
    placed = lodgen::world_matrices(out.scene);
  } catch (const lodgen::InputError& e) { throw lodgen::InputError(where + ": " + e.what()); }
  for (const lodgen::PlacedNode& p : placed) {
    const lodgen::Node& node = out.scene.nodes[std::size_t(p.node)];
    if (node.mesh < 0) continue;
    lodgen::LodObject obj;
    obj.name = node.name.empty() ? out.scene.mesh_names[std::size_t(node.mesh)] : node.name;
    obj.matrix = p.world;
    obj.chain = out.chains[std::size_t(node.mesh)];
    obj.material = obj.chain.levels[0].mesh.material;
    if (std::size_t(node.mesh) < out.clusters.size()) obj.clusters = out.clusters[std::size_t(node.mesh)];
    out.objects.push_back(std::move(obj));
  }
  if (out.objects.empty()) throw lodgen::InputError(where + ": the scene draws no mesh");
}

// What the table and the JSON say of a hierarchy: its roots (clusters in no group), their
// triangles, and the largest error a root carries [object diameters].
struct ClusterSummary {
  std::size_t roots = 0, root_triangles = 0;
  double root_error = 0;
};
ClusterSummary summarise(const lodgen::ClusterHierarchy& h, double diameter) {
  ClusterSummary s;
  for (const lodgen::Cluster& c : h.clusters) {
    if (c.group != lodgen::kNoGroup) continue;
    ++s.roots;
    s.root_triangles += c.triangle_count;
    if (c.refined != lodgen::kNoGroup && diameter > 0)
      s.root_error = std::max(s.root_error, double(h.groups[c.refined].error) / diameter);
  }
  return s;
}

}  // namespace

SceneChains chains_of_scene(lodgen::Scene scene, const std::string& where, lodgen::ChainOptions options,
                            const lodgen::ChainProgress& progress, double measure_seconds, bool clusters) {
  SceneChains out;
  out.scene = std::move(scene);
  if (clusters) options.levels = 1;  // level 0 only: the hierarchy holds the coarser geometry
  // One measurement budget for the asset: each measured side of a coarser level gets an equal part
  // of what is left (a side's samples follow the mesh's size, not its triangle count, up to the
  // sample cap; decimation itself is bounded by meshoptimizer's speed).
  const auto start = std::chrono::steady_clock::now();
  auto sides = [&](const lodgen::Mesh& mesh) {  // two per coarser level build_chain will make
    const double n = double(mesh.triangle_count()), floor = std::max(64.0, n / 100);
    const double levels = n > floor ? std::floor(std::log(n / floor) / std::log(1 / options.ratio)) : 0;
    return 2 * std::min(levels, options.levels ? double(options.levels) - 1 : 31.0);
  };
  double sides_left = 0;
  for (const lodgen::Mesh& mesh : out.scene.meshes) sides_left += sides(mesh);
  for (std::size_t m = 0; m < out.scene.meshes.size(); ++m) {
    const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    options.measure.max_seconds = std::max(0.01, (measure_seconds - spent) / std::max(1.0, sides_left));
    sides_left -= sides(out.scene.meshes[m]);
    out.chains.push_back(lodgen::build_chain(
        out.scene.meshes[m], where + ": mesh '" + out.scene.mesh_names[m] + "'", options, progress));
    if (clusters) {
      if (progress) progress("clusters", m, out.scene.meshes.size());
      out.cluster_stats.emplace_back();
      out.clusters.push_back(lodgen::build_clusters(out.chains.back().levels[0].mesh,
                                                    where + ": mesh '" + out.scene.mesh_names[m] + "'", {},
                                                    &out.cluster_stats.back()));
    }
  }
  if (clusters && progress) progress("clusters", out.scene.meshes.size(), out.scene.meshes.size());
  place_objects(out, where);
  return out;
}

SceneChains build_scene_chains(const ChainRequest& r, const lodgen::ChainProgress& progress) {
  if (r.refine <= 0) {
    lodgen::LoadOptions lo;
    lo.asset_root = r.asset_root;
    return chains_of_scene(lodgen::load_scene(r.input, lo), r.input, r.chain, progress, r.measure_seconds,
                           r.clusters);
  }
  if (r.clusters)
    throw lodgen::InputError(r.input + ": cluster hierarchies are built from a mesh, not a cage to refine");
  SceneChains out;
  const lodgen::PolygonMesh cage = lodgen::load_polygon_mesh(r.input);
  out.chains.push_back(lodgen::measure_chain(lodgen::refine(cage, r.refine), progress));
  out.scene.mesh_names.push_back(std::filesystem::path(r.input).stem().string());
  lodgen::Node node;  // identity matrix by default
  node.name = out.scene.mesh_names[0];
  node.mesh = 0;
  out.scene.nodes.push_back(node);
  out.scene.roots.push_back(0);
  place_objects(out, r.input);
  return out;
}

ChainFile read_chain_file(const std::string& path, const std::string& asset_root) {
  lodgen::LoadOptions lo;
  lo.asset_root = asset_root;
  return chain_file(lodgen::load_scene(path, lo), path);
}

ChainFile chain_file(lodgen::Scene scene, const std::string& path) {
  ChainFile f;
  f.scene = std::move(scene);
  for (const lodgen::Node& n : f.scene.nodes)
    if (n.mesh >= 0 && !n.lods.empty()) {
      f.chain = lodgen::chain_of_node(f.scene, n);
      f.material = spectra_material(f.scene, f.chain.levels[0].mesh.material);
      return f;
    }
  throw lodgen::InputError(path + ": no node with MSFT_lod levels");
}

spectra::ClusterMesh ClusterFile::view() const {
  return cluster_mesh(scene.meshes[mesh], scene.clusters[mesh]);
}

ClusterFile read_cluster_file(const std::string& path, const std::string& asset_root) {
  ClusterFile f;
  lodgen::LoadOptions lo;
  lo.asset_root = asset_root;
  f.scene = lodgen::load_scene(path, lo);
  while (f.mesh < f.scene.clusters.size() && f.scene.clusters[f.mesh].empty()) ++f.mesh;
  if (f.found()) f.material = spectra_material(f.scene, f.scene.meshes[f.mesh].material);
  return f;
}

spectra::ProfileData profile_clusters(const spectra::ClusterMesh& mesh, const spectra::Material& material,
                                      const spectra::ProfileSettings& settings,
                                      const spectra::ClusterLossSettings& clusters,
                                      const spectra::ProgressFn& progress, spectra::ProfileReport* report,
                                      spectra::ClusterLossReport* cluster_report) {
  spectra::LevelInput finest;  // the finest clusters: the first triangles of the hierarchy's indices
  finest.mesh = mesh.mesh;
  finest.mesh.indices = mesh.indices.data();
  finest.mesh.index_count = 0;
  for (std::size_t c = 0; c < mesh.clusters.size() && mesh.clusters[c].refined == lodgen::kNoGroup; ++c)
    finest.mesh.index_count += 3 * std::size_t(mesh.clusters[c].triangle_count);
  // One level loses nothing, so cell bounds would render their 162 samples to bound nothing.
  spectra::ProfileSettings level0 = settings;
  level0.bound_cells = false;
  spectra::ProfileData data = spectra::build_profile({finest}, material, level0, progress, report);
  data.clusters = spectra::measure_cluster_loss(mesh, material, clusters, progress, cluster_report);
  return data;
}

lodgen::LodObject cached_chain(const std::string& mesh, const std::string& cache_glb,
                               const lodgen::ChainOptions& options, bool* cached) {
  lodgen::LodObject obj;
  *cached = std::filesystem::exists(cache_glb);
  if (*cached) {
    obj.chain = read_chain_file(cache_glb).chain;
    return obj;
  }
  ChainRequest request;
  request.input = mesh;
  request.chain = options;
  obj = std::move(build_scene_chains(request).objects.at(0));
  lodgen::write_lod_gltf(cache_glb, {obj}, {});
  return obj;
}

bool refresh_cache(const std::string& dir, const std::vector<std::string>& names,
                   const std::string& settings) {
  namespace fs = std::filesystem;
  const std::string stamp = cache_format() + "\n" + tool_version() + "\n" + settings + "\n";
  const fs::path path = fs::path(dir) / "cache-stamp";
  try {
    const Blob old = io::read_file(path.string());
    if (std::string(static_cast<const char*>(old.data()), old.size) == stamp) return true;
  } catch (const io::Error&) {}  // no stamp yet, or an unreadable one: the cache is renewed
  for (const std::string& name : names) {
    std::error_code ec;
    fs::remove(fs::path(dir) / (name + ".glb"), ec);
    fs::remove(fs::path(dir) / "profiles" / (name + ".acuity"), ec);
  }
  fs::create_directories(dir);
  io::write_file_atomically(path.string(), stamp);
  return false;
}

std::string chains_table(const SceneChains& sc) {
  char line[256];
  std::snprintf(line, sizeof line, "%-24s %5s %10s %10s %12s %9s %8s\n", "mesh", "level", "target",
                "triangles", "hausdorff", "normal99", "seconds");
  std::string out = line;
  for (std::size_t m = 0; m < sc.chains.size(); ++m)
    for (std::size_t k = 0; k < sc.chains[m].levels.size(); ++k) {
      const lodgen::Level& l = sc.chains[m].levels[k];
      std::snprintf(line, sizeof line, "%-24.24s %5zu %10zu %10zu %12.6f %9.2f %8.3f\n",
                    sc.scene.mesh_names[m].c_str(), k, l.target_triangles, l.mesh.triangle_count(),
                    l.hausdorff, l.normal_deviation, l.seconds);
      out += line;
    }
  if (!sc.clusters.empty()) {
    std::snprintf(line, sizeof line, "%-24s %8s %7s %6s %6s %10s %12s %8s\n", "mesh", "clusters", "groups",
                  "levels", "roots", "root_tris", "root_error", "seconds");
    out += line;
  }
  for (std::size_t m = 0; m < sc.clusters.size(); ++m) {
    const ClusterSummary s = summarise(sc.clusters[m], sc.chains[m].diameter);
    std::snprintf(line, sizeof line, "%-24.24s %8zu %7zu %6zu %6zu %10zu %12.6f %8.3f\n",
                  sc.scene.mesh_names[m].c_str(), sc.clusters[m].clusters.size(),
                  sc.clusters[m].groups.size(), sc.clusters[m].levels(), s.roots, s.root_triangles,
                  s.root_error, sc.cluster_stats[m].seconds);
    out += line;
  }
  return out;
}

std::string chains_json(const SceneChains& sc, const std::string& input, const std::string& output,
                        const std::string& backend, double seconds) {
  nlohmann::json summary = {{"input", input}, {"output", output}, {"backend", backend}};
  for (std::size_t m = 0; m < sc.chains.size(); ++m) {
    nlohmann::json jm = {{"name", sc.scene.mesh_names[m]},
                         {"diameter", sc.chains[m].diameter},
                         {"warnings", sc.chains[m].warnings}};
    for (const lodgen::Level& l : sc.chains[m].levels)
      jm["levels"].push_back({{"target", l.target_triangles},
                              {"triangles", l.mesh.triangle_count()},
                              {"hausdorff_diameters", l.hausdorff},
                              {"normal_deviation_degrees", l.normal_deviation},
                              {"normal_deviation_max_degrees", l.normal_deviation_max},
                              {"measured_fully", l.measured_fully},
                              {"seconds", l.seconds}});
    if (m < sc.clusters.size()) {
      const lodgen::ClusterHierarchy& h = sc.clusters[m];
      const ClusterSummary s = summarise(h, sc.chains[m].diameter);
      jm["clusters"] = {{"clusters", h.clusters.size()},
                        {"groups", h.groups.size()},
                        {"levels", h.levels()},
                        {"roots", s.roots},
                        {"root_triangles", s.root_triangles},
                        {"root_error_diameters", s.root_error},
                        {"stuck_groups", sc.cluster_stats[m].stuck_groups},
                        {"seconds", sc.cluster_stats[m].seconds}};
    }
    summary["meshes"].push_back(jm);
  }
  summary["seconds"] = seconds;
  return summary.dump(2) + "\n";
}

WrittenChains write_scene_chains(const ChainRequest& request, const std::string& output,
                                 double reference_height, const std::string& backend,
                                 const lodgen::ChainProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (!output.empty())
    io::check_output(output, {request.input}, lodgen::chain_output_extensions());  // before any work
  WrittenChains out;
  out.chains = build_scene_chains(request, progress);
  if (!output.empty()) {
    lodgen::GltfWriteOptions wo;
    wo.reference_height = reference_height;
    wo.binary = io::lower_extension(output) != ".gltf";
    lodgen::write_lod_gltf(output, out.chains.objects, out.chains.scene.materials, wo);
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.json = chains_json(out.chains, request.input, output, backend, out.seconds);
  return out;
}

}  // namespace acuity::bake
