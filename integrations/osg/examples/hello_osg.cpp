// hello_osg.cpp — acuity in an OpenSceneGraph application: 100 copies of one object whose levels
// (finest first) come from `acuity lodgen`, with its profile from `acuity profile`; the mouse is the
// gaze. docs/integrations.md shows this file. Usage: hello_osg PROFILE.acuity CHAIN.glb [--frames N]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <osg/MatrixTransform>
#include <osgViewer/Viewer>

#include "acuity/osg/gaze.hpp"
#include "acuity/osg/kit.hpp"
#include "acuity/osg/loader.hpp"  // make_geometry

int main(int argc, char** argv) {
  int frames = argc > 3 && !std::strcmp(argv[argc - 2], "--frames") ? std::atoi(argv[argc - 1]) : 0;
  if (argc < 3) return std::fprintf(stderr, "usage: hello_osg PROFILE.acuity CHAIN.glb [--frames N]\n"), 2;
  acuity::SchedulerConfig config;
  config.max_objects = 100;
  config.transition_seconds = 0.25f;  // cross-fade each level change over 0.25 s
  osg::ref_ptr<acuity::osg::Kit> kit = new acuity::osg::Kit(config);
  acuity::Blob profile;
  std::string error;
  if (!acuity::read_file(argv[1], &profile, &error)) return std::fprintf(stderr, "%s\n", error.c_str()), 1;
  const int p = kit->add_profile(profile.data(), profile.size);  // validated and copied; throws if bad

  std::vector<osg::ref_ptr<osg::Geometry>>
      levels;  // your engine's meshes; here lodgen's chain, shared by every copy
  const acuity::lodgen::Scene chain =
      acuity::lodgen::load_scene(argv[2]);  // level 0's node lists the others (MSFT_lod)
  for (const acuity::lodgen::Node& n : chain.nodes)
    if (!n.lods.empty() && levels.empty()) {
      levels.push_back(acuity::osg::make_geometry(chain.meshes.at(std::size_t(n.mesh))));
      for (int l : n.lods)
        levels.push_back(
            acuity::osg::make_geometry(chain.meshes.at(std::size_t(chain.nodes.at(std::size_t(l)).mesh))));
    }
  osg::ref_ptr<osg::Group> root = new osg::Group;
  root->setStateSet(acuity::osg::make_shader_state());  // headlight + screen-door cross-fade
  for (int i = 0; i < 100; ++i) {
    osg::ref_ptr<acuity::osg::LodNode> node = new acuity::osg::LodNode;
    for (auto& level : levels) node->addChild(level.get());
    kit->add(node.get(), p);                             // now an acuity object
    if (i % 10 == 0) kit->set_clamps(node.get(), 0, 1);  // e.g. hero objects: never coarser than level 1
    osg::ref_ptr<osg::MatrixTransform> xf =
        new osg::MatrixTransform(osg::Matrix::translate(3.0 * (i % 10 - 4.5), 0, -3.0 * (i / 10)));
    xf->addChild(node.get());
    root->addChild(xf.get());
  }

  osgViewer::Viewer viewer;
  viewer.setSceneData(root.get());
  osg::ref_ptr<acuity::osg::MouseGaze> gaze = new acuity::osg::MouseGaze;  // or TrackGaze, or your tracker's
  viewer.addEventHandler(gaze->handler());
  kit->set_gaze_source(gaze.get());
  viewer.setUpViewInWindow(50, 50, 800, 600);
  viewer.realize();
  kit->attach(viewer);  // the cameras are the eyes (two slave cameras: stereo)
  if (!frames) return viewer.run();
  for (int f = 0; f < frames && !viewer.done(); ++f) viewer.frame();
  std::printf("frame %u: %llu triangles, acuity %.3f ms\n", kit->frame_number(),
              static_cast<unsigned long long>(kit->scheduler().stats().triangles), kit->last_acuity_ms());
  return 0;
}
