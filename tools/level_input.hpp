#pragma once
// A lodgen mesh as a spectra level (the arrays are borrowed: the mesh must outlive the result).
#include "acuity/lodgen/mesh.hpp"
#include "acuity/spectra/profile_builder.hpp"

namespace acuity::tools {

inline spectra::LevelInput level_input(const lodgen::Mesh& m, float geometric_error) {
  spectra::LevelInput l;
  l.mesh.positions = m.positions.data();
  l.mesh.vertex_count = m.vertex_count();
  l.mesh.indices = m.indices.data();
  l.mesh.index_count = m.indices.size();
  l.mesh.normals = m.normals.empty() ? nullptr : m.normals.data();
  l.mesh.texcoords = m.texcoords.empty() ? nullptr : m.texcoords.data();
  l.geometric_error = geometric_error;
  return l;
}

}  // namespace acuity::tools
