#include "acuity/lodgen/formats.hpp"

#include "acuity/file.hpp"

namespace acuity::lodgen {

const std::vector<InputFormat>& input_formats() {
  static const std::vector<InputFormat> formats = {
      {".off", "OFF", FormatReader::OpenMesh}, {".obj", "OBJ", FormatReader::OpenMesh},
      {".ply", "PLY", FormatReader::OpenMesh}, {".stl", "STL", FormatReader::OpenMesh},
      {".gltf", "glTF", FormatReader::Gltf},   {".glb", "GLB", FormatReader::Gltf},
  };
  return formats;
}

const InputFormat* input_format(const std::string& path) {
  const std::string ext = io::lower_extension(path);
  for (const InputFormat& f : input_formats())
    if (f.extension == ext) return &f;
  return nullptr;
}

bool is_gltf(const std::string& path) {
  const InputFormat* f = input_format(path);
  return f && f->reader == FormatReader::Gltf;
}

std::string input_format_names() {
  std::string out;
  for (const InputFormat& f : input_formats()) out += (out.empty() ? "" : ", ") + f.name;
  return out;
}

const std::vector<std::string>& chain_output_extensions() {
  static const std::vector<std::string> extensions = {".glb", ".gltf"};
  return extensions;
}

}  // namespace acuity::lodgen
