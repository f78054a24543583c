#pragma once
// Meshes with known answers for tests and benchmarks: a sphere of radius r (spectra's icosphere).
#include <cstdint>
#include <vector>

#include "acuity/spectra/profile_builder.hpp"
#include "acuity/spectra/render.hpp"

namespace acuity::testing {

struct TestMesh {
  std::vector<float> positions, normals;
  std::vector<std::uint32_t> indices;
  spectra::MeshView view() const {
    spectra::MeshView m;
    m.positions = positions.data();
    m.vertex_count = positions.size() / 3;
    m.indices = indices.data();
    m.index_count = indices.size();
    m.normals = normals.empty() ? nullptr : normals.data();
    return m;
  }
};

inline TestMesh icosphere(int subdivisions, float radius = 1.0f) {
  spectra::SphereMesh s = spectra::icosphere(subdivisions);
  TestMesh m;
  m.normals = s.positions;
  m.positions = std::move(s.positions);
  for (float& x : m.positions) x *= radius;
  m.indices = std::move(s.indices);
  return m;
}

}  // namespace acuity::testing
