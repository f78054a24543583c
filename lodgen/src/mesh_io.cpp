#include "acuity/lodgen/mesh.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace acuity::lodgen {
namespace {
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The element counts an OFF or PLY header declares (0 when there is none), checked against what
// the file's size can hold, so a lying header cannot make the reader reserve absurd memory.
std::size_t declared_faces(const std::string& path, std::uintmax_t size) {
  std::ifstream in(path, std::ios::binary);
  const std::string ext = lower_extension(path);
  std::size_t faces = 0;
  auto check = [&](const char* what, unsigned long long count, unsigned long long min_bytes) {
    if (count > size / min_bytes)
      throw InputError(path + ": header declares " + std::to_string(count) + " " + what + ", more than its " +
                       std::to_string(size) + " bytes can hold");
  };
  if (ext == ".off") {
    std::string word;
    in >> word;  // OFF, COFF, NOFF, "OFF BINARY", ...
    if (word.find("OFF") == std::string::npos) return 0;
    const bool binary = in.peek() == ' ' && (in >> word, word == "BINARY");
    long long nv = -1, nf = -1, ne = -1;
    in >> nv >> nf >> ne;
    if (!in || nv < 0 || nf < 0) throw InputError(path + ": malformed OFF header");
    check("vertices", static_cast<unsigned long long>(nv), binary ? 12 : 6);
    check("faces", static_cast<unsigned long long>(nf), binary ? 16 : 7);
    faces = static_cast<std::size_t>(nf);
  } else if (ext == ".ply") {
    // OpenMesh's PLY reader loops forever on a header that never ends: check it here first.
    std::string line;
    std::getline(in, line);
    if (line.rfind("ply", 0) != 0) throw InputError(path + ": not a PLY file (no 'ply' magic)");
    bool format = false, ended = false;
    int properties = 0;
    unsigned long long pending = 0;
    std::string pending_name;
    auto flush = [&] {
      if (!pending_name.empty()) check(pending_name.c_str(), pending, static_cast<unsigned long long>(std::max(1, properties)));
      if (pending_name == "faces") faces = static_cast<std::size_t>(pending);
    };
    while (std::getline(in, line)) {
      if (line.rfind("end_header", 0) == 0) { ended = true; break; }
      std::istringstream words(line);
      std::string key, name;
      words >> key;
      if (key == "format") {
        words >> name;
        format = name == "ascii" || name == "binary_little_endian" || name == "binary_big_endian";
        if (!format) throw InputError(path + ": unknown PLY format '" + name + "'");
      } else if (key == "property") {
        std::string type;
        words >> type;
        static const char* const kTypes[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double",
                                             "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32",
                                             "float64", "list"};
        if (std::find(std::begin(kTypes), std::end(kTypes), type) == std::end(kTypes))
          throw InputError(path + ": PLY property type '" + type + "' is not supported");
      } else if (!key.empty() && key != "element" && key != "comment" && key != "obj_info") {
        throw InputError(path + ": unexpected PLY header line '" + line + "'");
      }
      if (key == "element") {
        flush();
        unsigned long long count = 0;
        words >> name >> count;
        pending_name = name == "face" ? "faces" : name;
        pending = count;
        properties = 0;
      } else if (key == "property") {
        ++properties;
      }
    }
    if (!format || !ended) throw InputError(path + ": PLY header is incomplete (no format line or no end_header)");
    flush();
  }
  return faces;
}
}  // namespace

Mesh load_mesh(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such file");
  const std::size_t declared = declared_faces(path, std::filesystem::file_size(path));
  OmMesh om;
  OpenMesh::IO::Options options;
  if (!OpenMesh::IO::read_mesh(om, path, options))
    throw InputError(path + ": not a readable OFF, OBJ, PLY or STL mesh");
  if (declared > 0 && om.n_faces() < declared)
    throw InputError(path + ": header declares " + std::to_string(declared) + " faces, read " +
                     std::to_string(om.n_faces()) + " (truncated, or a malformed number)");
  Mesh mesh;
  mesh.positions.reserve(om.n_vertices() * 3);
  for (const auto vh : om.vertices()) {
    const auto& p = om.point(vh);
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k]))
        throw InputError(path + ": vertex " + std::to_string(vh.idx()) + " has a non-finite coordinate");
      mesh.positions.push_back(p[k]);
    }
  }
  mesh.indices.reserve(om.n_faces() * 3);
  for (const auto fh : om.faces())
    for (const auto vh : om.fv_range(fh)) mesh.indices.push_back(static_cast<std::uint32_t>(vh.idx()));
  if (mesh.indices.empty())
    throw InputError(path + ": no triangles could be read (faces with missing vertices or malformed lines are dropped)");
  return mesh;
}

double diameter(const Mesh& mesh) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], double(mesh.positions[i]));
    hi[i % 3] = std::max(hi[i % 3], double(mesh.positions[i]));
  }
  double r2 = 0;
  for (std::size_t i = 0; i + 2 < mesh.positions.size(); i += 3) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double d = mesh.positions[i + k] - 0.5 * (lo[k] + hi[k]);
      d2 += d * d;
    }
    r2 = std::max(r2, d2);
  }
  return 2 * std::sqrt(r2);
}

}  // namespace acuity::lodgen
