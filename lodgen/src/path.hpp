#pragma once
// A file's extension, lower case with its dot (".off", ".glb"): how the importers pick a format.
#include <cctype>
#include <filesystem>
#include <string>

namespace acuity::lodgen::detail {

inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace acuity::lodgen::detail
