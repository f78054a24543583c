// libFuzzer: the importers (OpenMesh for OFF/OBJ/PLY/STL, tinygltf for glTF/GLB) must turn any
// bytes into a mesh or an InputError. The first byte picks the format; the rest is the file.
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "acuity/lodgen/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExt[] = {".off", ".obj", ".ply", ".stl", ".gltf", ".glb"};
  const std::string path = "/tmp/acuity_fuzz_" + std::to_string(getpid()) + kExt[data[0] % 6];
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
  try {
    const acuity::lodgen::Scene s = acuity::lodgen::load_scene(path);
    for (const auto& m : s.meshes)
      for (std::uint32_t i : m.indices)
        if (i >= m.vertex_count()) __builtin_trap();  // the importer promised valid indices
  } catch (const acuity::lodgen::InputError&) {}
  unlink(path.c_str());
  return 0;
}
