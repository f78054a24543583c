// Views beyond the eyes (docs/design.md section 6): the frame's shadow and secondary views, and per
// view class each object's level, the finer need of the class's views winning.
#include "geometry.hpp"

namespace acuity {

void Scheduler::Impl::begin_views(const Frame& frame) {
  view_count_ = 0;
  const std::uint32_t given = frame.views ? std::min(frame.view_count, config_.max_views) : 0u;
  for (std::uint32_t i = 0; i < given; ++i) {
    const View& v = frame.views[i];
    if (v.view_class >= config_.max_view_classes) continue;
    ViewCache& c = views_[view_count_++];
    const bool ortho = v.projection == ViewProjection::Orthographic;
    // The pose (and, perspective, the projection) as an eye's, still and without gaze.
    Eye e;
    std::copy(v.position, v.position + 3, e.position);
    std::copy(v.orientation, v.orientation + 4, e.orientation);
    if (!ortho) std::copy(v.fov_deg, v.fov_deg + 4, e.fov_deg);  // else the default's (unused)
    std::copy(v.viewport, v.viewport + 2, e.viewport);
    pose_eye(e, &c.eye);
    c.eye.gaze = c.eye.gaze_moving = false;
    c.eye.gaze_dir = c.eye.forward;
    c.eye.gaze_velocity = Vec3{0, 0, 0};
    for (int k = 0; k < 3; ++k) c.to_view[k] = -c.eye.rotation[k];
    c.to_view[3] = c.eye.rotation[3];
    const float w = static_cast<float>(v.viewport[0]), h = static_cast<float>(v.viewport[1]);
    const float width = v.extent_m[1] - v.extent_m[0], height = v.extent_m[2] - v.extent_m[3];
    c.texels_per_m = std::max(w / width, h / height);
    const float tan_l = std::tan(v.fov_deg[0] * kRad), tan_r = std::tan(v.fov_deg[1] * kRad);
    const float tan_u = std::tan(v.fov_deg[2] * kRad), tan_d = std::tan(v.fov_deg[3] * kRad);
    c.focal_px = std::max(w / (tan_r - tan_l), h / (tan_u - tan_d));
    c.valid = c.eye.valid &&
              (ortho ? width > 0 && height > 0 && std::isfinite(c.texels_per_m) : std::isfinite(c.focal_px));
    c.eye.valid = c.valid;
    c.pixel_error = v.pixel_error;
    c.view_class = v.view_class;
    c.rule = ortho ? ViewRule::Footprint : v.rule;
    c.projection = v.projection;
  }
}

// Object id's Footprint level in view v (ViewRule::Footprint documents the bound): the coarsest
// level, from the finest up, whose geometric error covers at most pixel_error texels.
std::uint8_t Scheduler::Impl::footprint_level(const ViewCache& v, ObjectId id) const {
  const int p = profile_of_[id];
  const std::uint32_t K = level_count_[p];
  const float q[4] = {rotation_[0][id], rotation_[1][id], rotation_[2][id], rotation_[3][id]};
  const Vec3 centre = rotate(q, Vec3{sphere_[0][id], sphere_[1][id], sphere_[2][id]});
  const Vec3 rel{static_cast<float>(position_[0][id] - v.eye.position[0]) + centre.x,
                 static_cast<float>(position_[1][id] - v.eye.position[1]) + centre.y,
                 static_cast<float>(position_[2][id] - v.eye.position[2]) + centre.z};
  const float r = sphere_[3][id];
  float texels_per_m = v.texels_per_m;  // of geometric error
  if (v.projection == ViewProjection::Perspective) {
    const Vec3 in_view = rotate(v.to_view, rel);
    const float depth = -in_view.z, nearest = depth - r;
    if (depth + r <= 0.0f) return static_cast<std::uint8_t>(K - 1);  // wholly behind: not in the view
    if (!(nearest > 0.0f)) return 0;                                 // reaching the view's plane
    const float a = (std::abs(in_view.x) + r) / nearest, b = (std::abs(in_view.y) + r) / nearest;
    texels_per_m = v.focal_px / nearest * std::sqrt(1.0f + a * a + b * b);
  }
  const float* error_size = &error_size_[std::size_t(p) * kMaxLevels];  // 2 x error [radii]
  std::uint32_t level = 0;
  while (level + 1 < K && error_size[level + 1] * r * texels_per_m <= v.pixel_error) ++level;
  return static_cast<std::uint8_t>(level);
}

// One view's levels for `count` objects from `first` (free slots: 0).
void Scheduler::Impl::view_levels(const ViewCache& v, std::uint32_t first, std::uint32_t n,
                                  std::uint8_t* out) const {
  Block b;
  look_block(v.eye, first, n, &b);  // validity (an invalid view fails every object), and AsEye's geometry
  for (std::uint32_t j = 0; j < n; ++j) {
    const ObjectId id = first + j;
    out[j] = 0;
    if (profile_of_[id] < 0) continue;
    if (v.rule == ViewRule::AsEye) {
      Sight s;
      const Look look = sight(id, v.eye, b, j, &s);
      if (look == Look::Ok && perceptual()) aim(id, &s);
      out[j] = evaluate(id, look, s, nullptr, nullptr).fine;
    } else if (b.state(j) == Look::Invalid) {
      out[j] = static_cast<std::uint8_t>(
          std::min<std::uint32_t>(config_.fallback_level, level_count_[profile_of_[id]] - 1u));
    } else {
      out[j] = footprint_level(v, id);
    }
  }
}

// Per block of the range, every class's levels: the finest of its views', within the clamps; the
// coarsest allowed where no view of the class looked this frame.
void Scheduler::Impl::decide_views(std::uint32_t first, std::uint32_t end) {
  const std::uint32_t classes = config_.max_view_classes;
  const std::size_t stride = config_.max_objects;
  constexpr std::uint8_t kNone = 255;
  for (std::uint32_t start = first; start < end; start += kBlock) {
    const std::uint32_t n = std::min(kBlock, end - start);
    for (std::uint32_t c = 0; c < classes; ++c) std::fill_n(&view_levels_[c * stride + start], n, kNone);
    std::uint8_t levels[kBlock];
    for (std::uint32_t i = 0; i < view_count_; ++i) {
      view_levels(views_[i], start, n, levels);
      std::uint8_t* to = &view_levels_[views_[i].view_class * stride + start];
      for (std::uint32_t j = 0; j < n; ++j) to[j] = std::min(to[j], levels[j]);
    }
    for (std::uint32_t c = 0; c < classes; ++c) {
      std::uint8_t* to = &view_levels_[c * stride + start];
      for (std::uint32_t j = 0; j < n; ++j) {
        const std::uint8_t hi = max_level_[start + j], lo = std::min(min_level_[start + j], hi);
        to[j] = to[j] == kNone ? hi : std::clamp(to[j], lo, hi);
      }
    }
  }
}

}  // namespace acuity
