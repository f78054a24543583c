#include "acuity/lodgen/decimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "cgal_bridge.hpp"

namespace acuity::lodgen {

bool parse_backend(const std::string& name, Backend* out) {
  if (name == "openmesh") { *out = Backend::OpenMesh; return true; }
  if (name == "cgal" || name == "cgal-gh") { *out = Backend::CgalGarlandHeckbert; return true; }
  if (name == "cgal-lt") { *out = Backend::CgalLindstromTurk; return true; }
  if (name == "meshopt") { *out = Backend::Meshopt; return true; }
  return false;
}

const char* to_string(Backend b) {
  switch (b) {
    case Backend::OpenMesh: return "openmesh";
    case Backend::CgalGarlandHeckbert: return "cgal";
    case Backend::CgalLindstromTurk: return "cgal-lt";
    case Backend::Meshopt: return "meshopt";
  }
  return "?";
}

Mesh decimate(const Mesh& mesh, std::size_t target, const DecimateOptions& o) {
  if (target >= mesh.triangle_count()) {
    Mesh copy = mesh;
    compute_normals(copy);
    return copy;
  }
  switch (o.backend) {
    case Backend::OpenMesh: return detail::decimate_openmesh(mesh, target, o.lock_border);
    case Backend::Meshopt: return detail::decimate_meshopt(mesh, target, o.lock_border);
    case Backend::CgalGarlandHeckbert:
    case Backend::CgalLindstromTurk: break;
  }
  return detail::decimate_cgal(mesh, target, o.backend == Backend::CgalLindstromTurk, o.lock_border);
}

namespace {
// Twice the triangle's area times its unit normal.
std::array<float, 3> face_normal(const Mesh& m, std::size_t t) {
  const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
  float e1[3], e2[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = m.positions[3 * b + k] - m.positions[3 * a + k];
    e2[k] = m.positions[3 * c + k] - m.positions[3 * a + k];
  }
  return {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
}

void normalize_or_up(float* n) {
  const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (len > 0) for (int k = 0; k < 3; ++k) n[k] /= len;
  else { n[0] = 0; n[1] = 0; n[2] = 1; }
}
}  // namespace

Mesh split_creases(const Mesh& m, double crease_degrees) {
  if (crease_degrees >= 180) {
    Mesh copy = m;
    compute_normals(copy);
    return copy;
  }
  const double cos_crease = std::cos(crease_degrees * std::numbers::pi / 180);
  const std::size_t nv = m.vertex_count(), nt = m.triangle_count();
  std::vector<std::array<float, 3>> area_normal(nt), unit(nt);
  for (std::size_t f = 0; f < nt; ++f) {
    area_normal[f] = unit[f] = face_normal(m, 3 * f);
    const float len = std::sqrt(unit[f][0] * unit[f][0] + unit[f][1] * unit[f][1] + unit[f][2] * unit[f][2]);
    for (float& x : unit[f]) x = len > 0 ? x / len : 0.0f;
  }
  // Corners around each vertex (compressed rows).
  std::vector<std::size_t> first(nv + 1, 0), corners(m.indices.size());
  for (std::uint32_t v : m.indices) ++first[v + 1];
  for (std::size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  std::vector<std::size_t> fill(first.begin(), first.end() - 1);
  for (std::size_t c = 0; c < m.indices.size(); ++c) corners[fill[m.indices[c]]++] = c;

  Mesh out;
  out.material = m.material;
  out.indices.resize(m.indices.size());
  const bool uv = m.texcoords.size() == 2 * nv;
  std::vector<std::size_t> group_face;  // the first face of each group of the current vertex
  for (std::size_t v = 0; v < nv; ++v) {
    group_face.clear();
    const std::size_t base = out.vertex_count();
    for (std::size_t i = first[v]; i < first[v + 1]; ++i) {
      const std::size_t c = corners[i], f = c / 3;
      std::size_t g = 0;
      while (g < group_face.size()) {
        const auto& a = unit[group_face[g]];
        const double dot = double(a[0]) * unit[f][0] + double(a[1]) * unit[f][1] + double(a[2]) * unit[f][2];
        const bool degenerate = (a[0] == 0 && a[1] == 0 && a[2] == 0) || (unit[f][0] == 0 && unit[f][1] == 0 && unit[f][2] == 0);
        if (degenerate || dot >= cos_crease) break;
        ++g;
      }
      if (g == group_face.size()) {
        group_face.push_back(f);
        out.positions.insert(out.positions.end(), m.positions.begin() + 3 * v, m.positions.begin() + 3 * v + 3);
        out.normals.insert(out.normals.end(), {0.0f, 0.0f, 0.0f});
        if (uv) out.texcoords.insert(out.texcoords.end(), m.texcoords.begin() + 2 * v, m.texcoords.begin() + 2 * v + 2);
      }
      const std::size_t w = base + g;
      out.indices[c] = std::uint32_t(w);
      for (int k = 0; k < 3; ++k) out.normals[3 * w + k] += area_normal[f][k];
    }
    if (first[v] == first[v + 1]) {  // unused vertex: kept so indices stay meaningful to callers
      out.positions.insert(out.positions.end(), m.positions.begin() + 3 * v, m.positions.begin() + 3 * v + 3);
      out.normals.insert(out.normals.end(), {0.0f, 0.0f, 1.0f});
      if (uv) out.texcoords.insert(out.texcoords.end(), m.texcoords.begin() + 2 * v, m.texcoords.begin() + 2 * v + 2);
    }
  }
  for (std::size_t w = 0; w < out.vertex_count(); ++w) normalize_or_up(&out.normals[3 * w]);
  return out;
}

void compute_normals(Mesh& m) {
  m.normals.assign(m.positions.size(), 0.0f);
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const std::array<float, 3> n = face_normal(m, t);  // length = twice the area: area weighting
    for (std::size_t i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) m.normals[3 * m.indices[t + i] + k] += n[k];
  }
  for (std::size_t v = 0; v < m.vertex_count(); ++v) normalize_or_up(&m.normals[3 * v]);
}

}  // namespace acuity::lodgen
