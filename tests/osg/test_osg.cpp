// acuity::osg rendered for real (a pbuffer under xvfb-run, Mesa llvmpipe): for every frame of a
// recorded head path the level each LodNode draws is the level an independent acuity::Scheduler
// chooses from the same eyes and transforms; a CutNode draws the cluster cut an independent
// select_cut chooses, which follows the gaze; the camera-to-eye conversion matches the analytic eye;
// two slave cameras give two eyes; the fade goes 0 -> 1 over transition_seconds with both levels
// drawn meanwhile, and the dithered screen door covers the fade's share of the pixels; a PNG of a
// frame is written and is not blank.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include <osg/LightSource>
#include <osg/MatrixTransform>
#include <osg/Uniform>
#include <osgViewer/Viewer>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/clusters.hpp"
#include "acuity/osg/cut_node.hpp"
#include "acuity/osg/gaze.hpp"
#include "acuity/osg/kit.hpp"
#include "acuity/osg/loader.hpp"
#include "acuity/osg/shadow_map.hpp"
#include "acuity/sim/foveation_report.hpp"  // gazes_from
#include "acuity/sim/frame_image.hpp"
#include "acuity/sim/tracks.hpp"
#include "acuity/transform.hpp"
#include "profile_fixture.hpp"

namespace {

constexpr double kDeg = 57.295779513082320876;
constexpr int kWidth = 320, kHeight = 240;
constexpr double kFovY = 60, kFps = 60;

using acuity::osg::Kit;
using acuity::osg::LodNode;

// Reads the colour buffer after the draw, before the swap.
struct Capture : ::osg::Camera::DrawCallback {
  ::osg::ref_ptr<::osg::Image> image = new ::osg::Image;
  void operator()(::osg::RenderInfo&) const override {
    image->readPixels(0, 0, kWidth, kHeight, GL_RGB, GL_UNSIGNED_BYTE);
  }
};

// A quad of side 2 facing +Z (so it faces a camera looking down -Z), as a lodgen mesh.
acuity::lodgen::Mesh quad(float h = 1) {
  acuity::lodgen::Mesh m;
  m.positions = {-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

struct World {
  acuity::Blob blob = acuity::spectra::encode_profile(acuity::testing::small_profile(4));
  acuity::Profile profile{};
  acuity::SchedulerConfig config;
  ::osg::ref_ptr<Kit> kit;
  ::osg::ref_ptr<::osg::Group> root = new ::osg::Group;
  std::vector<::osg::ref_ptr<::osg::MatrixTransform>> transforms;
  std::vector<::osg::ref_ptr<LodNode>> nodes;
  osgViewer::Viewer viewer;
  ::osg::ref_ptr<Capture> capture = new Capture;
  ::osg::ref_ptr<::osg::Uniform> debug = new ::osg::Uniform("acuity_debug", 1.0f);

  World(std::uint32_t objects, float transition_seconds, bool stereo, float quad_half_size = 1,
        bool deferred = false) {
    EXPECT_EQ(acuity::open_profile(blob.data(), blob.size, &profile), acuity::ProfileStatus::Ok);
    config.max_objects = objects;
    config.transition_seconds = transition_seconds;
    kit = new Kit(config);
    const int p = kit->add_profile(blob.data(), blob.size, deferred);
    std::vector<::osg::ref_ptr<::osg::Geometry>> levels;
    for (int k = 0; k < 4; ++k) levels.push_back(acuity::osg::make_geometry(quad(quad_half_size)));
    for (std::uint32_t i = 0; i < objects; ++i) {
      transforms.push_back(new ::osg::MatrixTransform(matrix(i, 0)));
      nodes.push_back(new LodNode);
      for (auto& g : levels) nodes.back()->addChild(g.get());
      kit->add(nodes.back().get(), p);
      transforms.back()->addChild(nodes.back().get());
      root->addChild(transforms.back().get());
    }
    ::osg::ref_ptr<::osg::StateSet> ss = acuity::osg::make_shader_state();
    ss->addUniform(debug.get(), ::osg::StateAttribute::OVERRIDE);
    root->setStateSet(ss.get());
    realize(viewer, root.get(), capture.get(), stereo);
    kit->attach(viewer);
  }

  // A single-threaded viewer of `root` in a kWidth x kHeight pbuffer, its master camera at kFovY
  // (or two slaves side by side, eyes 64 mm apart), `capture` reading the frame (not stereo).
  static void realize(osgViewer::Viewer& viewer, ::osg::Node* root, Capture* capture, bool stereo) {
    ::osg::ref_ptr<::osg::GraphicsContext::Traits> traits = new ::osg::GraphicsContext::Traits;
    traits->readDISPLAY();  // xvfb-run's $DISPLAY
    traits->setUndefinedScreenDetailsToDefaultScreen();
    traits->width = kWidth;
    traits->height = kHeight;
    traits->pbuffer = true;
    traits->doubleBuffer = true;
    traits->red = traits->green = traits->blue = 8;
    traits->depth = 24;
    ::osg::ref_ptr<::osg::GraphicsContext> gc = ::osg::GraphicsContext::createGraphicsContext(traits.get());
    if (!gc) throw std::runtime_error("no pbuffer: is this running under xvfb-run with GLX?");
    viewer.setThreadingModel(osgViewer::ViewerBase::SingleThreaded);
    viewer.setSceneData(root);
    viewer.setCameraManipulator(nullptr);
    ::osg::Camera* master = viewer.getCamera();
    master->setProjectionMatrixAsPerspective(kFovY, double(kWidth) / kHeight, 0.1, 1000);
    master->setClearColor(::osg::Vec4(0, 0, 0, 1));
    if (!stereo) {
      master->setGraphicsContext(gc.get());
      master->setViewport(0, 0, kWidth, kHeight);
      master->setDrawBuffer(GL_BACK);
      master->setReadBuffer(GL_BACK);
      master->setFinalDrawCallback(capture);
    } else {  // two slaves side by side, eyes 64 mm apart; each keeps the master's projection
      for (int e = 0; e < 2; ++e) {
        ::osg::ref_ptr<::osg::Camera> cam = new ::osg::Camera;
        cam->setGraphicsContext(gc.get());
        cam->setViewport(e * kWidth / 2, 0, kWidth / 2, kHeight);
        cam->setDrawBuffer(GL_BACK);
        cam->setReadBuffer(GL_BACK);
        cam->setClearColor(::osg::Vec4(0, 0, 0, 1));
        viewer.addSlave(cam.get(), ::osg::Matrixd(), ::osg::Matrixd::translate(e ? -0.032 : 0.032, 0, 0));
      }
    }
    viewer.realize();
    if (!viewer.isRealized()) throw std::runtime_error("the viewer could not be realized");
  }

  // Objects in two rows in front of the head's start, 2 m apart in depth; object 0 moves sideways.
  static ::osg::Vec3d position(std::uint32_t i, double t) {
    return {(i % 2 ? 1.5 : -1.5) + (i == 0 ? 0.5 * std::sin(t) : 0.0), 0.0, -4.0 - 2.0 * (i / 2)};
  }
  static constexpr double kScale = 0.25;  // the profile's 1.5 m sphere becomes 0.375 m
  static ::osg::Matrixd matrix(std::uint32_t i, double t) {
    return ::osg::Matrixd::scale(kScale, kScale, kScale) * ::osg::Matrixd::translate(position(i, t));
  }
  acuity::ObjectTransform transform(std::uint32_t i, double t) const {
    acuity::ObjectTransform o;
    o.scale = float(kScale);
    const ::osg::Vec3d p = position(i, t);
    for (int k = 0; k < 3; ++k) o.position[k] = p[k];
    return o;
  }
  void place(double t) {
    for (std::uint32_t i = 0; i < transforms.size(); ++i) transforms[i]->setMatrix(matrix(i, t));
  }
};

// The recorded head path: backing away along +Z from z = 2 at 10 m/s with a slow yaw sway.
struct Head {
  ::osg::Vec3d position;
  ::osg::Quat orientation;
};
Head head_at(double t) {
  return {::osg::Vec3d(0.2 * std::sin(t), 1.0, 2.0 + 10.0 * t),
          ::osg::Quat(0.15 * std::sin(1.3 * t), ::osg::Vec3d(0, 1, 0))};
}
::osg::Matrixd view_of(const Head& h) {
  return ::osg::Matrixd::inverse(::osg::Matrixd::rotate(h.orientation) *
                                 ::osg::Matrixd::translate(h.position));
}

TEST(Osg, DitherIsAnOrderedEightByEightMatrix) {
  std::set<float> seen;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const float t = acuity::osg::dither_threshold(x, y);
      EXPECT_EQ(t, acuity::osg::dither_threshold(x + 8, y + 16));
      EXPECT_EQ(t * 64, std::floor(t * 64));
      seen.insert(t);
    }
  EXPECT_EQ(seen.size(), 64u);
  EXPECT_EQ(acuity::osg::dither_threshold(0, 0), 0.0f);
  EXPECT_EQ(acuity::osg::dither_threshold(1, 1), 16.0f / 64);  // Bayer [[0, 2], [3, 1]] / 4
  EXPECT_EQ(Kit::quantise_fade(0.999f), 63.0f / 64);
  EXPECT_EQ(Kit::quantise_fade(1.0f), 1.0f);
  EXPECT_EQ(Kit::quantise_fade(std::nanf("")), 1.0f);  // no fade: the level alone
}

// Head and gaze tracks recorded at 30 Hz in the CSV format `acuity simulate` reads.
std::string head_csv() {
  std::string s = "t,x,y,z,qx,qy,qz,qw\n";
  for (int i = 0; i <= 45; ++i) {
    const double t = i / 30.0;
    const Head h = head_at(t);
    char line[256];
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", t, h.position.x(),
                  h.position.y(), h.position.z(), h.orientation.x(), h.orientation.y(), h.orientation.z(),
                  h.orientation.w());
    s += line;
  }
  return s;
}
std::string gaze_csv() {  // a sideways sweep with a blink (confidence 0) from 0.5 s to 0.6 s
  std::string s = "t,x,y,z,confidence\n";
  for (int i = 0; i <= 45; ++i) {
    const double t = i / 30.0;
    char line[160];
    std::snprintf(line, sizeof line, "%.17g,%.17g,0,-1,%d\n", t, 0.3 * std::sin(2 * t),
                  t >= 0.5 && t <= 0.6 ? 0 : 1);
    s += line;
  }
  return s;
}

TEST(Osg, DrawnLevelsAreTheSchedulersForARecordedPath) {
  World w(12, 0.0f, false);
  const int frames = 90;
  const auto head =
      acuity::sim::head_path_from(acuity::sim::parse_table(head_csv(), "head.csv", false), kFps, frames);
  const auto samples =
      acuity::sim::gaze_trace_from(acuity::sim::parse_table(gaze_csv(), "gaze.csv", false), kFps, frames);
  ASSERT_EQ(head.size(), std::size_t(frames));
  w.kit->set_gaze_source(
      new acuity::osg::TrackGaze(acuity::sim::gazes_from(samples)));  // sample 0 at the first frame
  acuity::Scheduler ref(w.config);
  ASSERT_EQ(ref.add_profile(w.profile), 0);
  for (std::uint32_t i = 0; i < 12; ++i) ASSERT_EQ(ref.add_object(0, w.transform(i, 0)), w.nodes[i]->id());
  std::set<int> levels_seen;
  int changes = 0, blinks = 0;
  for (int f = 0; f < frames; ++f) {
    const double t = f / kFps;
    const Head h{::osg::Vec3d(head[f].position.x, head[f].position.y, head[f].position.z),
                 ::osg::Quat(head[f].orientation.x, head[f].orientation.y, head[f].orientation.z,
                             head[f].orientation.w)};
    w.viewer.getCamera()->setViewMatrix(view_of(h));
    w.place(t);
    w.viewer.frame(t);
    // The gaze is the track's sample for this frame.
    const acuity::Gaze& g = w.kit->frame().gaze[0];
    EXPECT_EQ(g.valid, samples[f].confidence > 0);
    blinks += !g.valid;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(g.direction[k], float(samples[f].direction[k]));
    // The eye the kit read from the camera is the analytic one.
    const acuity::Frame& fr = w.kit->frame();
    ASSERT_EQ(fr.eye_count, 1u);
    const acuity::Eye& e = fr.eyes[0];
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(e.position[k], h.position[k], 1e-9);
    const double sign = e.orientation[3] * h.orientation.w() < 0 ? -1 : 1;
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(sign * e.orientation[k], h.orientation[k], 1e-6);
    const double top = std::atan(std::tan(0.5 * kFovY / kDeg)) * kDeg;
    const double right = std::atan(std::tan(0.5 * kFovY / kDeg) * kWidth / kHeight) * kDeg;
    EXPECT_NEAR(e.fov_deg[0], -right, 1e-4);
    EXPECT_NEAR(e.fov_deg[1], right, 1e-4);
    EXPECT_NEAR(e.fov_deg[2], top, 1e-4);
    EXPECT_NEAR(e.fov_deg[3], -top, 1e-4);
    EXPECT_EQ(e.viewport[0], std::uint32_t(kWidth));
    EXPECT_EQ(e.viewport[1], std::uint32_t(kHeight));
    if (f > 0) { EXPECT_NEAR(e.velocity[2], 10.0, 1e-3); }
    EXPECT_FLOAT_EQ(fr.dt, f ? float(1 / kFps) : 0.0f);
    // An independent scheduler given the same eye and the analytic transforms.
    for (std::uint32_t i = 0; i < 12; ++i) ref.set_transform(w.nodes[i]->id(), w.transform(i, t));
    ref.run_frame(fr);
    for (std::uint32_t i = 0; i < 12; ++i) {
      const LodNode::Drawn d = w.nodes[i]->drawn();
      const acuity::ObjectId id = w.nodes[i]->id();
      ASSERT_EQ(d.frame, w.viewer.getFrameStamp()->getFrameNumber())
          << "object " << i << " was not culled in frame " << f;
      EXPECT_EQ(d.level, ref.level(id)) << "frame " << f << " object " << i;
      EXPECT_FALSE(d.both);
      levels_seen.insert(d.level);
      changes += (ref.flags(id) & acuity::kFlagChanged) != 0;
    }
  }
  EXPECT_GE(levels_seen.size(), 3u) << "the walk should cross several levels";
  EXPECT_GE(blinks, 5) << "the blink in the track reaches the scheduler as no gaze";
  EXPECT_GT(changes, 0);
  EXPECT_GT(w.kit->last_acuity_ms(), 0.0);
}

// A deferred profile: its objects decide exactly (as a scheduler evaluating exactly, given the same
// frames) until make_wanted_tables() makes the views they were seen from, one at the first call;
// then, once settled (a still head), as a scheduler with every table, while the kit holds only
// those views' tables; drop_idle_tables frees them.
TEST(Osg, ADeferredProfileGetsTheTablesOfTheViewsItsObjectsAreSeenFrom) {
  World w(12, 0.0f, false, 1, true);
  acuity::SchedulerConfig exact_config = w.config;
  exact_config.evaluation = acuity::Evaluation::Exact;
  acuity::Scheduler exact(exact_config), built(w.config);
  for (acuity::Scheduler* s : {&exact, &built}) {
    ASSERT_EQ(s->add_profile(w.profile), 0);
    for (std::uint32_t i = 0; i < 12; ++i) ASSERT_EQ(s->add_object(0, w.transform(i, 0)), w.nodes[i]->id());
  }
  w.viewer.getCamera()->setViewMatrix(view_of(head_at(0)));
  const int frames = 80, made_at = 10;
  for (int f = 0; f < frames; ++f) {
    w.viewer.frame(f / kFps);
    exact.run_frame(w.kit->frame());
    built.run_frame(w.kit->frame());
    for (std::uint32_t i = 0; i < 12; ++i) {
      const acuity::ObjectId id = w.nodes[i]->id();
      if (f < made_at) {
        EXPECT_EQ(w.nodes[i]->drawn().level, exact.level(id)) << "frame " << f << " object " << i;
      }
      if (f == frames - 1) { EXPECT_EQ(w.nodes[i]->drawn().level, built.level(id)) << "object " << i; }
    }
    if (f == made_at - 1) {
      EXPECT_EQ(w.kit->scheduler().table_bytes(0), 0u);
      EXPECT_EQ(w.kit->make_wanted_tables(1), 1u);
      while (w.kit->make_wanted_tables(4) > 0) {}
      EXPECT_GT(w.kit->scheduler().table_bytes(0), 0u);
      EXPECT_LT(w.kit->scheduler().table_bytes(0), built.table_bytes(0)) << "only the views seen";
    }
  }
  EXPECT_EQ(w.kit->make_wanted_tables(4), 0u);
  // Dropped: kept while read lately; with 0 every view goes, and the settled objects' remembered
  // decisions (made from those tables) still stand.
  const std::size_t held = w.kit->scheduler().table_bytes(0);
  EXPECT_EQ(w.kit->drop_idle_tables(1000), 0u);
  EXPECT_EQ(w.kit->drop_idle_tables(0), held);
  EXPECT_EQ(w.kit->scheduler().table_bytes(0), 0u);
  w.viewer.frame(frames / kFps);
  built.run_frame(w.kit->frame());
  for (std::uint32_t i = 0; i < 12; ++i)
    EXPECT_EQ(w.nodes[i]->drawn().level, built.level(w.nodes[i]->id())) << "object " << i;
}

TEST(Osg, TwoSlaveCamerasAreTwoEyes) {
  World w(8, 0.0f, true);
  acuity::Scheduler ref(w.config);
  ASSERT_EQ(ref.add_profile(w.profile), 0);
  for (std::uint32_t i = 0; i < 8; ++i) ASSERT_EQ(ref.add_object(0, w.transform(i, 0)), w.nodes[i]->id());
  std::set<int> levels_seen;
  for (int f = 0; f < 40; ++f) {
    const double t = f / kFps;
    const Head h = head_at(t);
    w.viewer.getCamera()->setViewMatrix(view_of(h));
    w.place(t);
    w.viewer.frame(t);
    const acuity::Frame& fr = w.kit->frame();
    ASSERT_EQ(fr.eye_count, 2u);
    for (int e = 0; e < 2; ++e) {  // each eye 32 mm along the head's x axis
      const ::osg::Vec3d expect = h.position + h.orientation * ::osg::Vec3d(e ? 0.032 : -0.032, 0, 0);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(fr.eyes[e].position[k], expect[k], 1e-9) << "eye " << e;
      EXPECT_EQ(fr.eyes[e].viewport[0], std::uint32_t(kWidth / 2));
    }
    for (std::uint32_t i = 0; i < 8; ++i) ref.set_transform(w.nodes[i]->id(), w.transform(i, t));
    ref.run_frame(fr);
    for (std::uint32_t i = 0; i < 8; ++i) {
      const LodNode::Drawn d = w.nodes[i]->drawn();
      EXPECT_EQ(d.level, ref.level(w.nodes[i]->id())) << "frame " << f << " object " << i;
      EXPECT_EQ(d.culls, 2u) << "both eye cameras drew object " << i;
      levels_seen.insert(d.level);
    }
  }
  EXPECT_GE(levels_seen.size(), 2u);
}

// Counts pixels close to a colour (the quad faces the camera, so the headlight factor is 1).
int count_color(const ::osg::Image& im, const ::osg::Vec4& c) {
  int n = 0;
  for (int y = 0; y < im.t(); ++y)
    for (int x = 0; x < im.s(); ++x) {
      const unsigned char* p = im.data(x, y);
      if (std::abs(p[0] - 255 * c.r()) < 6 && std::abs(p[1] - 255 * c.g()) < 6 &&
          std::abs(p[2] - 255 * c.b()) < 6)
        ++n;
    }
  return n;
}

TEST(Osg, CrossFadeRisesOverTransitionSecondsAndSplitsThePixels) {
  const float T = 0.5f;
  World w(1, T, false);
  // One quad 3 m ahead, filling a good part of the view; then the head steps back to 60 m.
  const int switch_frame = 5;
  int changed_at = -1;
  float last = -1;
  for (int f = 0; f < switch_frame + int(T * kFps) + 5; ++f) {
    const double t = f / kFps;
    const double z = f < switch_frame ? -1.0 : 56.0;
    w.transforms[0]->setMatrix(::osg::Matrixd::translate(0, 0, -4));
    w.viewer.getCamera()->setViewMatrix(::osg::Matrixd::translate(0, 0, -z));
    w.viewer.frame(t);
    const LodNode::Drawn d = w.nodes[0]->drawn();
    const acuity::Scheduler& s = w.kit->scheduler();
    if (changed_at < 0 && (s.flags(w.nodes[0]->id()) & acuity::kFlagChanged)) {
      changed_at = f;
      EXPECT_GT(d.level, d.previous);
    }
    if (changed_at < 0) {
      EXPECT_EQ(d.fade, 1.0f);
      continue;
    }
    const float expect = std::min(1.0f, float(f - changed_at) / float(T * kFps));
    EXPECT_NEAR(d.fade, expect, 1.0f / 64 + 1e-6f) << "frame " << f;
    EXPECT_EQ(d.fade, Kit::quantise_fade(s.transition(w.nodes[0]->id())));
    EXPECT_GE(d.fade, last);
    EXPECT_EQ(d.both, expect < 1.0f);
    // The uniform the node pushed carries that fade.
    float uniform = -1;
    w.kit->fade_state(d.fade, false)->getUniform("acuity_fade")->get(uniform);
    EXPECT_EQ(uniform, d.fade);
    last = d.fade;
  }
  ASSERT_GE(changed_at, switch_frame) << "stepping back must coarsen the quad";
  EXPECT_EQ(last, 1.0f);

  // The screen door: with the quad close (filling the view) and a fade in progress, the incoming
  // level's colour covers the fade's share of the pixels, the outgoing level's the rest.
  // The levels' geometry is a quad much larger than the profile's sphere, so it fills the view from afar.
  World v(1, 10.0f, false, 2000.0f);
  v.transforms[0]->setMatrix(::osg::Matrixd::translate(0, 0, -4));
  v.viewer.getCamera()->setViewMatrix(::osg::Matrixd::translate(0, 0, -1.0));
  v.viewer.frame(0);
  v.viewer.getCamera()->setViewMatrix(::osg::Matrixd::translate(0, 0, -400.0));
  int f = 1;
  for (; f < 200; ++f) {
    v.viewer.frame(f / kFps);
    if (v.nodes[0]->drawn().both && v.nodes[0]->drawn().fade >= 0.25f) break;
  }
  const LodNode::Drawn d = v.nodes[0]->drawn();
  ASSERT_TRUE(d.both) << "no fade in progress";
  const int in = count_color(*v.capture->image, acuity::osg::level_color(d.level));
  const int out = count_color(*v.capture->image, acuity::osg::level_color(d.previous));
  ASSERT_GT(in + out, kWidth * kHeight / 2) << "the quad should fill the view";
  EXPECT_NEAR(double(in) / (in + out), d.fade, 0.02) << in << " incoming, " << out << " outgoing pixels";
}

// A LodNode outside any kit draws its finest level only (never every level on top of each other).
TEST(Osg, ANodeWithoutAKitDrawsItsFinestLevel) {
  World w(1, 0.0f, false, 3.0f);
  ::osg::ref_ptr<LodNode> loose = new LodNode;
  ::osg::ref_ptr<::osg::Geometry> a = acuity::osg::make_geometry(quad(1)),
                                  b = acuity::osg::make_geometry(quad(2));
  loose->addChild(a.get());
  loose->addChild(b.get());
  EXPECT_EQ(loose->id(), acuity::kInvalidObject);
  struct Count : ::osg::NodeVisitor {
    int drawables = 0;
    Count() : ::osg::NodeVisitor(TRAVERSE_ACTIVE_CHILDREN) {}
    void apply(::osg::Drawable&) override { ++drawables; }
  } active;
  loose->accept(active);
  EXPECT_EQ(active.drawables, 1);
  struct CountAll : ::osg::NodeVisitor {
    int drawables = 0;
    CountAll() : ::osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
    void apply(::osg::Drawable&) override { ++drawables; }
  } all;
  loose->accept(all);
  EXPECT_EQ(all.drawables, 2);
  // A static node keeps the transform read on its first frame until marked moved.
  w.kit->set_static(w.nodes[0].get(), true);
  w.viewer.getCamera()->setViewMatrix(::osg::Matrixd::translate(0, 0, -3));
  w.viewer.frame(0);
  acuity::ObjectExplain first;
  ASSERT_TRUE(w.kit->scheduler().explain(w.nodes[0]->id(), &first));
  w.transforms[0]->setMatrix(World::matrix(0, 0) * ::osg::Matrixd::translate(0, 0, -40));
  w.viewer.frame(1 / kFps);
  acuity::ObjectExplain before;
  ASSERT_TRUE(w.kit->scheduler().explain(w.nodes[0]->id(), &before));
  EXPECT_EQ(before.distance_m, first.distance_m) << "a static node's move is not read";
  w.kit->mark_moved(w.nodes[0].get());
  w.viewer.frame(2 / kFps);
  acuity::ObjectExplain after;
  ASSERT_TRUE(w.kit->scheduler().explain(w.nodes[0]->id(), &after));
  EXPECT_NEAR(after.distance_m, before.distance_m + 40, 0.5) << "the move is seen after mark_moved";
  // The kit is full (one object): removing the world's node frees its slot for this one.
  EXPECT_THROW(w.kit->add(loose.get(), 0), std::runtime_error);
  w.kit->remove(w.nodes[0].get());
  EXPECT_EQ(w.nodes[0]->id(), acuity::kInvalidObject);
  w.kit->add(loose.get(), 0);
  EXPECT_NE(loose->id(), acuity::kInvalidObject);
  EXPECT_THROW(w.kit->add(loose.get(), 0), std::runtime_error);
  w.kit->remove(loose.get());
  EXPECT_EQ(loose->id(), acuity::kInvalidObject);
}

TEST(Osg, APngOfAFrameIsWrittenAndIsNotBlank) {
  World w(12, 0.0f, false, 3.0f);
  w.viewer.getCamera()->setViewMatrix(view_of(head_at(0)));
  w.viewer.frame(0);
  const ::osg::Image& im = *w.capture->image;
  ASSERT_EQ(im.s(), kWidth);
  acuity::sim::RgbImage out;
  out.width = im.s();
  out.height = im.t();
  std::set<int> colors;
  int lit = 0;
  for (int y = out.height - 1; y >= 0; --y)  // OpenGL rows start at the bottom
    for (int x = 0; x < out.width; ++x) {
      const unsigned char* p = im.data(x, y);
      out.pixels.insert(out.pixels.end(), p, p + 3);
      lit += p[0] + p[1] + p[2] > 30;
      colors.insert(p[0] << 16 | p[1] << 8 | p[2]);
    }
  const std::string path = (std::filesystem::path(ACUITY_OSG_TEST_OUT) / "osg_frame.png").string();
  std::filesystem::create_directories(ACUITY_OSG_TEST_OUT);
  acuity::sim::write_png(path, out);
  EXPECT_GT(std::filesystem::file_size(path), 1000u);
  EXPECT_GT(lit, kWidth * kHeight / 50) << "objects were drawn";
  EXPECT_LT(lit, kWidth * kHeight) << "the background shows";
  EXPECT_GE(colors.size(), 3u);
  std::printf("wrote %s: %d of %d pixels lit, %zu colours\n", path.c_str(), lit, kWidth * kHeight,
              colors.size());
}

}  // namespace

// A shadowed scene (osgShadow's ShadowMap, a directional light from above, 512 texels): an object
// behind the eye, which the eye's pass culls, is drawn in the light's pass at its shadow level: the
// footprint level of the map's texels, from the light camera's own projection and viewport (one
// frame behind it, as the kit reads the camera before osgShadow places it), finer than the level the
// eyes give it. An object in front is drawn in both passes.
TEST(Osg, AnObjectOutsideTheEyesViewGetsItsShadowLevelInTheLightsPass) {
  const acuity::Blob blob = acuity::spectra::encode_profile(acuity::testing::small_profile(4));
  acuity::SchedulerConfig config;
  config.max_objects = 2;
  config.max_views = 1;
  config.max_view_classes = 1;
  ::osg::ref_ptr<Kit> kit = new Kit(config);
  const int p = kit->add_profile(blob.data(), blob.size);
  ::osg::ref_ptr<osgShadow::ShadowedScene> scene = new osgShadow::ShadowedScene;
  ::osg::ref_ptr<acuity::osg::ShadowMap> map = new acuity::osg::ShadowMap;
  map->setTextureSize(::osg::Vec2s(512, 512));
  scene->setShadowTechnique(map.get());
  ::osg::ref_ptr<::osg::LightSource> sun = new ::osg::LightSource;
  sun->getLight()->setPosition(::osg::Vec4(0, 1, 0, 0));  // from straight above
  map->setLight(sun.get());
  scene->addChild(sun.get());
  ::osg::ref_ptr<LodNode> nodes[2];
  const double z[2] = {-6, 20};  // in front of the eye, and behind it
  for (int i = 0; i < 2; ++i) {
    nodes[i] = new LodNode;
    for (int k = 0; k < 4; ++k) nodes[i]->addChild(acuity::osg::make_geometry(quad(1)));
    kit->add(nodes[i].get(), p);
    ::osg::ref_ptr<::osg::MatrixTransform> at =
        new ::osg::MatrixTransform(::osg::Matrixd::translate(0, 0, z[i]));
    at->addChild(nodes[i].get());
    scene->addChild(at.get());
  }
  ASSERT_NE(map->camera(), nullptr);
  kit->set_view_cameras({{map->camera(), acuity::View{}}});  // class 0, Footprint, 1 texel
  EXPECT_EQ(kit->view_class_of(map->camera()), 0);
  osgViewer::Viewer viewer;
  ::osg::ref_ptr<Capture> capture = new Capture;
  World::realize(viewer, scene.get(), capture.get(), false);
  kit->attach(viewer);
  EXPECT_EQ(kit->view_class_of(viewer.getCamera()), -1);
  viewer.getCamera()->setViewMatrix(::osg::Matrixd::identity());  // at the origin, looking along -Z
  for (int f = 0; f < 4; ++f) viewer.frame(f / kFps);
  const unsigned frame = viewer.getFrameStamp()->getFrameNumber();
  const acuity::Scheduler& s = kit->scheduler();
  const LodNode::DrawnInView behind = nodes[1]->drawn_in_view(), ahead = nodes[0]->drawn_in_view();
  EXPECT_EQ(behind.frame, frame) << "the light's pass drew the object behind the eye";
  EXPECT_EQ(behind.view_class, 0u);
  EXPECT_EQ(behind.level, s.view_level_array(0)[nodes[1]->id()]);
  EXPECT_NE(nodes[1]->drawn().frame, frame) << "the eye's pass culled it";
  EXPECT_EQ(ahead.frame, frame);
  EXPECT_EQ(nodes[0]->drawn().frame, frame);
  // The footprint, independently: the light camera's orthographic map, texels per metre along
  // either axis (the larger), and small_profile's errors (0.01 k diameters of its 1.5 m sphere).
  double left, right, bottom, top, znear, zfar;
  ASSERT_TRUE(map->camera()->getProjectionMatrix().getOrtho(left, right, bottom, top, znear, zfar));
  const ::osg::Viewport* vp = map->camera()->getViewport();
  ASSERT_NE(vp, nullptr);
  EXPECT_EQ(vp->width(), 512);
  const double texels_per_m = std::max(vp->width() / (right - left), vp->height() / (top - bottom));
  std::uint8_t want = 0;
  while (want + 1 < 4 && 0.01 * (want + 1) * 3.0 * texels_per_m <= 1.0) ++want;
  EXPECT_EQ(behind.level, want) << texels_per_m << " texels per metre";
  EXPECT_LT(behind.level, s.level(nodes[1]->id())) << "finer than the eyes need behind them";
  EXPECT_EQ(ahead.level, want) << "orthographic: the same footprint anywhere";
}

// A CutNode draws the cut select_cut chooses from the kit's eyes and gaze: a real mesh (armadillo,
// through lodgen's cluster hierarchy) spanning 40 degrees, the gaze 18 degrees left, then right. Each
// frame the DrawElementsUInt holds exactly the cut's triangles, the cut is an independent
// scheduler's, the half under the gaze holds more triangles than the other, and the buffer is
// rebuilt when the gaze moves (and only then).
TEST(Osg, ACutNodeDrawsTheCutThatFollowsTheGaze) {
  acuity::lodgen::ChainOptions o;
  o.levels = 1;
  const acuity::lodgen::Mesh mesh =
      acuity::lodgen::build_chain(acuity::lodgen::load_mesh(std::string(ACUITY_MESH_DIR) + "/armadillo.off"),
                                  "armadillo.off", o)
          .levels[0]
          .mesh;
  acuity::lodgen::ClusterHierarchy ch = acuity::lodgen::build_clusters(mesh, "armadillo.off");
  const double diameter = acuity::lodgen::diameter(mesh);
  acuity::osg::CutNode::Hierarchy h;
  h.indices = ch.indices;
  h.clusters = ch.clusters;
  h.groups = ch.groups;
  h.bands_cpod = {2, 4, 8, 16, 32, 64};
  h.diameter = float(diameter);
  for (const acuity::ClusterGroup& g : h.groups)  // a stand-in loss growing with the group's error
    for (int b = 0; b < 6; ++b)
      h.lost.push_back(float(std::min(1.0, g.error / diameter * std::ldexp(1.0, b - 4))));
  // Object-space x of each cluster's triangles' centroid: which half it lies in.
  std::vector<double> cluster_x(h.clusters.size());
  for (std::size_t c = 0; c < h.clusters.size(); ++c) {
    double x = 0;
    const acuity::Cluster& k = h.clusters[c];
    for (std::size_t i = 3 * std::size_t(k.first_triangle);
         i < 3 * (std::size_t(k.first_triangle) + k.triangle_count); ++i)
      x += mesh.positions[3 * std::size_t(h.indices[i])];
    cluster_x[c] = x / (3.0 * k.triangle_count);
  }
  double centre_x = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) centre_x += mesh.positions[3 * v];
  centre_x /= double(mesh.vertex_count());

  acuity::SchedulerConfig config;
  config.max_objects = 1;
  ::osg::ref_ptr<Kit> kit = new Kit(config);
  const double distance = 3, scale = 2 * distance * std::tan(20 / kDeg) / diameter;  // 40 degrees wide
  ::osg::ref_ptr<::osg::MatrixTransform> place = new ::osg::MatrixTransform(
      ::osg::Matrixd::translate(-centre_x, 0, 0) * ::osg::Matrixd::scale(scale, scale, scale) *
      ::osg::Matrixd::translate(0, 0, -distance));
  ::osg::ref_ptr<acuity::osg::CutNode> node =
      new acuity::osg::CutNode(kit.get(), acuity::osg::make_geometry(mesh).get(), h);
  place->addChild(node.get());
  ::osg::ref_ptr<::osg::Group> root = new ::osg::Group;
  root->addChild(place.get());
  root->setStateSet(acuity::osg::make_shader_state().get());
  osgViewer::Viewer viewer;
  ::osg::ref_ptr<Capture> capture = new Capture;
  World::realize(viewer, root.get(), capture.get(), false);
  kit->attach(viewer);
  viewer.getCamera()->setViewMatrix(::osg::Matrixd::identity());

  acuity::Scheduler ref(config);
  std::vector<std::uint8_t> scratch(h.groups.size());
  std::vector<std::uint32_t> ref_drawn(h.clusters.size());
  const std::vector<std::uint32_t> roots = acuity::cluster_roots(h.clusters);
  const acuity::ClusterView view{h.clusters, h.groups, roots};
  const acuity::ClusterLoss loss{h.bands_cpod, h.diameter, h.lost};
  const double m[16] = {scale, 0, 0, 0, 0, scale, 0, 0, 0, 0, scale, 0, -centre_x * scale, 0, -distance, 1};
  const acuity::ObjectTransform t = acuity::transform_from_matrix(m);
  std::uint64_t halves[2][2] = {};  // [gaze left, right][triangles left, right of the centre]
  std::uint32_t rebuilds_before_right = 0;
  for (int f = 0; f < 8; ++f) {
    const bool right = f >= 4;
    acuity::Gaze g;
    g.direction[0] = float(std::sin((right ? 18 : -18) / kDeg));
    g.direction[2] = -float(std::cos(18 / kDeg));
    g.valid = true;
    kit->set_gaze_source(new acuity::osg::FixedGaze(g));
    if (f == 4) rebuilds_before_right = node->drawn().rebuilds;
    viewer.frame(f / kFps);
    const acuity::osg::CutNode::Drawn d = node->drawn();
    ASSERT_EQ(d.frame, viewer.getFrameStamp()->getFrameNumber()) << "frame " << f;
    ASSERT_EQ(d.cut.status, acuity::CutStatus::Ok);
    EXPECT_EQ(d.indices, 3 * d.cut.triangles) << "the index buffer holds the cut";
    EXPECT_EQ(node->geometry()->getPrimitiveSet(0)->getNumIndices(), d.indices);
    ref.begin_frame(kit->frame());
    const acuity::CutResult r = ref.select_cut(view, loss, t, nullptr, scratch, ref_drawn);
    const std::vector<std::uint32_t> cut = node->drawn_clusters();
    ASSERT_EQ(cut.size(), r.clusters) << "frame " << f;
    EXPECT_TRUE(std::equal(cut.begin(), cut.end(), ref_drawn.begin())) << "frame " << f;
    EXPECT_LT(d.cut.triangles, ch.finest_triangles()) << "the cut is coarser than the finest mesh";
    if (f == 3 || f == 7) {
      for (std::uint32_t c : cut) halves[right][cluster_x[c] > centre_x] += h.clusters[c].triangle_count;
    }
  }
  EXPECT_GT(halves[0][0], halves[0][1]) << "gaze left: the left half is finer";
  EXPECT_GT(halves[1][1], halves[1][0]) << "gaze right: the right half is finer";
  EXPECT_GT(node->drawn().rebuilds, rebuilds_before_right) << "the gaze moved: the buffer was rebuilt";
  EXPECT_LE(node->drawn().rebuilds, rebuilds_before_right + 2) << "and not every frame";
}
