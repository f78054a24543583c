#pragma once
// acuity/osg/shadow_map.hpp — osgShadow's ShadowMap with its light camera in reach, for
// Kit::set_view_cameras (the camera is a protected member there). Header-only; a program that
// includes it links osgShadow (the kit itself does not).
//
//   osg::ref_ptr<osgShadow::ShadowedScene> scene = new osgShadow::ShadowedScene;
//   osg::ref_ptr<acuity::osg::ShadowMap> shadow = new acuity::osg::ShadowMap;
//   scene->setShadowTechnique(shadow.get());                  // before camera()
//   kit->set_view_cameras({{shadow->camera(), settings}});    // settings.view_class, rule, pixel_error
#include <osgShadow/ShadowMap>
#include <osgShadow/ShadowedScene>

namespace acuity::osg {

class ShadowMap : public osgShadow::ShadowMap {
 public:
  // The light's camera (osgShadow places it in each frame's cull: orthographic for a directional
  // light, perspective for a spot light; its viewport is the map's size). Creates it on first use;
  // nullptr before the technique is given to a ShadowedScene.
  ::osg::Camera* camera() {
    if (!_camera.valid()) init();
    return _camera.get();
  }
};

}  // namespace acuity::osg
