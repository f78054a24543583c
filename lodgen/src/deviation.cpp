// Bounded two-way deviation between meshes: positions (Hausdorff) and shading normals, on sample
// points matched to their closest point on the other mesh through a CGAL AABB tree.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "acuity/lodgen/decimate.hpp"

namespace acuity::lodgen {
namespace {

using K = CGAL::Simple_cartesian<double>;
using P3 = K::Point_3;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
using Clock = std::chrono::steady_clock;

P3 vertex(const Mesh& m, std::uint32_t v) {
  return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}

// The triangles of `m` with positive area, and for each its triangle index in `m`.
void solid_triangles(const Mesh& m, Triangles& out, std::vector<std::size_t>& index) {
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    K::Triangle_3 tri(vertex(m, m.indices[3 * t]), vertex(m, m.indices[3 * t + 1]),
                      vertex(m, m.indices[3 * t + 2]));
    if (tri.is_degenerate()) continue;
    out.push_back(tri);
    index.push_back(t);
  }
}

// Grid resolution on triangle t for `spacing`: steps along its longest edge and across it.
std::array<std::size_t, 2> grid(const K::Triangle_3& t, double spacing) {
  const double area = std::sqrt(t.squared_area());
  double longest = 0;
  for (int i = 0; i < 3; ++i)
    longest = std::max(longest, std::sqrt(CGAL::squared_distance(t[i], t[(i + 1) % 3])));
  const double height = longest > 0 ? 2 * area / longest : 0;
  const auto steps = [&](double length) { return std::size_t(std::min(1e9, std::ceil(length / spacing))); };
  return {steps(longest), steps(height)};
}

// Every `stride`-th triangle is sampled, so that one sample per triangle fits `budget`.
std::size_t triangle_stride(const Triangles& tris, std::size_t budget) {
  return std::max<std::size_t>(1, (tris.size() + budget - 1) / std::max<std::size_t>(1, budget));
}

std::size_t grid_samples(const Triangles& tris, double spacing, std::size_t stride) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < tris.size(); i += stride) {
    const auto g = grid(tris[i], spacing);
    n += std::max<std::size_t>(1, g[0] * g[1] / 2);
  }
  return n;
}

// Barycentric coordinates of p (on or near triangle t).
std::array<double, 3> barycentric(const K::Triangle_3& t, const P3& p) {
  const K::Vector_3 e0 = t[1] - t[0], e1 = t[2] - t[0], d = p - t[0];
  const double d00 = e0 * e0, d01 = e0 * e1, d11 = e1 * e1, d20 = d * e0, d21 = d * e1;
  const double den = d00 * d11 - d01 * d01;
  if (!(den > 0)) return {1, 0, 0};
  const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  return {1 - v - w, v, w};
}

// Unit shading normal of m's triangle `tri` at barycentric b.
K::Vector_3 shading_normal(const Mesh& m, std::size_t tri, const std::array<double, 3>& b) {
  double n[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) n[k] += b[i] * m.normals[3 * m.indices[3 * tri + i] + k];
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  return len > 0 ? K::Vector_3(n[0] / len, n[1] / len, n[2] / len) : K::Vector_3(0, 0, 0);
}

struct Side {
  double hausdorff = 0;
  std::vector<float> angles;  // degrees, one per face sample when both meshes have normals
  std::size_t samples = 0;
  bool complete = true;
};

// Samples on `from` matched against `to`'s tree.
Side one_side(const Mesh& from, const Triangles& from_tris, const std::vector<std::size_t>& from_index,
              const Mesh& to, const Tree& to_tree, const Triangles& to_tris,
              const std::vector<std::size_t>& to_index, const DeviationOptions& o, double spacing,
              std::size_t face_stride) {
  Side s;
  const bool normals =
      from.normals.size() == from.positions.size() && to.normals.size() == to.positions.size();
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(std::clamp(o.max_seconds, 0.0, 1e6)));
  auto out_of_time = [&] {
    if ((s.samples & 1023) != 0 || Clock::now() < deadline) return false;
    s.complete = false;
    return true;
  };
  // Vertices (strided when there are more than half the budget): positions only, since a vertex on
  // a crease has one normal per side.
  const std::size_t nv = from.vertex_count(), half = std::max<std::size_t>(1, o.max_samples / 2);
  const std::size_t stride = std::max<std::size_t>(1, nv / half + (nv % half != 0));
  P3 last;
  for (std::size_t v = 0; v < nv; v += stride, ++s.samples) {
    if (out_of_time()) return s;
    const P3 p = vertex(from, std::uint32_t(v));
    const P3 q = v ? to_tree.closest_point(p, last) : to_tree.closest_point(p);
    last = q;
    s.hausdorff = std::max(s.hausdorff, std::sqrt(CGAL::squared_distance(p, q)));
  }
  // Face grids: cell centres of a grid along the longest edge and across it, inside the triangle
  // (every face_stride-th triangle when there are more triangles than the budget).
  const auto angle_degrees = [](double cosine) {
    return std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / std::numbers::pi;
  };
  Tree::Point_and_primitive_id hint;
  bool have_hint = false;
  for (std::size_t i = 0; i < from_tris.size(); i += face_stride) {
    const K::Triangle_3& t = from_tris[i];
    int a = 0;  // the longest edge runs from t[a] to t[a+1]
    for (int e = 1; e < 3; ++e)
      if (CGAL::squared_distance(t[e], t[(e + 1) % 3]) > CGAL::squared_distance(t[a], t[(a + 1) % 3])) a = e;
    const auto g = grid(t, spacing);
    const std::size_t nu = std::max<std::size_t>(1, g[0]), nw = std::max<std::size_t>(1, g[1]);
    auto sample = [&](double u, double w) {
      ++s.samples;
      std::array<double, 3> b{};  // barycentric in t's own vertex order
      b[std::size_t(a)] = 1 - u - w;
      b[std::size_t((a + 1) % 3)] = u;
      b[std::size_t((a + 2) % 3)] = w;
      const P3 p = CGAL::barycenter(t[0], b[0], t[1], b[1], t[2], b[2]);
      // The previous answer (a nearby sample's) bounds the search: far fewer tree nodes visited.
      const auto hit =
          have_hint ? to_tree.closest_point_and_primitive(p, hint) : to_tree.closest_point_and_primitive(p);
      hint = hit;
      have_hint = true;
      s.hausdorff = std::max(s.hausdorff, std::sqrt(CGAL::squared_distance(p, hit.first)));
      if (!normals) return;
      const std::size_t to_local = std::size_t(hit.second - to_tris.begin());
      const K::Vector_3 n0 = shading_normal(from, from_index[i], b);
      const K::Vector_3 n1 =
          shading_normal(to, to_index[to_local], barycentric(to_tris[to_local], hit.first));
      s.angles.push_back(float(angle_degrees(n0 * n1)));
    };
    bool inside = false;
    for (std::size_t iu = 0; iu < nu; ++iu) {
      const double u = (double(iu) + 0.5) / double(nu);
      if (u + 0.5 / double(nw) >= 1) break;  // this column and the later ones lie outside
      for (std::size_t iw = 0; iw < nw; ++iw) {
        const double w = (double(iw) + 0.5) / double(nw);
        if (u + w >= 1) break;  // the rest of this column lies outside too
        if (out_of_time()) return s;
        inside = true;
        sample(u, w);
      }
    }
    if (!inside) {  // no cell centre inside: the centroid
      if (out_of_time()) return s;
      sample(1.0 / 3, 1.0 / 3);
    }
  }
  return s;
}

}  // namespace

Deviation deviation(const Mesh& reference, const Mesh& approx, const DeviationOptions& o) {
  Deviation d;
  Triangles ta, tb;
  std::vector<std::size_t> ia, ib;
  solid_triangles(reference, ta, ia);
  solid_triangles(approx, tb, ib);
  if (ta.empty() || tb.empty()) return d;
  // Spacing: relative to the reference's size, widened until both sides' face grids fit the budget.
  double spacing = o.spacing > 0 ? o.spacing : diameter(reference) / 250;
  if (!(spacing > 0) || !std::isfinite(spacing)) spacing = 1;
  const std::size_t face_budget = std::max<std::size_t>(1, o.max_samples / 2);
  const std::size_t stride_a = triangle_stride(ta, face_budget), stride_b = triangle_stride(tb, face_budget);
  for (int i = 0; i < 64; ++i) {
    const std::size_t n = std::max(grid_samples(ta, spacing, stride_a), grid_samples(tb, spacing, stride_b));
    if (n <= face_budget) break;
    spacing *= std::max(1.1, std::sqrt(double(n) / double(face_budget)));
  }
  Tree tree_a(ta.begin(), ta.end()), tree_b(tb.begin(), tb.end());
  tree_a.accelerate_distance_queries();
  tree_b.accelerate_distance_queries();
  Side ab = one_side(reference, ta, ia, approx, tree_b, tb, ib, o, spacing, stride_a);
  Side ba = one_side(approx, tb, ib, reference, tree_a, ta, ia, o, spacing, stride_b);
  d.hausdorff = std::max(ab.hausdorff, ba.hausdorff);
  d.samples = ab.samples + ba.samples;
  d.complete = ab.complete && ba.complete;
  std::vector<float>& angles = ab.angles;
  angles.insert(angles.end(), ba.angles.begin(), ba.angles.end());
  if (!angles.empty()) {
    d.normal_degrees = *std::max_element(angles.begin(), angles.end());
    const auto p99 = angles.begin() + std::ptrdiff_t(double(angles.size() - 1) * 0.99);
    std::nth_element(angles.begin(), p99, angles.end());
    d.normal_p99_degrees = *p99;
  }
  return d;
}

double hausdorff(const Mesh& a, const Mesh& b, double spacing) {
  DeviationOptions o;
  o.spacing = spacing > 0 ? spacing : 1e-12;
  return deviation(a, b, o).hausdorff;
}

}  // namespace acuity::lodgen
