#include "acuity/lodgen/mesh.hpp"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cmath>
#include <filesystem>

namespace acuity::lodgen {
namespace {
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;
}

Mesh load_mesh(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such file");
  OmMesh om;
  OpenMesh::IO::Options options;
  if (!OpenMesh::IO::read_mesh(om, path, options))
    throw InputError(path + ": not a readable OFF, OBJ, PLY or STL mesh");
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
  if (mesh.indices.empty()) throw InputError(path + ": the mesh has no triangles");
  return mesh;
}

}  // namespace acuity::lodgen
