#include "acuity/bake/scene.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "acuity/transform.hpp"

namespace acuity::bake {
namespace fs = std::filesystem;
namespace {

using Matrix = std::array<double, 16>;

// Reads the cached profile into a when it describes this chain (same level count and triangles)
// measured with these snapshots (pixels across). Whether its views bound their cells is not in the
// file: a caller that changes bound_cells keeps those profiles in a folder of their own.
bool load_matching_profile(const std::string& path, const lodgen::Chain& chain, std::uint32_t pixels,
                           Asset* a) {
  if (!fs::exists(path)) return false;
  try {
    a->blob = io::read_file(path);
  } catch (const io::Error&) { return false; }  // unreadable: built and written again
  const Profile& p = a->profile;
  if (open_profile(a->blob.data(), a->blob.size, &a->profile) != ProfileStatus::Ok ||
      p.meta.level_count != chain.levels.size() || p.meta.snapshot_pixels != pixels)
    return false;
  for (std::size_t k = 0; k < chain.levels.size(); ++k)
    if (p.levels[k].triangles != chain.levels[k].mesh.triangle_count()) return false;
  return true;
}

}  // namespace

std::string file_safe(const std::string& name) {
  std::string s;
  for (char c : name) s += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return s.empty() ? "object" : s;
}

spectra::MeshView spectra_mesh(const lodgen::Mesh& m) {
  spectra::MeshView v;
  v.positions = m.positions.data();
  v.vertex_count = m.vertex_count();
  v.indices = m.indices.data();
  v.index_count = m.indices.size();
  v.normals = m.normals.empty() ? nullptr : m.normals.data();
  v.texcoords = m.texcoords.empty() ? nullptr : m.texcoords.data();
  return v;
}

spectra::ClusterMesh cluster_mesh(const lodgen::Mesh& mesh, const lodgen::ClusterHierarchy& h) {
  return {spectra_mesh(mesh), h.indices, h.clusters, h.groups};
}

std::vector<spectra::LevelInput> spectra_levels(const lodgen::Chain& chain) {
  std::vector<spectra::LevelInput> out;
  for (const lodgen::Level& level : chain.levels) {
    spectra::LevelInput l;
    l.mesh = spectra_mesh(level.mesh);
    l.geometric_error = float(level.hausdorff);
    out.push_back(l);
  }
  return out;
}

spectra::Material spectra_material(const lodgen::Scene& scene, int index) {
  spectra::Material material;
  if (index < 0 || std::size_t(index) >= scene.materials.size()) return material;
  const lodgen::Material& m = scene.materials[std::size_t(index)];
  std::copy(m.base_color, m.base_color + 4, material.base_color);
  if (!m.pixels.empty()) {
    material.texture = m.pixels.data();
    material.texture_width = m.width;
    material.texture_height = m.height;
    material.texture_channels = 4;
  }
  return material;
}

std::unique_ptr<SceneAssets> load_scene_assets(const std::string& path, const AssetOptions& o) {
  auto out = std::make_unique<SceneAssets>();
  lodgen::LoadOptions lo;
  lo.asset_root = o.asset_root;
  out->scene = lodgen::load_scene(path, lo);
  const lodgen::Scene& scene = out->scene;
  std::vector<bool> is_lod(scene.nodes.size(), false);
  for (const lodgen::Node& n : scene.nodes)
    for (int l : n.lods) is_lod[std::size_t(l)] = true;

  // Instances: every node with a mesh reached from the roots that is not another node's coarser level.
  std::map<int, int> asset_of_mesh;
  std::map<std::string, int> names;
  std::vector<const lodgen::Node*> tops;
  std::vector<lodgen::PlacedNode> placed;
  try {
    placed = lodgen::world_matrices(scene, [&](int id) { return is_lod[std::size_t(id)]; });
  } catch (const lodgen::InputError& e) { throw lodgen::InputError(path + ": " + e.what()); }
  for (const lodgen::PlacedNode& p : placed) {
    const int id = p.node;
    const Matrix& world = p.world;
    const lodgen::Node& n = scene.nodes[std::size_t(id)];
    if (n.mesh < 0 || scene.meshes[std::size_t(n.mesh)].indices.empty()) continue;
    auto [it, fresh] = asset_of_mesh.try_emplace(n.mesh, int(tops.size()));
    if (fresh) tops.push_back(&n);
    Instance in;
    in.asset = it->second;
    in.name = n.name.empty() ? "node" + std::to_string(id) : n.name;
    in.transform = transform_from_matrix(world.data());
    out->instances.push_back(in);
  }
  if (out->instances.empty()) throw lodgen::InputError(path + ": the scene has no mesh to simulate");

  if (!o.profiles.empty()) fs::create_directories(o.profiles);
  for (const lodgen::Node* top : tops) {
    Asset a;
    std::string base = file_safe(scene.mesh_names[std::size_t(top->mesh)]);
    const int seen = names[base]++;
    a.name = seen ? base + "_" + std::to_string(seen) : base;
    const auto t0 = std::chrono::steady_clock::now();
    std::string what;
    if (!top->lods.empty()) {
      a.chain = lodgen::chain_of_node(scene, *top);
    } else {  // a plain mesh: lodgen builds its chain
      lodgen::ChainOptions co;
      co.levels = o.lod_levels;
      a.chain = lodgen::build_chain(scene.meshes[std::size_t(top->mesh)], path + ": mesh " + a.name, co);
      what = "lodgen + ";
    }
    a.material = spectra_material(scene, a.chain.levels[0].mesh.material);
    const std::string file =
        o.profiles.empty() ? std::string() : (fs::path(o.profiles) / (a.name + ".acuity")).string();
    if (file.empty() || !load_matching_profile(file, a.chain, o.profile_pixels, &a)) {
      const std::vector<spectra::LevelInput> levels = spectra_levels(a.chain);
      spectra::ProfileSettings ps;
      ps.render.pixels = o.profile_pixels;
      ps.bound_cells = o.bound_cells;
      spectra::ProfileReport report;
      const spectra::ProfileData data = spectra::build_profile(levels, a.material, ps, {}, &report);
      if (!file.empty()) spectra::write_profile(file, data);
      a.blob = spectra::encode_profile(data);
      ProfileError pe;
      if (open_profile(a.blob.data(), a.blob.size, &a.profile, &pe) != ProfileStatus::Ok)
        throw std::runtime_error(a.name + ": " + pe.message);
      what += "profile (" + std::to_string(report.views_kept) + " views)";
    } else {
      what = "profile from " + file;
    }
    if (!o.quiet)
      std::printf("  %-12s %zu levels, %zu -> %zu triangles: %s, %.1f s\n", a.name.c_str(),
                  a.chain.levels.size(), a.chain.levels.front().mesh.triangle_count(),
                  a.chain.levels.back().mesh.triangle_count(), what.c_str(),
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    out->assets.push_back(std::move(a));
  }
  for (Instance& in : out->instances)
    in.radius = double(out->assets[std::size_t(in.asset)].profile.meta.sphere[3]) * in.transform.scale;
  return out;
}

}  // namespace acuity::bake
