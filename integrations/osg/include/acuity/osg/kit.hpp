#pragma once
// acuity/osg/kit.hpp — acuity inside OpenSceneGraph: a LodNode per object whose children are its
// levels (finest first), and one Kit per viewer that owns the acuity::Scheduler.
//
//   osg::ref_ptr<acuity::osg::Kit> kit = new acuity::osg::Kit(config);
//   int p = kit->add_profile(blob);                       // .acuity bytes (copied)
//                                                         // (deferred: tables later, make_wanted_tables)
//   auto* node = new acuity::osg::LodNode;                // addChild(level 0), addChild(level 1), ...
//   kit->add(node, p);                                    // now an acuity object
//   parent->addChild(node);                               // anywhere under transforms
//   kit->attach(viewer);                                  // cameras -> eyes (two slaves: stereo)
//   root->setStateSet(acuity::osg::make_shader_state());  // the screen-door cross-fade shader
//
// Each frame the first cull traversal (of any attached camera) runs the scheduler once: eyes from
// the cameras (view matrix -> pose, projection -> FOV half-angles, viewport -> pixels), the gaze
// from the GazeSource, each node's world transform from its parent path (osg::computeLocalToWorld;
// a LodNode has one parent path), dt from the frame stamp's simulation time. Then every LodNode
// culled draws the scheduler's level; while a transition fades (transition_seconds > 0) it draws
// both levels, the new one where an 8x8 ordered dither is below the fade and the old one elsewhere.
// Thread-safe for OSG's threading models: the frame runs under a mutex, once per frame number; the
// culls after it take no lock of the kit's (the frame's number is published when it has run, and
// the view cameras are looked up under the mutex only when there are any).
//
// Views beyond the eyes (acuity::View): set_view_cameras() names cameras that render the scene for
// something else, osgShadow's light camera or a mirror's render-to-texture camera; a cull under one
// of them draws its view class's level (Scheduler::view_level_array), not the eyes'.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

#include <osg/Camera>
#include <osg/Group>
#include <osg/NodeVisitor>
#include <osg/StateSet>
#include <osg/observer_ptr>
#include <osgViewer/View>

#include "acuity/blob.hpp"
#include "acuity/scheduler.hpp"

namespace acuity::osg {

class Kit;

// Where the eyes look. gaze() is called once per eye per frame, under the kit's frame lock.
class GazeSource : public ::osg::Referenced {
 public:
  // Gaze of eye `eye` (0 or 1) whose camera is `camera`, for frame `frame` at `time` [s]; the
  // direction is in that camera's eye space (-Z forward, +Y up).
  virtual Gaze gaze(std::uint32_t frame, double time, const ::osg::Camera& camera, std::uint32_t eye) = 0;
};

// The eye space of a camera: pose from the inverse view matrix, FOV half-angles from the projection
// frustum (false for a projection that is not a perspective frustum), viewport in pixels.
bool eye_from_camera(const ::osg::Camera& camera, Eye* eye);
// A camera as a View (beside the eye's pose: an orthographic projection's extents or a perspective
// one's half-angles, and its viewport); the other fields are left as given. False for a projection
// that is neither, or a camera without a viewport.
bool view_from_camera(const ::osg::Camera& camera, View* view);

// One acuity object: children are its levels, finest first (as many as its profile has levels; a
// level without a child draws nothing). One parent path: its first parents give its world transform.
class LodNode : public ::osg::Group {
 public:
  LodNode() = default;
  LodNode(const LodNode& other, const ::osg::CopyOp& op = ::osg::CopyOp::SHALLOW_COPY);
  // META_Node(acuity, LodNode), spelled out: the macro's unqualified osg:: would name this namespace.
  ::osg::Object* cloneType() const override { return new LodNode(); }
  ::osg::Object* clone(const ::osg::CopyOp& op) const override { return new LodNode(*this, op); }
  bool isSameKindAs(const ::osg::Object* obj) const override {
    return dynamic_cast<const LodNode*>(obj) != nullptr;
  }
  const char* className() const override { return "LodNode"; }
  const char* libraryName() const override { return "acuity"; }
  void accept(::osg::NodeVisitor& nv) override {
    if (nv.validNodeMask(*this)) {
      nv.pushOntoNodePath(this);
      nv.apply(*this);
      nv.popFromNodePath();
    }
  }

  ObjectId id() const { return id_; }  // kInvalidObject until Kit::add
  Kit* kit() const { return kit_.get(); }

  // What the last cull traversal drew (for debug views and tests).
  struct Drawn {
    std::uint32_t frame = 0xffffffffu;     // frame number of that cull
    std::uint8_t level = 0, previous = 0;  // drawn level, and the level faded out
    float fade = 1;                        // acuity_fade uniform given to `level` (1: alone)
    bool both = false;                     // previous was drawn too (a cross-fade)
    std::uint32_t culls = 0;               // culls of that frame that drew the node (cameras)
  };
  Drawn drawn() const;
  // What the last cull under a view camera (Kit::set_view_cameras) drew: its frame and level.
  struct DrawnInView {
    std::uint32_t frame = 0xffffffffu;
    std::uint32_t view_class = 0;
    std::uint8_t level = 0;
  };
  DrawnInView drawn_in_view() const;

  // In a cull traversal: the scheduler's level (and the faded-out one); other visitors traverse the
  // active level (TRAVERSE_ACTIVE_CHILDREN) or every level. Before Kit::add (or after its kit is
  // gone) the active level is level 0.
  void traverse(::osg::NodeVisitor& nv) override;

 protected:
  ~LodNode() override;

 private:
  friend class Kit;
  ::osg::observer_ptr<Kit> kit_;
  ObjectId id_ = kInvalidObject;
  bool static_ = false, placed_ = false;  // placed_: a static node's transform was read
  mutable std::mutex drawn_mutex_;
  Drawn drawn_;
  DrawnInView drawn_in_view_;
};

class Kit : public ::osg::Referenced {
 public:
  explicit Kit(const SchedulerConfig& config);

  // Validates and keeps a copy of profile bytes; returns its index. Throws std::runtime_error.
  // deferred: its tables are not built (Scheduler::add_profile_deferred; quick whatever the profile),
  // and its objects decide exactly until make_wanted_tables() makes the views they are seen from.
  int add_profile(const void* data, std::size_t size, bool deferred = false);
  // Between frames, on a thread of the application's choosing: makes and installs the tables of up
  // to `max_views` of the views objects of deferred profiles were seen from without them
  // (Scheduler::wanted_tables; several ms of CPU each: a loading screen, or one per frame). Returns
  // how many it made; the rest wait for the next call.
  std::uint32_t make_wanted_tables(std::uint32_t max_views);
  // Between frames: frees the tables of the views no object has read in the last `frames` frames
  // (Scheduler::drop_idle_tables; every few seconds, not every frame). Returns the bytes freed.
  std::size_t drop_idle_tables(std::uint32_t frames);
  // Makes `node` an acuity object with `profile`; its world transform is read from its parent path
  // each frame. Throws std::runtime_error when full, for a bad profile, or when the node is taken.
  void add(LodNode* node, int profile);
  void remove(LodNode* node);
  void set_bias(LodNode* node, float quality_bias);  // multiplies q (> 1 coarser)
  void set_clamps(LodNode* node, std::uint8_t min_level, std::uint8_t max_level);
  // A static node's world transform is read from its parent path once (on the next frame) instead
  // of every frame; mark_moved() reads it again on the next frame.
  void set_static(LodNode* node, bool is_static);
  void mark_moved(LodNode* node);

  // The cameras that are the eyes (one, or two for stereo), each given a cull callback (added to
  // theirs) that runs the frame; a second call replaces the first. Without cameras the camera of
  // the first cull is the one eye. A camera whose projection is not a perspective frustum keeps
  // its last eye.
  void set_cameras(const std::vector<::osg::Camera*>& cameras);
  // The view's two slave cameras when it has two (stereo), else its master camera.
  void attach(::osgViewer::View& view);
  // Views beyond the eyes: each camera becomes, every frame, a View with `settings`' view_class,
  // rule and pixel_error, and its own pose, projection and viewport as of its last cull (for a
  // camera placed during the cull, as osgShadow's light camera is, the previous frame's: a frame
  // behind; none before its first). A cull under one of them draws that class's level, without
  // cross-fades. At most SchedulerConfig::max_views cameras; a second call replaces the first.
  // Throws std::runtime_error for a null camera, too many, or a class not below max_view_classes.
  struct ViewCamera {
    ::osg::Camera* camera;
    View settings;
  };
  void set_view_cameras(const std::vector<ViewCamera>& cameras);
  // The view class whose camera `camera` is, or -1 (an eye, or no view camera).
  int view_class_of(const ::osg::Camera* camera);
  void set_gaze_source(GazeSource* source) { gaze_ = source; }
  GazeSource* gaze_source() const { return gaze_.get(); }

  // Runs the scheduler for this frame stamp unless this frame number already ran. `fallback` is the
  // eye when no camera was set. Called by the camera callbacks and by LodNode::traverse.
  void run_frame(const ::osg::FrameStamp& stamp, const ::osg::Camera* fallback);

  const Scheduler& scheduler() const { return *scheduler_; }
  const Frame& frame() const { return frame_; }  // the last frame's input
  const std::vector<LodNode*>& nodes() const { return nodes_; }
  std::uint32_t frame_number() const { return frame_number_; }
  double last_acuity_ms() const { return acuity_ms_; }          // eyes + transforms + scheduler, last frame
  double last_transforms_ms() const { return transforms_ms_; }  // of which eyes and node-path transforms

  // Shared, immutable state sets pushed around a level in the cull: acuity_fade quantised to 1/64
  // (the dither's resolution) with acuity_outgoing false (incoming) or true (faded out); and one
  // per level setting acuity_level_color (the debug palette).
  ::osg::StateSet* fade_state(float fade, bool outgoing) const;
  ::osg::StateSet* level_state(std::uint8_t level) const { return level_states_[level % kMaxLevels].get(); }
  static float quantise_fade(float fade);

 protected:
  ~Kit() override;

 private:
  friend class LodNode;
  class CameraCallback;
  void forget(LodNode* node);
  void read_eyes(const ::osg::Camera* fallback, double dt);

  std::unique_ptr<Scheduler> scheduler_;
  std::deque<Blob> profiles_;
  std::deque<TablesWanted> wanted_;  // listed by the scheduler, not made yet
  std::vector<LodNode*> nodes_;
  std::vector<::osg::observer_ptr<::osg::Camera>> cameras_;
  std::vector<::osg::observer_ptr<::osg::Camera>> view_cameras_;
  std::vector<View> view_settings_, views_;   // per view camera; the frame's (frame_.views)
  ::osg::ref_ptr<::osg::Callback> callback_;  // the cull callback added to each eye camera
  ::osg::ref_ptr<GazeSource> gaze_;
  std::mutex mutex_;
  // Published after a frame has run (its number + 1; 0 before any) and the number of view cameras:
  // read without the mutex by each cull (run_frame, view_class_of).
  std::atomic<std::uint64_t> completed_frame_{0};
  std::atomic<std::size_t> view_camera_count_{0};
  std::uint32_t frame_number_ = 0xffffffffu;
  double time_ = 0;
  bool ran_ = false;
  Frame frame_;
  Eye previous_eyes_[2];
  double acuity_ms_ = 0, transforms_ms_ = 0;
  ::osg::NodePath path_;  // reused by the transform walk
  std::vector<::osg::ref_ptr<::osg::StateSet>> fade_states_[2];
  std::vector<::osg::ref_ptr<::osg::StateSet>> level_states_;
};

// The shader program and its default uniforms, for the scene root. Fragment colour: a headlight-lit
// acuity_color (the material, set per level by the loader), mixed with acuity_level_color by
// acuity_debug (0 off, 1 colour by level); fragments are discarded by the screen-door cross-fade.
::osg::ref_ptr<::osg::StateSet> make_shader_state();
// The debug palette: level 0 blue, 1 cyan, 2 green, 3 yellow, 4 orange, 5 red, then purple, grey.
::osg::Vec4 level_color(std::uint32_t level);
// The dither threshold in [0, 1) of pixel (x, y): the 8x8 Bayer matrix, as the shader computes it.
float dither_threshold(int x, int y);

}  // namespace acuity::osg
