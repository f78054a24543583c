// libFuzzer: glTF and GLB through lodgen's one resolving reader (confined uris, JSON depth scan,
// tree and size limits, then tinygltf, then the ACUITY_cluster_hierarchy checks) must give a scene
// whose indices and cluster hierarchies are valid or an InputError:
// never a crash, a hang, a read outside the asset folder or another exception. The input is the
// whole file (GLB when it starts with "glTF"); uris resolve in a private folder holding one
// valid buffer (buffer.bin) and, outside it, a secret the reader must never return.
#include <stdlib.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "acuity/lodgen/mesh.hpp"

namespace {

// 3 positions (a triangle) then 3 uint16 indices, and a secret of 44 bytes of recognisable floats.
void write_fixture(const std::string& dir) {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t i[4] = {0, 1, 2, 0};
  std::ofstream b(dir + "/asset/buffer.bin", std::ios::binary);
  b.write(reinterpret_cast<const char*>(p), sizeof p);
  b.write(reinterpret_cast<const char*>(i), sizeof i);
  const float secret[11] = {1234.5f, 1234.5f, 1234.5f, 1234.5f, 1234.5f, 1234.5f,
                            1234.5f, 1234.5f, 1234.5f, 0,       0};
  std::ofstream(dir + "/secret.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(secret), sizeof secret);
}

const std::string& folder() {
  static const std::string dir = [] {
    char tmpl[] = "/tmp/acuity_fuzz_gltf_XXXXXX";
    const std::string d = mkdtemp(tmpl);
    std::filesystem::create_directories(d + "/asset");
    write_fixture(d);
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = folder() + "/asset/input" + (glb ? ".glb" : ".gltf");
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  try {
    const acuity::lodgen::Scene s = acuity::lodgen::load_scene(path);
    for (const auto& m : s.meshes) {
      for (std::uint32_t i : m.indices)
        if (i >= m.vertex_count()) __builtin_trap();  // the reader promised valid indices
      for (float x : m.positions)
        if (x == 1234.5f) __builtin_trap();  // the secret beside the asset folder was read
    }
    for (std::size_t m = 0; m < s.clusters.size(); ++m) {  // ACUITY_cluster_hierarchy: checked whole
      const acuity::lodgen::ClusterHierarchy& h = s.clusters[m];
      if (!acuity::lodgen::check_cluster_hierarchy(h, s.meshes[m].vertex_count()).empty()) __builtin_trap();
      if (s.meshes[m].indices.size() != 3 * h.finest_triangles() && !h.empty()) __builtin_trap();
    }
    for (const auto& n : s.nodes)
      if (n.lods.size() + 1 > 32) __builtin_trap();  // max_levels
    (void)acuity::lodgen::world_matrices(s);         // a tree: never reached twice
  } catch (const acuity::lodgen::InputError&) {}
  return 0;
}
