#include "acuity/osg/loader.hpp"

#include <stdexcept>

#include <osg/MatrixTransform>
#include <osg/Uniform>

namespace acuity::osg {

::osg::ref_ptr<::osg::Geometry> make_geometry(const lodgen::Mesh& mesh) {
  ::osg::ref_ptr<::osg::Geometry> g = new ::osg::Geometry;
  ::osg::ref_ptr<::osg::Vec3Array> v = new ::osg::Vec3Array(static_cast<unsigned>(mesh.vertex_count()));
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
    (*v)[i].set(mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]);
  g->setVertexArray(v.get());
  g->addPrimitiveSet(new ::osg::DrawElementsUInt(GL_TRIANGLES, mesh.indices.begin(), mesh.indices.end()));
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  return g;
}

SceneNodes make_nodes(const bake::SceneAssets& assets, const std::vector<bake::Instance>& instances,
                      Kit& kit) {
  SceneNodes out;
  out.root = new ::osg::Group;
  out.root->setName("acuity_scene");
  std::vector<std::vector<::osg::ref_ptr<::osg::Geometry>>> levels;
  for (const bake::Asset& a : assets.assets) {
    out.profile_of_asset.push_back(kit.add_profile(a.blob.data(), a.blob.size));
    ::osg::ref_ptr<::osg::StateSet> material = new ::osg::StateSet;
    const float* c = a.material.base_color;
    material->addUniform(new ::osg::Uniform("acuity_color", ::osg::Vec4(c[0], c[1], c[2], c[3])));
    levels.emplace_back();
    for (const lodgen::Level& l : a.chain.levels) {
      levels.back().push_back(make_geometry(l.mesh));
      levels.back().back()->setStateSet(material.get());
    }
  }
  for (const bake::Instance& in : instances) {
    if (in.asset < 0 || std::size_t(in.asset) >= assets.assets.size())
      throw std::runtime_error("acuity::osg: bad asset index in an instance");
    const ObjectTransform& t = in.transform;
    ::osg::ref_ptr<::osg::MatrixTransform> xf = new ::osg::MatrixTransform(
        ::osg::Matrixd::scale(t.scale, t.scale, t.scale) *
        ::osg::Matrixd::rotate(::osg::Quat(t.rotation[0], t.rotation[1], t.rotation[2], t.rotation[3])) *
        ::osg::Matrixd::translate(t.position[0], t.position[1], t.position[2]));
    ::osg::ref_ptr<LodNode> node = new LodNode;
    node->setName(in.name);
    for (const auto& g : levels[std::size_t(in.asset)]) node->addChild(g.get());
    kit.add(node.get(), out.profile_of_asset[std::size_t(in.asset)]);
    xf->addChild(node.get());
    out.root->addChild(xf.get());
    out.nodes.push_back(node);
  }
  return out;
}

LoadedScene load_scene(const std::string& path, const bake::AssetOptions& options, Kit& kit) {
  LoadedScene s;
  s.assets = bake::load_scene_assets(path, options);
  s.nodes = make_nodes(*s.assets, s.assets->instances, kit);
  return s;
}

}  // namespace acuity::osg
