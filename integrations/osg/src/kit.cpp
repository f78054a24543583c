#include "acuity/osg/kit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <osg/Transform>
#include <osg/Uniform>

#include "acuity/transform.hpp"

namespace acuity::osg {
namespace {

constexpr double kDeg = 57.295779513082320876;
constexpr int kFadeSteps = 64;  // the 8x8 dither's coverage levels

// The rotation from p to q, q * p^-1 (Hamilton product), for quaternions stored x y z w.
std::array<double, 4> turn_between(const float q[4], const float p[4]) {
  const double d = double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2] + double(p[3]) * p[3];
  const double bx = -p[0] / d, by = -p[1] / d, bz = -p[2] / d, bw = p[3] / d;
  const double ax = q[0], ay = q[1], az = q[2], aw = q[3];
  return {aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
          aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz};
}

}  // namespace

// Runs the kit's frame at the start of an eye camera's cull, then culls the camera's subgraph.
class Kit::CameraCallback : public ::osg::NodeCallback {
 public:
  explicit CameraCallback(Kit* kit) : kit_(kit) {}
  void operator()(::osg::Node* node, ::osg::NodeVisitor* nv) override {
    ::osg::ref_ptr<Kit> kit;
    if (kit_.lock(kit) && nv->getFrameStamp()) kit->run_frame(*nv->getFrameStamp(), nullptr);
    traverse(node, nv);
  }

 private:
  ::osg::observer_ptr<Kit> kit_;
};

namespace {
// A camera's pose (from the inverse view matrix) and viewport (or its context's size); false when
// it has neither.
bool pose_and_viewport(const ::osg::Camera& camera, double position[3], float orientation[4],
                       std::uint32_t viewport[2]) {
  const ::osg::Matrixd world = ::osg::Matrixd::inverse(camera.getViewMatrix());
  ::osg::Vec3d t, s;
  ::osg::Quat r, so;
  world.decompose(t, r, s, so);
  for (int k = 0; k < 3; ++k) position[k] = t[k];
  const ::osg::Vec4d q = r.asVec4();
  const double n = q.length();
  for (int k = 0; k < 4; ++k) orientation[k] = float(n > 0 ? q[k] / n : (k == 3));
  const ::osg::Viewport* vp = camera.getViewport();
  if (vp && vp->width() > 0 && vp->height() > 0) {
    viewport[0] = std::uint32_t(vp->width());
    viewport[1] = std::uint32_t(vp->height());
  } else if (const ::osg::GraphicsContext* gc = camera.getGraphicsContext(); gc && gc->getTraits()) {
    viewport[0] = std::uint32_t(std::max(1, gc->getTraits()->width));
    viewport[1] = std::uint32_t(std::max(1, gc->getTraits()->height));
  } else {
    return false;
  }
  return true;
}
// A perspective frustum's half-angles [deg] (left, right, up, down), or false.
bool frustum_deg(const ::osg::Matrixd& projection, float fov_deg[4]) {
  double left = 0, right = 0, bottom = 0, top = 0, znear = 0, zfar = 0;
  if (!projection.getFrustum(left, right, bottom, top, znear, zfar) || !(znear > 0)) return false;
  fov_deg[0] = float(std::atan(left / znear) * kDeg);
  fov_deg[1] = float(std::atan(right / znear) * kDeg);
  fov_deg[2] = float(std::atan(top / znear) * kDeg);
  fov_deg[3] = float(std::atan(bottom / znear) * kDeg);
  return true;
}
}  // namespace

bool eye_from_camera(const ::osg::Camera& camera, Eye* eye) {
  pose_and_viewport(camera, eye->position, eye->orientation, eye->viewport);
  return frustum_deg(camera.getProjectionMatrix(), eye->fov_deg);
}

bool view_from_camera(const ::osg::Camera& camera, View* view) {
  if (!pose_and_viewport(camera, view->position, view->orientation, view->viewport)) return false;
  const ::osg::Matrixd& p = camera.getProjectionMatrix();
  double left = 0, right = 0, bottom = 0, top = 0, znear = 0, zfar = 0;
  if (p(3, 3) == 1.0 && p.getOrtho(left, right, bottom, top, znear, zfar)) {  // orthographic
    view->projection = ViewProjection::Orthographic;
    view->extent_m[0] = float(left);
    view->extent_m[1] = float(right);
    view->extent_m[2] = float(top);
    view->extent_m[3] = float(bottom);
    return true;
  }
  view->projection = ViewProjection::Perspective;
  return frustum_deg(p, view->fov_deg);
}

Kit::Kit(const SchedulerConfig& config) : scheduler_(std::make_unique<Scheduler>(config)) {
  for (int side = 0; side < 2; ++side)
    for (int i = 0; i <= kFadeSteps; ++i) {
      ::osg::ref_ptr<::osg::StateSet> ss = new ::osg::StateSet;
      ss->addUniform(new ::osg::Uniform("acuity_fade", float(i) / float(kFadeSteps)));
      ss->addUniform(new ::osg::Uniform("acuity_outgoing", side == 1));
      ss->setDataVariance(::osg::Object::STATIC);
      fade_states_[side].push_back(ss);
    }
  for (std::uint32_t k = 0; k < kMaxLevels; ++k) {
    ::osg::ref_ptr<::osg::StateSet> ss = new ::osg::StateSet;
    ss->addUniform(new ::osg::Uniform("acuity_level_color", level_color(k)));
    level_states_.push_back(ss);
  }
}

Kit::~Kit() {
  for (LodNode* n : nodes_) {
    if (!n) continue;
    n->kit_ = nullptr;
    n->id_ = kInvalidObject;
  }
}

int Kit::add_profile(const void* data, std::size_t size, bool deferred) {
  Blob blob;
  blob.size = size;
  blob.storage.assign((size + 7) / 8, 0);
  if (size) std::memcpy(blob.storage.data(), data, size);
  Profile p;
  ProfileError e;
  if (open_profile(blob.data(), blob.size, &p, &e) != ProfileStatus::Ok)
    throw std::runtime_error(std::string("acuity::osg::Kit::add_profile: ") + to_string(e.status) + ": " +
                             e.message);
  std::lock_guard<std::mutex> lock(mutex_);
  profiles_.push_back(std::move(blob));
  open_profile(profiles_.back().data(), profiles_.back().size, &p);  // point into the kept copy
  const int index = deferred ? scheduler_->add_profile_deferred(p) : scheduler_->add_profile(p);
  if (index < 0) {
    profiles_.pop_back();
    throw std::runtime_error("acuity::osg::Kit::add_profile: max_profiles reached");
  }
  return index;
}

std::uint32_t Kit::make_wanted_tables(std::uint32_t max_views) {
  std::lock_guard<std::mutex> lock(mutex_);  // between frames: run_frame holds it for a whole frame
  TablesWanted listed[64];
  for (std::uint32_t n; (n = scheduler_->wanted_tables(listed)) > 0;)
    wanted_.insert(wanted_.end(), listed, listed + n);
  std::uint32_t made = 0;
  for (; made < max_views && !wanted_.empty(); ++made) {
    const TablesWanted w = wanted_.front();
    wanted_.pop_front();
    scheduler_->install_tables(w.profile, scheduler_->make_tables(w.profile, static_cast<int>(w.view)));
  }
  return made;
}

std::size_t Kit::drop_idle_tables(std::uint32_t frames) {
  std::lock_guard<std::mutex> lock(mutex_);  // between frames, as make_wanted_tables
  return scheduler_->drop_idle_tables(frames);
}

void Kit::add(LodNode* node, int profile) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!node || node->id_ != kInvalidObject)
    throw std::runtime_error("acuity::osg::Kit::add: null node, or one already added");
  const ObjectId id = scheduler_->add_object(profile, ObjectTransform{});
  if (id == kInvalidObject)
    throw std::runtime_error("acuity::osg::Kit::add: max_objects reached or bad profile " +
                             std::to_string(profile));
  node->kit_ = this;
  node->id_ = id;
  node->placed_ = false;
  if (nodes_.size() <= id) nodes_.resize(std::size_t(id) + 1, nullptr);
  nodes_[id] = node;
}

void Kit::forget(LodNode* node) {
  if (node->id_ == kInvalidObject) return;
  scheduler_->remove_object(node->id_);
  nodes_[node->id_] = nullptr;
  node->id_ = kInvalidObject;
  node->kit_ = nullptr;
}

void Kit::remove(LodNode* node) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (node && node->kit_.get() == this) forget(node);
}

void Kit::set_bias(LodNode* node, float bias) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (node && node->kit_.get() == this) scheduler_->set_bias(node->id_, bias);
}

void Kit::set_clamps(LodNode* node, std::uint8_t lo, std::uint8_t hi) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (node && node->kit_.get() == this) scheduler_->set_clamps(node->id_, lo, hi);
}

void Kit::set_static(LodNode* node, bool is_static) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (node && node->kit_.get() == this) {
    node->static_ = is_static;
    node->placed_ = false;
  }
}

void Kit::mark_moved(LodNode* node) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (node && node->kit_.get() == this) node->placed_ = false;
}

void Kit::set_cameras(const std::vector<::osg::Camera*>& cameras) {
  if (cameras.size() > 2) throw std::runtime_error("acuity::osg::Kit::set_cameras: one or two cameras");
  std::lock_guard<std::mutex> lock(mutex_);
  if (!callback_) callback_ = new CameraCallback(this);
  for (const auto& c : cameras_) {
    ::osg::ref_ptr<::osg::Camera> old;
    if (c.lock(old)) old->removeCullCallback(callback_.get());
  }
  cameras_.clear();
  for (::osg::Camera* c : cameras) {
    if (!c) throw std::runtime_error("acuity::osg::Kit::set_cameras: null camera");
    cameras_.emplace_back(c);
    c->addCullCallback(callback_.get());  // nested with the application's own cull callbacks
  }
}

void Kit::attach(::osgViewer::View& view) {
  if (view.getNumSlaves() == 2 && view.getSlave(0)._camera.valid() && view.getSlave(1)._camera.valid())
    set_cameras({view.getSlave(0)._camera.get(), view.getSlave(1)._camera.get()});
  else
    set_cameras({view.getCamera()});
}

void Kit::set_view_cameras(const std::vector<ViewCamera>& cameras) {
  const SchedulerConfig& c = scheduler_->config();
  if (cameras.size() > c.max_views)
    throw std::runtime_error("acuity::osg::Kit::set_view_cameras: more cameras than max_views");
  for (const ViewCamera& v : cameras)
    if (!v.camera || v.settings.view_class >= c.max_view_classes)
      throw std::runtime_error(
          "acuity::osg::Kit::set_view_cameras: a null camera or a class past max_view_classes");
  std::lock_guard<std::mutex> lock(mutex_);
  view_cameras_.clear();
  view_settings_.clear();
  for (const ViewCamera& v : cameras) {
    view_cameras_.emplace_back(v.camera);
    view_settings_.push_back(v.settings);
  }
  views_.assign(cameras.size(), View{});
  view_camera_count_.store(view_cameras_.size(), std::memory_order_release);
}

int Kit::view_class_of(const ::osg::Camera* camera) {
  if (!camera || view_camera_count_.load(std::memory_order_acquire) == 0) return -1;
  std::lock_guard<std::mutex> lock(mutex_);
  for (std::size_t i = 0; i < view_cameras_.size(); ++i)
    if (view_cameras_[i].get() == camera) return int(view_settings_[i].view_class);
  return -1;
}

void Kit::read_eyes(const ::osg::Camera* fallback, double dt) {
  std::vector<const ::osg::Camera*> cams;
  for (const auto& c : cameras_)
    if (c.valid()) cams.push_back(c.get());
  if (cams.empty() && fallback) cams.push_back(fallback);
  frame_.eye_count = std::uint32_t(std::max<std::size_t>(1, cams.size()));
  for (std::uint32_t e = 0; e < cams.size(); ++e) {
    Eye& eye = frame_.eyes[e];
    const Eye before = eye;
    if (!eye_from_camera(*cams[e], &eye)) {  // not a perspective frustum: keep the last eye
      eye = before;
      continue;
    }
    // Velocities by differences with the previous frame (0 on the first frame).
    const Eye& p = previous_eyes_[e];
    for (int k = 0; k < 3; ++k)
      eye.velocity[k] = ran_ && dt > 0 ? float((eye.position[k] - p.position[k]) / dt) : 0.0f;
    const std::array<double, 4> turn = turn_between(eye.orientation, p.orientation);
    const double len = std::sqrt(turn[0] * turn[0] + turn[1] * turn[1] + turn[2] * turn[2]);
    const double angle = 2 * std::atan2(len, std::abs(turn[3])) * kDeg;
    for (int k = 0; k < 3; ++k)
      eye.angular_velocity[k] =
          ran_ && dt > 0 && len > 0 ? float(turn[k] / len * (turn[3] < 0 ? -1.0 : 1.0) * angle / dt) : 0.0f;
    previous_eyes_[e] = eye;
    frame_.gaze[e] = gaze_.valid() ? gaze_->gaze(frame_number_, time_, *cams[e], e) : Gaze{};
  }
}

void Kit::run_frame(const ::osg::FrameStamp& stamp, const ::osg::Camera* fallback) {
  const std::uint32_t number = stamp.getFrameNumber();
  // This frame already ran: every cull after the first returns here without the mutex.
  if (completed_frame_.load(std::memory_order_acquire) == std::uint64_t(number) + 1) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (ran_ && number == frame_number_) return;
  const auto t0 = std::chrono::steady_clock::now();
  const double time = stamp.getSimulationTime();
  const double dt = ran_ ? std::max(0.0, time - time_) : 0.0;
  frame_number_ = number;
  time_ = time;
  read_eyes(fallback, dt);
  frame_.dt = float(dt);
  // The view cameras as they were last placed (views_ holds one per camera: no allocation).
  std::uint32_t view_count = 0;
  for (std::size_t i = 0; i < view_cameras_.size(); ++i) {
    View v = view_settings_[i];
    if (view_cameras_[i].valid() && view_from_camera(*view_cameras_[i], &v)) views_[view_count++] = v;
  }
  frame_.views = views_.data();
  frame_.view_count = view_count;
  // World transforms from each node's parent path.
  for (LodNode* n : nodes_) {
    if (!n || (n->static_ && n->placed_)) continue;
    n->placed_ = true;
    path_.clear();
    for (::osg::Node* p = n; p; p = p->getNumParents() ? p->getParent(0) : nullptr) {
      path_.push_back(p);
      if (path_.size() > 4096) break;  // a cycle guard; OSG graphs are DAGs
    }
    std::reverse(path_.begin(), path_.end());
    const ::osg::Matrixd m = ::osg::computeLocalToWorld(path_);
    // osg's row-vector layout is the column-major array transform_from_matrix takes.
    scheduler_->set_transform(n->id_, transform_from_matrix(m.ptr()));
  }
  const auto t1 = std::chrono::steady_clock::now();
  scheduler_->run_frame(frame_);
  ran_ = true;
  completed_frame_.store(std::uint64_t(number) + 1, std::memory_order_release);
  const auto t2 = std::chrono::steady_clock::now();
  acuity_ms_ = std::chrono::duration<double, std::milli>(t2 - t0).count();
  transforms_ms_ = std::chrono::duration<double, std::milli>(t1 - t0).count();
}

float Kit::quantise_fade(float fade) {
  if (!(fade < 1.0f)) return 1.0f;
  if (!(fade > 0.0f)) return 0.0f;
  return float(std::min(kFadeSteps - 1, int(fade * float(kFadeSteps)))) / float(kFadeSteps);
}

::osg::StateSet* Kit::fade_state(float fade, bool outgoing) const {
  const int i = int(std::lround(quantise_fade(fade) * float(kFadeSteps)));
  return fade_states_[outgoing ? 1 : 0][std::size_t(std::clamp(i, 0, kFadeSteps))].get();
}

}  // namespace acuity::osg
