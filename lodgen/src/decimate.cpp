#include "acuity/lodgen/decimate.hpp"

#include <cmath>
#include <cstring>

#include "cgal_bridge.hpp"

namespace acuity::lodgen {

bool parse_backend(const std::string& name, Backend* out) {
  if (name == "openmesh") { *out = Backend::OpenMesh; return true; }
  if (name == "cgal" || name == "cgal-gh") { *out = Backend::CgalGarlandHeckbert; return true; }
  if (name == "cgal-lt") { *out = Backend::CgalLindstromTurk; return true; }
  return false;
}

const char* to_string(Backend b) {
  switch (b) {
    case Backend::OpenMesh: return "openmesh";
    case Backend::CgalGarlandHeckbert: return "cgal";
    case Backend::CgalLindstromTurk: return "cgal-lt";
  }
  return "?";
}

Mesh decimate(const Mesh& mesh, std::size_t target, const DecimateOptions& o) {
  if (target >= mesh.triangle_count()) {
    Mesh copy = mesh;
    compute_normals(copy);
    return copy;
  }
  return o.backend == Backend::OpenMesh ? detail::decimate_openmesh(mesh, target, o.lock_border)
                                        : detail::decimate_cgal(mesh, target, o.backend == Backend::CgalLindstromTurk, o.lock_border);
}

void compute_normals(Mesh& m) {
  m.normals.assign(m.positions.size(), 0.0f);
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
    float e1[3], e2[3], n[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = m.positions[3 * b + k] - m.positions[3 * a + k];
      e2[k] = m.positions[3 * c + k] - m.positions[3 * a + k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];  // length = twice the area: area weighting
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    for (std::uint32_t v : {a, b, c})
      for (int k = 0; k < 3; ++k) m.normals[3 * v + k] += n[k];
  }
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    float* n = &m.normals[3 * v];
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0) for (int k = 0; k < 3; ++k) n[k] /= len;
    else { n[0] = 0; n[1] = 0; n[2] = 1; }
  }
}

}  // namespace acuity::lodgen
