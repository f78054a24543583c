// OpenMesh Decimater: quadric error with normal-flip and aspect-ratio guards.
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "cgal_bridge.hpp"

namespace acuity::lodgen::detail {

Mesh decimate_openmesh(const Mesh& in, std::size_t target, bool lock_border) {
  using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;
  OmMesh om;
  om.request_vertex_status();
  om.request_edge_status();
  om.request_face_status();
  om.request_face_normals();
  const bool uv = !in.texcoords.empty();
  if (uv) om.request_vertex_texcoords2D();
  std::vector<OmMesh::VertexHandle> v(in.vertex_count());
  for (std::size_t i = 0; i < v.size(); ++i) {
    v[i] =
        om.add_vertex(OmMesh::Point(in.positions[3 * i], in.positions[3 * i + 1], in.positions[3 * i + 2]));
    if (uv) om.set_texcoord2D(v[i], OmMesh::TexCoord2D(in.texcoords[2 * i], in.texcoords[2 * i + 1]));
  }
  for (std::size_t t = 0; t < in.indices.size(); t += 3)
    om.add_face(v[in.indices[t]], v[in.indices[t + 1]],
                v[in.indices[t + 2]]);  // non-manifold ones are refused
  om.update_face_normals();
  if (lock_border)
    for (auto vh : om.vertices())
      if (om.is_boundary(vh)) om.status(vh).set_locked(true);

  OpenMesh::Decimater::DecimaterT<OmMesh> decimater(om);
  OpenMesh::Decimater::ModQuadricT<OmMesh>::Handle quadric;
  OpenMesh::Decimater::ModNormalFlippingT<OmMesh>::Handle flips;
  OpenMesh::Decimater::ModAspectRatioT<OmMesh>::Handle aspect;
  decimater.add(quadric);
  decimater.add(flips);
  decimater.add(aspect);
  decimater.module(quadric).unset_max_err();
  decimater.module(flips).set_max_normal_deviation(60.0);
  decimater.module(aspect).set_aspect_ratio(10.0);
  decimater.initialize();
  decimater.decimate_to_faces(0, target);
  om.garbage_collection();

  Mesh out;
  out.material = in.material;
  for (auto vh : om.vertices()) {
    const auto& p = om.point(vh);
    out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
    if (uv) {
      const auto& t = om.texcoord2D(vh);
      out.texcoords.insert(out.texcoords.end(), {t[0], t[1]});
    }
  }
  for (auto fh : om.faces())
    for (auto vh : om.fv_range(fh)) out.indices.push_back(static_cast<std::uint32_t>(vh.idx()));
  compute_normals(out);
  return out;
}

}  // namespace acuity::lodgen::detail
