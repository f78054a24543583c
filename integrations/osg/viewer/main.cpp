// acuity-osg: a glTF scene in OpenSceneGraph with acuity choosing every object's level.
//
//   acuity-osg build/demo/field.glb --profiles build/demo/profiles            # a window, flying the field
//   acuity-osg SCENE.glb --headless --frames 120 --out DIR --debug            # PNGs, levels.csv, frames.csv
//
// The scene is lodgen's glTF with MSFT_lod chains, or plain meshes chained on the fly (the code
// `acuity simulate` uses); profiles come from --profiles (built and saved there when missing). The
// head flies the built-in path over the scene or replays --head; the gaze replays --gaze, follows
// the mouse (windowed), or comes from simulate's gaze generator (headless). --debug colours objects
// by level and rings the gaze. Each frame's times (cull, acuity, draw) go to frames.csv and a
// summary line; the levels drawn go to levels.csv.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <osg/ComputeBoundsVisitor>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/LightSource>
#include <osg/LineWidth>
#include <osg/MatrixTransform>
#include <osg/Uniform>
#include <osgViewer/Viewer>

#include "acuity/file.hpp"
#include "acuity/osg/gaze.hpp"
#include "acuity/osg/kit.hpp"
#include "acuity/osg/loader.hpp"
#include "acuity/osg/shadow_map.hpp"
#include "acuity/sim/foveation_report.hpp"  // gazes_from
#include "acuity/sim/frame_image.hpp"
#include "acuity/sim/generators.hpp"

namespace fs = std::filesystem;
using namespace acuity;
namespace aosg = acuity::osg;

namespace {

constexpr double kDeg = 57.295779513082320876;

struct Options {
  std::string scene, profiles, head, gaze_file, gaze_mode = "auto", out, threading = "single";
  std::uint32_t frames = 0, skip = 1, png_every = 1, objects = 0, res = 256, width = 960, height = 540,
                seed = 1, shadow = 0;
  double seconds = 20, fps = 60, fov = 90, ipd = 0.064;
  float transition = 0.25f, quality = 1.0f;
  bool headless = false, stereo = false, debug = false, quiet = false, static_scene = false;
};

// Reads the whole colour buffer after the last camera's draw (and its HUD), before the swap.
struct Capture : ::osg::Camera::DrawCallback {
  ::osg::ref_ptr<::osg::Image> image = new ::osg::Image;
  int width = 0, height = 0;
  bool enabled = false;
  void operator()(::osg::RenderInfo&) const override {
    if (enabled) image->readPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE);
  }
};

sim::RgbImage to_rgb(const ::osg::Image& im) {
  sim::RgbImage out;
  out.width = im.s();
  out.height = im.t();
  out.pixels.reserve(std::size_t(out.width) * std::size_t(out.height) * 3);
  for (int y = out.height - 1; y >= 0; --y) {  // OpenGL rows start at the bottom
    const unsigned char* row = im.data(0, y);
    out.pixels.insert(out.pixels.end(), row, row + 3 * out.width);
  }
  return out;
}

// N objects on a square grid 3 m apart in front of the origin, cycling the scene's assets, each
// scaled to a 0.75 m bounding sphere resting at eye level's feet (for measuring scale).
std::vector<bake::Instance> grid(const bake::SceneAssets& s, std::uint32_t n) {
  std::vector<bake::Instance> out;
  const auto side = std::uint32_t(std::ceil(std::sqrt(double(n))));
  for (std::uint32_t i = 0; i < n; ++i) {
    bake::Instance in;
    in.asset = int(i % s.assets.size());
    const float* sphere = s.assets[std::size_t(in.asset)].profile.meta.sphere;
    const double scale = 0.75 / std::max(1e-9, double(sphere[3]));
    const double at[3] = {(double(i % side) - 0.5 * (side - 1)) * 3.0, 0.75, -(4.0 + double(i / side) * 3.0)};
    for (int k = 0; k < 3; ++k) in.transform.position[k] = at[k] - scale * double(sphere[k]);
    in.transform.scale = float(scale);
    in.radius = 0.75;
    in.name = s.assets[std::size_t(in.asset)].name + "_" + std::to_string(i);
    out.push_back(in);
  }
  return out;
}

::osg::Matrixd view_of(const sim::HeadPose& h) {
  const ::osg::Quat q(h.orientation.x, h.orientation.y, h.orientation.z, h.orientation.w);
  return ::osg::Matrixd::inverse(::osg::Matrixd::rotate(q) *
                                 ::osg::Matrixd::translate(h.position.x, h.position.y, h.position.z));
}

// A HUD camera with a ring (2 deg radius) that is moved to the gaze every frame.
struct GazeRing {
  ::osg::ref_ptr<::osg::Camera> hud = new ::osg::Camera;
  ::osg::ref_ptr<::osg::MatrixTransform> ring = new ::osg::MatrixTransform;
  GazeRing(int w, int h) {
    hud->setReferenceFrame(::osg::Transform::ABSOLUTE_RF);
    hud->setProjectionMatrixAsOrtho2D(0, w, 0, h);
    hud->setViewMatrix(::osg::Matrixd::identity());
    hud->setRenderOrder(::osg::Camera::POST_RENDER);
    hud->setClearMask(GL_DEPTH_BUFFER_BIT);
    hud->setAllowEventFocus(false);
    ::osg::ref_ptr<::osg::Geometry> g = new ::osg::Geometry;
    ::osg::ref_ptr<::osg::Vec3Array> v = new ::osg::Vec3Array;
    for (int i = 0; i < 64; ++i)
      v->push_back({float(std::cos(i * 2 * M_PI / 64)), float(std::sin(i * 2 * M_PI / 64)), 0});
    g->setVertexArray(v.get());
    ::osg::ref_ptr<::osg::Vec4Array> c = new ::osg::Vec4Array;
    c->push_back({1, 1, 1, 1});
    g->setColorArray(c.get(), ::osg::Array::BIND_OVERALL);
    g->addPrimitiveSet(new ::osg::DrawArrays(GL_LINE_LOOP, 0, 64));
    g->getOrCreateStateSet()->setMode(GL_LIGHTING, ::osg::StateAttribute::OFF);
    g->getOrCreateStateSet()->setAttribute(new ::osg::LineWidth(2));
    ring->addChild(g.get());
    hud->addChild(ring.get());
  }
  // Places the ring where `gaze` (eye space) projects in `camera`; hidden without gaze.
  void place(const ::osg::Camera& camera, const Gaze& gaze) {
    const ::osg::Viewport* vp = camera.getViewport();
    if (!gaze.valid || !vp || !(gaze.direction[2] < 0)) {
      ring->setNodeMask(0);
      return;
    }
    const ::osg::Matrixd& p = camera.getProjectionMatrix();
    const ::osg::Vec3d d(gaze.direction[0], gaze.direction[1], gaze.direction[2]);
    const ::osg::Vec3d ndc = d * p;
    double l, r, b, t, n, f;
    const double radius =
        p.getFrustum(l, r, b, t, n, f) ? std::tan(2.0 / kDeg) * n / (t - b) * vp->height() : 10.0;
    ring->setNodeMask(~0u);
    ring->setMatrix(::osg::Matrixd::scale(radius, radius, 1) *
                    ::osg::Matrixd::translate(vp->x() + 0.5 * (ndc.x() + 1) * vp->width(),
                                              vp->y() + 0.5 * (ndc.y() + 1) * vp->height(), 0));
  }
};

std::string csv_name(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '"' || c == '\n') c = '_';
  return s;
}

int run(const Options& o) {
  if (o.headless && o.frames == 0) throw std::runtime_error("--headless needs --frames N");
  SchedulerConfig config;
  config.transition_seconds = o.transition;
  config.quality = o.quality;
  // Load the scene (lodgen chains, profiles); the instances may be replaced by a grid of N objects.
  bake::AssetOptions ao;
  ao.profiles = o.profiles;
  ao.profile_pixels = o.res;
  ao.quiet = o.quiet;
  if (!o.quiet) std::printf("acuity-osg: loading %s\n", o.scene.c_str());
  std::unique_ptr<bake::SceneAssets> assets = bake::load_scene_assets(o.scene, ao);
  if (o.objects) assets->instances = grid(*assets, o.objects);
  config.max_objects = std::uint32_t(assets->instances.size());
  config.max_profiles = std::uint32_t(assets->assets.size());
  config.max_views = config.max_view_classes = o.shadow ? 1 : 0;  // the light's view: class 0
  ::osg::ref_ptr<aosg::Kit> kit = new aosg::Kit(config);
  aosg::SceneNodes nodes = aosg::make_nodes(*assets, assets->instances, *kit);
  if (o.static_scene)
    for (const auto& n : nodes.nodes) kit->set_static(n.get(), true);
  ::osg::ref_ptr<::osg::StateSet> shader = aosg::make_shader_state();
  shader->addUniform(new ::osg::Uniform("acuity_debug", o.debug ? 1.0f : 0.0f),
                     ::osg::StateAttribute::OVERRIDE);
  nodes.root->setStateSet(shader.get());

  // Head path and gaze.
  const std::size_t frames = o.frames ? o.frames : std::size_t(std::llround(o.seconds * o.fps));
  const std::vector<sim::HeadPose> head = o.head.empty()
                                              ? sim::flythrough(*assets, o.seconds, o.fps)
                                              : sim::head_path_from(sim::read_table(o.head), o.fps, frames);
  if (head.empty()) throw std::runtime_error("the head path is empty (--seconds too short?)");
  std::string mode = o.gaze_mode;
  if (mode == "auto") mode = !o.gaze_file.empty() ? "track" : o.headless ? "generated" : "mouse";
  ::osg::ref_ptr<aosg::GazeSource> gaze;
  ::osg::ref_ptr<aosg::MouseGaze> mouse;
  if (mode == "track") {
    if (o.gaze_file.empty()) throw std::runtime_error("--gaze-source track needs --gaze FILE");
    gaze = new aosg::TrackGaze(
        sim::gazes_from(sim::gaze_trace_from(sim::read_table(o.gaze_file), o.fps, frames)));
  } else if (mode == "generated") {
    gaze = new aosg::TrackGaze(sim::gazes_from(sim::generate_gaze(*assets, head, {}, o.fps, o.seed).samples));
  } else if (mode == "mouse") {
    mouse = new aosg::MouseGaze;
    gaze = mouse.get();
  } else if (mode == "fixed") {
    Gaze g;
    g.valid = true;
    gaze = new aosg::FixedGaze(g);
  } else if (mode != "none") {
    throw std::runtime_error("unknown --gaze-source " + mode);
  }
  kit->set_gaze_source(gaze.get());

  // The viewer: a window or a pbuffer; one camera, or two slaves side by side for --stereo.
  osgViewer::Viewer viewer;
  if (o.threading == "single")
    viewer.setThreadingModel(osgViewer::ViewerBase::SingleThreaded);
  else if (o.threading == "cull-draw")
    viewer.setThreadingModel(osgViewer::ViewerBase::CullDrawThreadPerContext);
  else if (o.threading == "draw")
    viewer.setThreadingModel(osgViewer::ViewerBase::DrawThreadPerContext);
  else if (o.threading == "cull-per-camera")
    viewer.setThreadingModel(osgViewer::ViewerBase::CullThreadPerCameraDrawThreadPerContext);
  else
    throw std::runtime_error("unknown --threading " + o.threading);
  if (o.threading != "single" && o.png_every && !o.out.empty())
    throw std::runtime_error(
        "PNG frames need --threading single (a draw thread may still be reading back); use --png-every 0");
  viewer.setCameraManipulator(nullptr);
  if (mouse) viewer.addEventHandler(mouse->handler());
  ::osg::ref_ptr<::osg::GraphicsContext::Traits> traits = new ::osg::GraphicsContext::Traits;
  traits->readDISPLAY();
  traits->setUndefinedScreenDetailsToDefaultScreen();
  traits->x = 50;
  traits->y = 50;
  traits->width = int(o.width);
  traits->height = int(o.height);
  traits->windowDecoration = true;
  traits->doubleBuffer = true;
  traits->pbuffer = o.headless;
  traits->red = traits->green = traits->blue = 8;
  traits->depth = 24;
  traits->windowName = "acuity-osg";
  ::osg::ref_ptr<::osg::GraphicsContext> gc = ::osg::GraphicsContext::createGraphicsContext(traits.get());
  if (!gc)
    throw std::runtime_error(std::string("cannot open ") + (o.headless ? "a pbuffer" : "a window") +
                             " on DISPLAY (try xvfb-run -a)");
  ::osg::ref_ptr<::osg::Group> top = new ::osg::Group;
  if (o.shadow) {
    // osgShadow's ShadowMap under a directional light from above: the kit's shader goes above it,
    // so its shadow shader draws the objects (no debug palette or dither inside), and its light
    // camera is the kit's view of class 0, whose levels the shadow pass draws.
    ::osg::ref_ptr<osgShadow::ShadowedScene> shadowed = new osgShadow::ShadowedScene;
    ::osg::ref_ptr<aosg::ShadowMap> map = new aosg::ShadowMap;
    map->setTextureSize(::osg::Vec2s(short(o.shadow), short(o.shadow)));
    shadowed->setShadowTechnique(map.get());
    ::osg::ref_ptr<::osg::LightSource> sun = new ::osg::LightSource;
    sun->getLight()->setPosition(::osg::Vec4(0.3f, 1.0f, 0.4f, 0.0f));  // directional
    map->setLight(sun.get());
    shadowed->addChild(sun.get());
    shadowed->addChild(nodes.root.get());
    // A ground under the objects (+Y up), half again as wide, to receive their shadows.
    ::osg::ComputeBoundsVisitor bounds;
    nodes.root->accept(bounds);
    const ::osg::BoundingBox& b = bounds.getBoundingBox();
    const float wide = 1.5f * std::max(b.xMax() - b.xMin(), b.zMax() - b.zMin());
    ::osg::ref_ptr<::osg::Geode> ground = new ::osg::Geode;
    ground->addDrawable(::osg::createTexturedQuadGeometry(
        {b.center().x() - wide / 2, b.yMin(), b.center().z() + wide / 2}, {wide, 0, 0}, {0, 0, -wide}));
    shadowed->addChild(ground.get());
    nodes.root->setStateSet(nullptr);
    top->setStateSet(shader.get());
    top->addChild(shadowed.get());
    kit->set_view_cameras({{map->camera(), View{}}});  // Footprint, 1 texel
  } else {
    top->addChild(nodes.root.get());
  }
  viewer.setSceneData(top.get());
  ::osg::Camera* master = viewer.getCamera();
  const double aspect = o.stereo ? 0.5 * o.width / o.height : double(o.width) / o.height;
  const double fovy = 2 * std::atan(std::tan(0.5 * o.fov / kDeg) / std::max(1.0, aspect)) *
                      kDeg;  // o.fov across the wider side
  master->setProjectionMatrixAsPerspective(fovy, aspect, 0.05, 5000);
  master->setClearColor({0.08f, 0.09f, 0.11f, 1});
  ::osg::ref_ptr<Capture> capture = new Capture;
  capture->width = int(o.width);
  capture->height = int(o.height);
  std::unique_ptr<GazeRing> ring;
  if (!o.stereo) {
    master->setGraphicsContext(gc.get());
    master->setViewport(0, 0, int(o.width), int(o.height));
    master->setDrawBuffer(GL_BACK);
    master->setReadBuffer(GL_BACK);
    if (o.debug) {
      ring = std::make_unique<GazeRing>(int(o.width), int(o.height));
      ring->hud->setViewport(0, 0, int(o.width), int(o.height));
      top->addChild(ring->hud.get());  // a nested post-render camera: drawn before the master's final draw
    }
    master->setFinalDrawCallback(capture.get());
  } else {
    for (int e = 0; e < 2; ++e) {
      ::osg::ref_ptr<::osg::Camera> cam = new ::osg::Camera;
      cam->setGraphicsContext(gc.get());
      cam->setViewport(e * int(o.width) / 2, 0, int(o.width) / 2, int(o.height));
      cam->setDrawBuffer(GL_BACK);
      cam->setReadBuffer(GL_BACK);
      cam->setClearColor(master->getClearColor());
      viewer.addSlave(cam.get(), ::osg::Matrixd(), ::osg::Matrixd::translate((e ? -0.5 : 0.5) * o.ipd, 0, 0));
    }
    viewer.getSlave(1)._camera->setFinalDrawCallback(capture.get());  // the right eye draws last
  }
  kit->attach(viewer);
  for (std::uint32_t i = 0; i < (o.stereo ? 2u : 1u); ++i) {
    ::osg::Camera* c = o.stereo ? viewer.getSlave(i)._camera.get() : master;
    c->setStats(new ::osg::Stats("camera"));
    c->getStats()->collectStats("rendering", true);
  }
  viewer.realize();
  if (!viewer.isRealized()) throw std::runtime_error("the viewer could not be realized");

  // Outputs.
  std::ofstream levels_csv, frames_csv, shadow_csv;
  std::string levels_tmp, frames_tmp, shadow_tmp;
  if (!o.out.empty()) {
    fs::create_directories(o.out);
    levels_tmp = (fs::path(o.out) / "levels.csv.tmp").string();
    frames_tmp = (fs::path(o.out) / "frames.csv.tmp").string();
    levels_csv.open(levels_tmp);
    frames_csv.open(frames_tmp);
    if (!levels_csv || !frames_csv) throw std::runtime_error("cannot write into " + o.out);
    levels_csv << "frame";
    for (const auto& n : nodes.nodes) levels_csv << ',' << csv_name(n->getName());
    levels_csv << '\n';
    if (o.shadow) {  // the same columns: each object's level in the shadow map
      shadow_tmp = (fs::path(o.out) / "shadow_levels.csv.tmp").string();
      shadow_csv.open(shadow_tmp);
      if (!shadow_csv) throw std::runtime_error("cannot write into " + o.out);
      shadow_csv << "frame";
      for (const auto& n : nodes.nodes) shadow_csv << ',' << csv_name(n->getName());
      shadow_csv << '\n';
    }
    frames_csv << "frame,time_s,frame_ms,cull_ms,acuity_ms,transforms_ms,draw_ms,triangles,changed\n";
  }
  if (!o.quiet)
    std::printf("acuity-osg: %zu objects, %zu assets, %s, %s gaze, %zu frames%s\n", nodes.nodes.size(),
                assets->assets.size(), o.headless ? "headless" : "windowed", mode.c_str(), frames,
                o.stereo ? ", stereo" : "");
  double sum_frame = 0, sum_cull = 0, sum_acuity = 0, sum_transforms = 0, sum_draw = 0;
  std::size_t measured = 0, pngs = 0;
  for (std::size_t f = 0; (o.frames == 0 || f < frames) && !viewer.done(); ++f) {
    const double t = double(f) / o.fps;
    master->setViewMatrix(view_of(head[f % head.size()]));
    // The gaze the kit will ask for in this frame (viewer.frame() advances the frame number first).
    if (ring && gaze)
      ring->place(*master, gaze->gaze(viewer.getFrameStamp()->getFrameNumber() + 1, t, *master, 0));
    const bool png = !o.out.empty() && o.png_every && f % o.png_every == 0;
    capture->enabled = png;
    const auto t0 = std::chrono::steady_clock::now();
    viewer.frame(t);
    const double frame_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const unsigned number = viewer.getFrameStamp()->getFrameNumber();
    double cull = 0, draw = 0;
    for (std::uint32_t i = 0; i < (o.stereo ? 2u : 1u); ++i) {
      ::osg::Stats* st = (o.stereo ? viewer.getSlave(i)._camera.get() : master)->getStats();
      double v = 0;
      if (st->getAttribute(number, "Cull traversal time taken", v)) cull += 1000 * v;
      if (st->getAttribute(number, "Draw traversal time taken", v)) draw += 1000 * v;
    }
    const double acuity_ms = kit->last_acuity_ms();
    if (f >= o.skip) {  // frame 0 compiles shaders and uploads buffers; the first fades start from level 0
      sum_frame += frame_ms;
      sum_cull += cull;
      sum_acuity += acuity_ms;
      sum_transforms += kit->last_transforms_ms();
      sum_draw += draw;
      ++measured;
    }
    if (!o.out.empty()) {
      levels_csv << f;
      for (const auto& n : nodes.nodes) levels_csv << ',' << int(kit->scheduler().level(n->id()));
      levels_csv << '\n';
      if (o.shadow) {
        shadow_csv << f;
        for (const auto& n : nodes.nodes)
          shadow_csv << ',' << int(kit->scheduler().view_level_array(0)[n->id()]);
        shadow_csv << '\n';
      }
      frames_csv << f << ',' << t << ',' << frame_ms << ',' << cull << ',' << acuity_ms << ','
                 << kit->last_transforms_ms() << ',' << draw << ',' << kit->scheduler().stats().triangles
                 << ',' << kit->scheduler().stats().changed << '\n';
      if (png) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05zu.png", f);
        sim::write_png((fs::path(o.out) / name).string(), to_rgb(*capture->image));
        ++pngs;
      }
    }
  }
  if (!o.out.empty()) {
    levels_csv.close();
    frames_csv.close();
    if (!levels_csv || !frames_csv) throw std::runtime_error("writing into " + o.out + " failed");
    fs::rename(levels_tmp, fs::path(o.out) / "levels.csv");
    fs::rename(frames_tmp, fs::path(o.out) / "frames.csv");
    if (o.shadow) {
      shadow_csv.close();
      if (!shadow_csv) throw std::runtime_error("writing into " + o.out + " failed");
      fs::rename(shadow_tmp, fs::path(o.out) / "shadow_levels.csv");
    }
  }
  if (measured) {
    const double n = double(measured);
    std::printf(
        "frame time [ms, mean of %zu frames after the first %u]: frame %.3f, cull %.3f (acuity %.3f inside "
        "it, of which "
        "eyes and transforms %.3f), draw %.3f; acuity %.2f%% of the frame, %zu objects\n",
        measured, o.skip, sum_frame / n, sum_cull / n, sum_acuity / n, sum_transforms / n, sum_draw / n,
        100 * sum_acuity / sum_frame, nodes.nodes.size());
  }
  if (!o.out.empty() && !o.quiet)
    std::printf("wrote %zu PNG frames, levels.csv and frames.csv into %s\n", pngs, o.out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"acuity-osg: a glTF scene in OpenSceneGraph with acuity choosing the levels"};
  app.add_option("scene", o.scene, "glTF/GLB (MSFT_lod chains from acuity lodgen, or plain meshes)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--profiles", o.profiles,
                 "Directory of <asset>.acuity profiles (built and saved there when missing)");
  app.add_option("--res", o.res, "Snapshot pixels for profiles built here")->capture_default_str();
  app.add_option("--head", o.head,
                 "Head path to replay (CSV/JSON: t,x,y,z,qx,qy,qz,qw); default: fly over the scene")
      ->check(CLI::ExistingFile);
  app.add_option("--gaze", o.gaze_file, "Gaze trace to replay (CSV/JSON: t,x,y,z[,confidence], head space)")
      ->check(CLI::ExistingFile);
  app.add_option("--gaze-source", o.gaze_mode, "auto | track | generated | mouse | fixed | none")
      ->capture_default_str();
  app.add_option("--seconds", o.seconds, "Length of the built-in path [s]")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--fps", o.fps, "Frames per second of the simulated clock")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option("--frames", o.frames,
                 "Stop after N frames (default: the path's length, looping when windowed)");
  app.add_option("--skip", o.skip, "Frames left out of the frame-time means (warm-up)")
      ->capture_default_str();
  app.add_option("--out", o.out, "Directory for frame_NNNNN.png, levels.csv, frames.csv");
  app.add_option("--png-every", o.png_every, "Write every K-th frame as PNG (0: none)")
      ->capture_default_str();
  app.add_option("--objects", o.objects, "Replace the instances by a grid of N objects cycling the assets")
      ->check(CLI::Range(1u, 1000000u));
  app.add_option("--width", o.width, "Pixels")->capture_default_str()->check(CLI::Range(16u, 8192u));
  app.add_option("--height", o.height, "Pixels")->capture_default_str()->check(CLI::Range(16u, 8192u));
  app.add_option("--fov", o.fov, "Field of view across the wider side [deg]")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 170.0));
  app.add_option("--transition", o.transition, "Cross-fade seconds")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 10.0f));
  app.add_option("--quality", o.quality, "q: invisible when lost <= q CT")
      ->capture_default_str()
      ->check(CLI::Range(0.01f, 100.0f));
  app.add_option("--seed", o.seed, "Seed of the generated gaze")->capture_default_str();
  app.add_option("--threading", o.threading,
                 "OSG threading model: single | cull-draw | draw | cull-per-camera")
      ->capture_default_str();
  app.add_option("--shadow", o.shadow,
                 "Draw shadows (osgShadow's ShadowMap, a directional light; TEXELS across its map; 0: none): "
                 "each object's shadow level is its error's footprint in texels (shadow_levels.csv)")
      ->check(CLI::Range(0u, 8192u));
  app.add_flag("--headless", o.headless, "Render into a pbuffer (under xvfb-run -a without a display)");
  app.add_flag("--stereo", o.stereo, "Two slave cameras side by side, one per eye");
  app.add_flag("--static", o.static_scene,
               "Objects never move: read each world transform once, not every frame");
  app.add_flag("--debug", o.debug, "Colour objects by level and ring the gaze");
  app.add_flag("-q,--quiet", o.quiet, "Only the frame-time line");
  CLI11_PARSE(app, argc, argv);
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "acuity-osg: %s\n", e.what());
    return 1;
  }
}
