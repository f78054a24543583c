// OpenSubdiv uniform refinement (Loop or Catmull-Clark) of a polygon cage.
#include "acuity/lodgen/refine.hpp"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <cmath>
#include <filesystem>
#include <memory>

#include "acuity/lodgen/decimate.hpp"

namespace acuity::lodgen {
namespace {
struct Point3 {
  float p[3];
  void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const Point3& s, float w) {
    for (int k = 0; k < 3; ++k) p[k] += w * s.p[k];
  }
};
}  // namespace

PolygonMesh load_polygon_mesh(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such file");
  OpenMesh::PolyMesh_ArrayKernelT<> om;
  if (!OpenMesh::IO::read_mesh(om, path))
    throw InputError(path + ": not a readable OFF, OBJ, PLY or STL mesh");
  PolygonMesh out;
  for (auto vh : om.vertices()) {
    const auto& p = om.point(vh);
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k]))
        throw InputError(path + ": vertex " + std::to_string(vh.idx()) + " is not finite");
      out.positions.push_back(p[k]);
    }
  }
  for (auto fh : om.faces()) {
    std::uint32_t n = 0;
    for (auto vh : om.fv_range(fh)) {
      out.indices.push_back(std::uint32_t(vh.idx()));
      ++n;
    }
    out.face_sizes.push_back(n);
  }
  if (out.face_sizes.empty()) throw InputError(path + ": the mesh has no faces");
  return out;
}

PolygonMesh to_polygons(const Mesh& m) {
  PolygonMesh out;
  out.positions = m.positions;
  out.indices = m.indices;
  out.face_sizes.assign(m.triangle_count(), 3);
  return out;
}

Mesh triangulate(const PolygonMesh& p) {
  Mesh out;
  out.positions = p.positions;
  std::size_t at = 0;
  for (std::uint32_t n : p.face_sizes) {
    for (std::uint32_t i = 1; i + 1 < n; ++i)
      out.indices.insert(out.indices.end(), {p.indices[at], p.indices[at + i], p.indices[at + i + 1]});
    at += n;
  }
  compute_normals(out);
  return out;
}

std::vector<Mesh> refine(const PolygonMesh& cage, int levels) {
  using namespace OpenSubdiv;
  bool triangles = true;
  for (std::uint32_t n : cage.face_sizes) triangles &= n == 3;
  std::vector<int> sizes(cage.face_sizes.begin(), cage.face_sizes.end());
  std::vector<int> indices(cage.indices.begin(), cage.indices.end());
  Far::TopologyDescriptor desc;
  desc.numVertices = int(cage.positions.size() / 3);
  desc.numFaces = int(sizes.size());
  desc.numVertsPerFace = sizes.data();
  desc.vertIndicesPerFace = indices.data();
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(triangles ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, sdc)));
  if (!refiner) throw InputError("refine: OpenSubdiv rejected the cage's topology");
  refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
  std::vector<Point3> verts(std::size_t(refiner->GetNumVerticesTotal()));
  for (std::size_t i = 0; i < cage.positions.size() / 3; ++i)
    for (int k = 0; k < 3; ++k) verts[i].p[k] = cage.positions[3 * i + k];
  Far::PrimvarRefiner primvar(*refiner);
  std::vector<std::size_t> first = {0};
  for (int l = 1; l <= levels; ++l) {
    first.push_back(first.back() + std::size_t(refiner->GetLevel(l - 1).GetNumVertices()));
    Point3* src = &verts[first[l - 1]];
    Point3* dst = &verts[first[l]];
    primvar.Interpolate(l, src, dst);
  }
  std::vector<Mesh> out;
  for (int l = levels; l >= 0; --l) {
    const Far::TopologyLevel& level = refiner->GetLevel(l);
    PolygonMesh p;
    for (int v = 0; v < level.GetNumVertices(); ++v)
      for (int k = 0; k < 3; ++k) p.positions.push_back(verts[first[l] + std::size_t(v)].p[k]);
    for (int f = 0; f < level.GetNumFaces(); ++f) {
      const Far::ConstIndexArray fv = level.GetFaceVertices(f);
      p.face_sizes.push_back(std::uint32_t(fv.size()));
      for (int i = 0; i < fv.size(); ++i) p.indices.push_back(std::uint32_t(fv[i]));
    }
    out.push_back(triangulate(p));
  }
  return out;
}

}  // namespace acuity::lodgen
