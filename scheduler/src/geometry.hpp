#pragma once
// One eye's view of objects (scheduler/src only): the eye as a frame sees it, one object's sight,
// a block's geometry (look_block()), and the retinal slip and view helpers the choosers share.
#include "runtime_math.hpp"

namespace acuity {

struct Scheduler::Impl::EyeCache {
  double position[3];
  float rotation[4];
  Vec3 forward;   // world
  Vec3 velocity;  // world [m/s]
  Vec3 omega;     // head angular velocity, world [rad/s]
  bool valid;
  bool gaze;                      // a usable gaze this frame
  Vec3 gaze_dir;                  // world, unit
  bool gaze_moving;               // measured gaze velocity
  Vec3 gaze_velocity;             // world tangent velocity of the gaze direction [deg/s]
  float focal_px;                 // horizontal focal length [px]
  float center_right, center_up;  // tangent offsets of the projection centre (off-axis frusta)
  // The eye's velocity, the head's angular velocity and the gaze's motion are last frame's, bit for
  // bit (begin_frame): retinal slips then change only as the objects' directions do, so holds of
  // the view (Memo::Hold) can last. Where they change, every image's slip moves with them and a hold
  // rarely outlives its frame: none is set (a hold never changes a decision, only its cost).
  bool steady;
};

// A view beyond the eyes (View) as a frame uses it (views.cpp): its pose as an eye without gaze (for
// AsEye, and the pose and validity of every view), and what its footprint reads.
struct Scheduler::Impl::ViewCache {
  EyeCache eye;
  float to_view[4];    // world to view: the inverse of the eye's rotation
  float texels_per_m;  // orthographic: the larger of the map's texels per metre across either axis
  float focal_px;      // perspective: the larger of the two focal lengths [px]
  float pixel_error;   // Footprint's allowance [texels or px]
  std::uint32_t view_class;
  ViewRule rule;  // AsEye only for perspective views
  ViewProjection projection;
  bool valid;
};

// One eye's view of one object: everything the rules read.
struct Scheduler::Impl::Sight {
  float d, r;  // distance to the sphere's centre, radius [m]
  float radius_deg, diameter_deg, ln_diam;
  float focal_px;
  // Perceptual and Reddy only:
  Vec3 u;                     // unit direction eye -> centre, world
  Vec3 image, slip;           // image_to_track() and retinal angular velocity [deg/s], world tangent vectors
  Vec3 to_eye;                // unit direction centre -> eye, object space
  float e;                    // eccentricity [deg]
  float nyquist_cpd;          // the display's limit in the object's direction
  const std::uint16_t* cand;  // the lookup cell's candidate views
  std::uint32_t view;         // the nearest of them
  float vx, vy;               // slip in the view's image axes [deg/s]
  bool moving;
  std::uint8_t flags;  // kFlagNoGaze
};

// One eye's view of up to kSize consecutive objects, structure of arrays (the frame loop's first pass).
struct Scheduler::Impl::Block {
  static constexpr std::uint32_t kSize = kBlock;
  float d[kSize], r[kSize], radius_deg[kSize], ln_diam[kSize];
  // Perceptual and Reddy only:
  float test[kSize];  // 0 where the input is valid (NaN otherwise)
  float e[kSize], nyquist[kSize];
  float u[3][kSize];       // unit direction eye -> centre, world
  float image[3][kSize];   // image_to_track() [deg/s], world tangent vector
  float to_eye[3][kSize];  // unit direction centre -> eye, object space (the view lookup)
  Look state(std::uint32_t j) const {
    return !(test[j] == 0.0f) ? Look::Invalid : !(d[j] > r[j]) ? Look::Inside : Look::Ok;
  }
  Vec3 to_eye_at(std::uint32_t j) const { return {to_eye[0][j], to_eye[1][j], to_eye[2][j]}; }
};

// One block's choices, both eyes combined (the finer need wins), before clamps and hysteresis.
struct Scheduler::Impl::Decisions {
  std::uint8_t fine[kBlock], coarse[kBlock], flags[kBlock];
};

namespace internal {
// What look_block() computes per object and stands_at_rest() at the ends of a range of poses, written
// once so that the two compute alike.
// ln of the angular diameter [ln deg] of a sphere of angular radius radius_deg [deg].
[[gnu::always_inline]] inline float ln_angular_diameter(float radius_deg) {
  return ln_positive(2.0f * radius_deg);
}
// The eccentricity [deg] of a sphere's nearest point: its centre angle_deg from the gaze, less its
// angular radius and the gaze's uncertainty offset_deg; 0 where the gaze falls inside.
[[gnu::always_inline]] inline float nearest_eccentricity(float angle_deg, float radius_deg,
                                                         float offset_deg) {
  return std::max(0.0f, angle_deg - radius_deg - offset_deg);
}
// The display's Nyquist frequency [cpd] in a direction whose cosine to the view axis is cos_phi
// (clamped to [0.05, 1]; pixels subtend less off axis): half_focal / cos^2, half_focal = focal
// length [px] / 2 in radians per degree.
constexpr float kLeastViewCosine = 0.05f;
[[gnu::always_inline]] inline float nyquist_cpd(float half_focal, float cos_phi) {
  const float c = std::clamp(cos_phi, kLeastViewCosine, 1.0f);
  return half_focal / (c * c);
}

// The angular velocity [deg/s, world tangent vector] an eye must follow to hold an object still on
// the retina, from the object's direction's velocity in the world (`world`: its own motion and the
// eye's translation) and the head's rotation at that direction (`turn`: omega x u; in the head the
// direction moves at world - turn). The vestibulo-ocular reflex cancels the head's rotation, so a
// still object stays still on the retina of a turning head: with a measured gaze the slip is
// world - the gaze's world velocity (`world_only`). Without one, the eye may fixate the world (VOR)
// or ride with a head that follows the object: the slower of the two motions, whose speed is above
// neither case's. Its direction is that case's: an orientation across it may see less blur under
// the other case (docs/design.md section 3 counts the decisions this changed).
[[gnu::always_inline]] inline Vec3 image_to_track(Vec3 world, Vec3 turn, bool world_only) {
  const Vec3 in_head = world - turn;
  return world_only || dot(world, world) <= dot(in_head, in_head) ? world : in_head;
}
// Retinal slip of an image the eye must follow at `image` [deg/s] (image_to_track()): against the
// measured gaze motion, or Daly's pursuit model.
inline Vec3 retinal_slip(Vec3 image, bool gaze_moving, Vec3 gaze_velocity, const ModelParams& params) {
  if (gaze_moving) return image - gaze_velocity;
  const float vi = length(image);
  return vi > 0 ? (daly_retinal_velocity(vi, params) / vi) * image : Vec3{0, 0, 0};
}
// Whether retinal_slip() is 0 (Daly's pursuit leaves at least the drift of any moving image), without
// branches: the image moves with the measured gaze (`tracked`: the gaze velocity, or 0 without one).
[[gnu::always_inline]] inline bool no_retinal_slip(Vec3 image, Vec3 tracked) {
  return (image.x == tracked.x) & (image.y == tracked.y) & (image.z == tracked.z);
}
// Of a lookup cell's candidates, the view nearest to the direction to the eye (the first on ties).
inline std::uint32_t nearest_view(const Profile& p, const std::uint16_t* cand, Vec3 to_eye) {
  std::uint32_t view = cand[0];
  float best = -2.0f;
  for (std::uint32_t k = 0; k < kLookupCandidates; ++k) {
    const float dd = dot(to_eye, load(p.views[cand[k]].direction));
    view = dd > best ? cand[k] : view;
    best = std::max(best, dd);
  }
  return view;
}
// The slip [deg/s] in a view's image axes (right, up; object space, q the object's rotation): there
// it meets the profile's orientations. 0 for no slip.
inline void slip_in_view(Vec3 slip, const float q[4], const float* right, const float* up, float* vx,
                         float* vy) {
  *vx = *vy = 0;
  if (slip.x == 0.0f && slip.y == 0.0f && slip.z == 0.0f) return;
  *vx = dot(slip, rotate(q, load(right)));
  *vy = dot(slip, rotate(q, load(up)));
}
}  // namespace internal

// The lookup cell's candidate views of block b's j-th object: of the direction from it to the eye.
inline const std::uint16_t* Scheduler::Impl::lookup_candidates(const Profile& p, const Block& b,
                                                               std::uint32_t j) {
  const float to_eye[3] = {b.to_eye[0][j], b.to_eye[1][j], b.to_eye[2][j]};
  return p.lookup + cube_cell(to_eye, p.meta.lookup_resolution) * kLookupCandidates;
}

}  // namespace acuity
