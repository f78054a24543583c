#pragma once
// acuity/osg/gaze.hpp — gaze sources for acuity::osg::Kit: a fixed direction, the mouse as a gaze
// proxy, and a recorded trace played back frame by frame.
#include <vector>

#include <osgGA/GUIEventHandler>

#include "acuity/osg/kit.hpp"

namespace acuity::osg {

// One direction in eye space for every eye and frame (valid = false: no eye tracker).
class FixedGaze : public GazeSource {
 public:
  explicit FixedGaze(const Gaze& gaze = {}) : gaze_(gaze) {}
  void set(const Gaze& gaze) { gaze_ = gaze; }
  Gaze gaze(std::uint32_t, double, const ::osg::Camera&, std::uint32_t) override { return gaze_; }

 private:
  Gaze gaze_;
};

// The mouse pointer as the gaze: the direction through the pointer in each eye's projection.
// Add handler() to the viewer's event handlers. Invalid until the pointer has moved.
class MouseGaze : public GazeSource {
 public:
  MouseGaze();
  osgGA::GUIEventHandler* handler() const { return handler_.get(); }
  void set_pointer(float x, float y);  // normalised [-1, 1], +y up
  Gaze gaze(std::uint32_t frame, double time, const ::osg::Camera& camera, std::uint32_t eye) override;

 private:
  ::osg::ref_ptr<osgGA::GUIEventHandler> handler_;
  float x_ = 0, y_ = 0;
  bool seen_ = false;
};

// Eye-space direction through normalised device coordinates (x, y) of a perspective camera.
::osg::Vec3d direction_through(const ::osg::Camera& camera, double x, double y);

// A recorded trace, one gaze per frame for every eye, sample 0 at frame number `first_frame` (by
// default the first frame it is asked for); held past the ends. The file formats `acuity simulate
// --gaze` reads become such samples with sim::gazes_from(sim::gaze_trace_from(...))
// (acuity/sim/foveation_report.hpp, the offline library; the kit itself needs only the runtime).
class TrackGaze : public GazeSource {
 public:
  static constexpr std::uint32_t kFirstAsked = 0xffffffffu;
  explicit TrackGaze(std::vector<Gaze> samples, std::uint32_t first_frame = kFirstAsked);
  Gaze gaze(std::uint32_t frame, double time, const ::osg::Camera& camera, std::uint32_t eye) override;

 private:
  std::vector<Gaze> samples_;
  std::uint32_t first_;
};

}  // namespace acuity::osg
