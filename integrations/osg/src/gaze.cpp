#include "acuity/osg/gaze.hpp"

#include <algorithm>
#include <cmath>

namespace acuity::osg {
namespace {

class PointerHandler : public osgGA::GUIEventHandler {
 public:
  explicit PointerHandler(MouseGaze* gaze) : gaze_(gaze) {}
  bool handle(const osgGA::GUIEventAdapter& ea, osgGA::GUIActionAdapter&) override {
    if (ea.getEventType() == osgGA::GUIEventAdapter::MOVE ||
        ea.getEventType() == osgGA::GUIEventAdapter::DRAG) {
      float y = ea.getYnormalized();
      if (ea.getMouseYOrientation() == osgGA::GUIEventAdapter::Y_INCREASING_DOWNWARDS) y = -y;
      gaze_->set_pointer(ea.getXnormalized(), y);
    }
    return false;
  }

 private:
  MouseGaze* gaze_;  // the gaze owns this handler
};

}  // namespace

::osg::Vec3d direction_through(const ::osg::Camera& camera, double x, double y) {
  double l = -1, r = 1, b = -1, t = 1, n = 1, f = 2;
  if (!camera.getProjectionMatrix().getFrustum(l, r, b, t, n, f) || !(n > 0)) return {0, 0, -1};
  ::osg::Vec3d d(0.5 * ((1 - x) * l + (1 + x) * r) / n, 0.5 * ((1 - y) * b + (1 + y) * t) / n, -1);
  d.normalize();
  return d;
}

MouseGaze::MouseGaze() : handler_(new PointerHandler(this)) {}

void MouseGaze::set_pointer(float x, float y) {
  x_ = std::clamp(x, -1.0f, 1.0f);
  y_ = std::clamp(y, -1.0f, 1.0f);
  seen_ = true;
}

Gaze MouseGaze::gaze(std::uint32_t, double, const ::osg::Camera& camera, std::uint32_t) {
  Gaze g;
  const ::osg::Vec3d d = direction_through(camera, x_, y_);
  for (int k = 0; k < 3; ++k) g.direction[k] = float(d[k]);
  g.valid = seen_;
  return g;
}

TrackGaze::TrackGaze(std::vector<Gaze> samples, std::uint32_t first_frame)
    : samples_(std::move(samples)), first_(first_frame) {}

Gaze TrackGaze::gaze(std::uint32_t frame, double, const ::osg::Camera&, std::uint32_t) {
  if (samples_.empty()) return Gaze{};
  if (first_ == kFirstAsked) first_ = frame;
  return samples_[std::min<std::size_t>(frame > first_ ? frame - first_ : 0, samples_.size() - 1)];
}

}  // namespace acuity::osg
