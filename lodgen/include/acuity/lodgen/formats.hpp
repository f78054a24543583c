#pragma once
// acuity/lodgen/formats.hpp — the formats lodgen reads, and how: the one list load_scene picks a
// reader from, `acuity bake` walks a folder for, and the command's help names.
#include <string>
#include <vector>

namespace acuity::lodgen {

// How a format is read.
enum class FormatReader {
  Gltf,      // lodgen's glTF reader: tinygltf behind lodgen's checks, bounded by LoadLimits
  OpenMesh,  // OpenMesh, one mesh per file, in a child process by default (load_mesh_isolated)
};

struct InputFormat {
  std::string extension;  // lower case, with the dot: ".glb"
  std::string name;       // as help texts write it: "GLB"
  FormatReader reader;
};

// Every format lodgen reads, meshes first (OFF, OBJ, PLY, STL), then glTF and GLB.
const std::vector<InputFormat>& input_formats();

// The format of `path` by its extension (any case), or nullptr when lodgen reads none.
const InputFormat* input_format(const std::string& path);

// True when `path` names a glTF or GLB file (FormatReader::Gltf).
bool is_gltf(const std::string& path);

// The formats' names for help texts and messages: "OFF, OBJ, PLY, STL, glTF, GLB".
std::string input_format_names();

// What a chain is written as: ".glb" (binary) or ".gltf" (JSON with the buffer embedded).
const std::vector<std::string>& chain_output_extensions();

}  // namespace acuity::lodgen
