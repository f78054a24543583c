#pragma once
// acuity/osg/loader.hpp — lodgen's output as OpenSceneGraph nodes: a glTF whose nodes carry MSFT_lod
// chains (or plain meshes, chained on the fly by lodgen exactly as `acuity simulate` does) plus a
// profiles folder (<asset>.acuity, built and saved there when missing) become one LodNode per
// instance under a MatrixTransform, registered with a Kit. The glTF is read by lodgen's reader and
// the chains and profiles come from acuity::bake (acuity/bake/scene.hpp, the code `simulate` uses).
#include <memory>
#include <string>
#include <vector>

#include <osg/Geometry>
#include <osg/Group>

#include "acuity/bake/scene.hpp"
#include "acuity/osg/kit.hpp"

namespace acuity::osg {

struct SceneNodes {
  ::osg::ref_ptr<::osg::Group> root;           // one MatrixTransform -> LodNode per instance
  std::vector<::osg::ref_ptr<LodNode>> nodes;  // [instance]
  std::vector<int> profile_of_asset;           // kit profile index per asset
};

// A triangle mesh as an osg::Geometry (vertex buffer objects, one DrawElementsUInt).
::osg::ref_ptr<::osg::Geometry> make_geometry(const lodgen::Mesh& mesh);

// Nodes for `instances` of the assets (each asset's levels shared by its instances), registered
// with the kit. Throws std::runtime_error when the kit is full.
SceneNodes make_nodes(const bake::SceneAssets& assets, const std::vector<bake::Instance>& instances,
                      Kit& kit);

struct LoadedScene {
  std::unique_ptr<bake::SceneAssets> assets;
  SceneNodes nodes;
};
// Reads the glTF at `path` (see bake::load_scene_assets for the options) and makes its nodes.
LoadedScene load_scene(const std::string& path, const bake::AssetOptions& options, Kit& kit);

}  // namespace acuity::osg
