// CGAL: soup repair and edge-collapse decimation (deviation.cpp measures with its AABB tree).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Constrained_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <map>

#include "cgal_bridge.hpp"

namespace acuity::lodgen {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using VertexIndex = SurfaceMesh::Vertex_index;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;

struct Converted {
  SurfaceMesh mesh;
  SurfaceMesh::Property_map<VertexIndex, std::size_t> origin;  // input vertex index
};

// Builds a Surface_mesh; triangles that cannot be added (non-manifold) are skipped.
void to_surface_mesh(const Mesh& in, Converted& out) {
  out.origin = out.mesh.add_property_map<VertexIndex, std::size_t>("v:origin", 0).first;
  std::vector<VertexIndex> v(in.vertex_count());
  for (std::size_t i = 0; i < in.vertex_count(); ++i) {
    v[i] = out.mesh.add_vertex(Point(in.positions[3 * i], in.positions[3 * i + 1], in.positions[3 * i + 2]));
    out.origin[v[i]] = i;
  }
  for (std::size_t t = 0; t < in.indices.size(); t += 3)
    out.mesh.add_face(v[in.indices[t]], v[in.indices[t + 1]], v[in.indices[t + 2]]);
  // Drop vertices no triangle uses.
  for (VertexIndex vi : out.mesh.vertices())
    if (out.mesh.is_isolated(vi)) out.mesh.remove_vertex(vi);
  out.mesh.collect_garbage();
}

Mesh from_surface_mesh(const Converted& c, const Mesh& in) {
  Mesh out;
  out.material = in.material;
  std::map<VertexIndex, std::uint32_t> index;
  for (VertexIndex vi : c.mesh.vertices()) {
    if (c.mesh.is_removed(vi)) continue;
    index[vi] = std::uint32_t(out.vertex_count());
    const Point& p = c.mesh.point(vi);
    out.positions.insert(out.positions.end(), {float(p.x()), float(p.y()), float(p.z())});
    const std::size_t o = c.origin[vi];
    if (!in.texcoords.empty())
      out.texcoords.insert(out.texcoords.end(), {in.texcoords[2 * o], in.texcoords[2 * o + 1]});
  }
  for (auto f : c.mesh.faces()) {
    if (c.mesh.is_removed(f)) continue;
    for (VertexIndex vi : CGAL::vertices_around_face(c.mesh.halfedge(f), c.mesh))
      out.indices.push_back(index.at(vi));
  }
  compute_normals(out);
  return out;
}

struct FaceCountStop {
  std::size_t target;
  const SurfaceMesh* mesh;
  template <class Profile>
  bool operator()(const double&, const Profile&, std::size_t, std::size_t) const {
    return mesh->number_of_faces() <= target;
  }
};

}  // namespace

namespace detail {

bool repair_soup(std::vector<std::array<double, 3>>& points,
                 std::vector<std::array<std::size_t, 3>>& triangles, std::vector<std::size_t>& origin) {
  // Tag each point with its input index through the repair, which may merge and reorder.
  std::vector<Point> pts;
  for (const auto& p : points) pts.emplace_back(p[0], p[1], p[2]);
  std::vector<std::vector<std::size_t>> polys;
  for (const auto& t : triangles) polys.push_back({t[0], t[1], t[2]});
  std::map<Point, std::size_t> first;
  for (std::size_t i = 0; i < pts.size(); ++i) first.emplace(pts[i], i);
  PMP::repair_polygon_soup(pts, polys);
  PMP::orient_polygon_soup(pts, polys);
  if (!PMP::is_polygon_soup_a_polygon_mesh(polys)) return false;
  points.clear();
  origin.clear();
  for (const Point& p : pts) {
    points.push_back({p.x(), p.y(), p.z()});
    auto it = first.find(p);
    origin.push_back(it == first.end() ? 0 : it->second);
  }
  triangles.clear();
  for (const auto& poly : polys)
    if (poly.size() == 3) triangles.push_back({poly[0], poly[1], poly[2]});
  return !triangles.empty();
}

Mesh decimate_cgal(const Mesh& mesh, std::size_t target, bool lindstrom_turk, bool lock_border) {
  Converted c;
  to_surface_mesh(mesh, c);
  auto constrained = c.mesh.add_property_map<SurfaceMesh::Edge_index, bool>("e:constrained", false).first;
  if (lock_border)
    for (auto e : c.mesh.edges()) constrained[e] = c.mesh.is_border(e);
  const FaceCountStop stop{target, &c.mesh};
  if (lindstrom_turk) {
    SMS::Constrained_placement<SMS::LindstromTurk_placement<SurfaceMesh>, decltype(constrained)> placement(
        constrained);
    SMS::edge_collapse(c.mesh, stop,
                       CGAL::parameters::get_cost(SMS::LindstromTurk_cost<SurfaceMesh>())
                           .get_placement(placement)
                           .edge_is_constrained_map(constrained));
  } else {
    using GH = SMS::GarlandHeckbert_plane_policies<SurfaceMesh, K>;
    GH policies(c.mesh);
    SMS::Constrained_placement<GH::Get_placement, decltype(constrained)> placement(constrained,
                                                                                   policies.get_placement());
    SMS::edge_collapse(c.mesh, stop,
                       CGAL::parameters::get_cost(policies.get_cost())
                           .get_placement(placement)
                           .edge_is_constrained_map(constrained));
  }
  c.mesh.collect_garbage();
  return from_surface_mesh(c, mesh);
}

}  // namespace detail

}  // namespace acuity::lodgen
