#include "acuity/lodgen/decimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "cgal_bridge.hpp"

namespace acuity::lodgen {

bool parse_backend(const std::string& name, Backend* out) {
  if (name == "openmesh") {
    *out = Backend::OpenMesh;
    return true;
  }
  if (name == "cgal" || name == "cgal-gh") {
    *out = Backend::CgalGarlandHeckbert;
    return true;
  }
  if (name == "cgal-lt") {
    *out = Backend::CgalLindstromTurk;
    return true;
  }
  if (name == "meshopt") {
    *out = Backend::Meshopt;
    return true;
  }
  return false;
}

const char* to_string(Backend b) {
  switch (b) {
    case Backend::OpenMesh:
      return "openmesh";
    case Backend::CgalGarlandHeckbert:
      return "cgal";
    case Backend::CgalLindstromTurk:
      return "cgal-lt";
    case Backend::Meshopt:
      return "meshopt";
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
    case Backend::OpenMesh:
      return detail::decimate_openmesh(mesh, target, o.lock_border);
    case Backend::Meshopt:
      return detail::decimate_meshopt(mesh, target, o.lock_border, o.crease_degrees);
    case Backend::CgalGarlandHeckbert:
    case Backend::CgalLindstromTurk:
      break;
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
  if (len > 0)
    for (int k = 0; k < 3; ++k) n[k] /= len;
  else {
    n[0] = 0;
    n[1] = 0;
    n[2] = 1;
  }
}

// Union-find over the mesh's corners (3 per triangle).
std::size_t find_root(std::vector<std::size_t>& parent, std::size_t c) {
  while (parent[c] != c) c = parent[c] = parent[parent[c]];
  return c;
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
  std::vector<std::array<float, 3>> area_normal(nt);
  std::vector<std::array<double, 3>> unit(nt);
  for (std::size_t f = 0; f < nt; ++f) {
    area_normal[f] = face_normal(m, 3 * f);
    const auto& n = area_normal[f];
    const double len = std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
    for (int k = 0; k < 3; ++k) unit[f][std::size_t(k)] = len > 0 ? n[std::size_t(k)] / len : 0.0;
  }
  // Corners around each vertex (compressed rows).
  std::vector<std::size_t> first(nv + 1, 0), corners(m.indices.size());
  for (std::uint32_t v : m.indices) ++first[v + 1];
  for (std::size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  std::vector<std::size_t> fill(first.begin(), first.end() - 1);
  for (std::size_t c = 0; c < m.indices.size(); ++c) corners[fill[m.indices[c]]++] = c;
  const auto next = [](std::size_t c) { return c - c % 3 + (c + 1) % 3; };
  // Corners around a vertex stay together across every edge shared by exactly two triangles, in
  // opposite directions, whose normals lie within the crease angle (a degenerate triangle joins
  // either side); each resulting fan becomes one vertex. A crease that ends inside a surface
  // leaves its end vertex one fan.
  std::vector<std::size_t> parent(m.indices.size());
  for (std::size_t c = 0; c < parent.size(); ++c) parent[c] = c;
  for (std::size_t c = 0; c < m.indices.size(); ++c) {
    const std::uint32_t a = m.indices[c], b = m.indices[next(c)];
    if (a >= b) continue;  // each edge once, from its lower vertex
    std::size_t twin = 0, twins = 0, same = 0;
    for (std::size_t i = first[b]; i < first[b + 1]; ++i)
      if (m.indices[next(corners[i])] == a) {
        twin = corners[i];
        ++twins;
      }
    for (std::size_t i = first[a]; i < first[a + 1]; ++i) same += m.indices[next(corners[i])] == b;
    if (twins != 1 || same != 1) continue;  // a border, or three and more triangles: a crease
    const auto& n1 = unit[c / 3];
    const auto& n2 = unit[twin / 3];
    const bool degenerate =
        (n1[0] == 0 && n1[1] == 0 && n1[2] == 0) || (n2[0] == 0 && n2[1] == 0 && n2[2] == 0);
    if (!degenerate && n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2] < cos_crease) continue;
    parent[find_root(parent, c)] = find_root(parent, next(twin));  // the corners at a
    parent[find_root(parent, next(c))] = find_root(parent, twin);  // the corners at b
  }
  // One output vertex per (vertex, fan), numbered in vertex order; unused vertices are kept.
  Mesh out;
  out.material = m.material;
  out.indices.resize(m.indices.size());
  const bool uv = m.texcoords.size() == 2 * nv;
  std::vector<std::size_t> roots;
  auto add_vertex = [&](std::size_t v) {
    out.positions.insert(out.positions.end(), m.positions.begin() + 3 * v, m.positions.begin() + 3 * v + 3);
    out.normals.insert(out.normals.end(), {0.0f, 0.0f, 0.0f});
    if (uv)
      out.texcoords.insert(out.texcoords.end(), m.texcoords.begin() + 2 * v, m.texcoords.begin() + 2 * v + 2);
  };
  for (std::size_t v = 0; v < nv; ++v) {
    roots.clear();
    const std::size_t base = out.vertex_count();
    for (std::size_t i = first[v]; i < first[v + 1]; ++i) {
      const std::size_t c = corners[i], root = find_root(parent, c);
      const std::size_t g = std::size_t(std::find(roots.begin(), roots.end(), root) - roots.begin());
      if (g == roots.size()) {
        roots.push_back(root);
        add_vertex(v);
      }
      out.indices[c] = std::uint32_t(base + g);
      for (int k = 0; k < 3; ++k)
        out.normals[3 * (base + g) + std::size_t(k)] += area_normal[c / 3][std::size_t(k)];
    }
    if (roots.empty()) add_vertex(v);
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
