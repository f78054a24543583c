// The geometry of a block: the frame loop's first pass (look_block), then per object the view
// lookup and the slip in its axes (sight, aim).
#include "tables.hpp"

namespace acuity {

// The first pass, for `count` consecutive objects from `first` and one eye: arithmetic only, no
// branches and no calls, so the compiler vectorises it. Camera-relative geometry subtracts in double
// first, so 1e7 m from the origin is exact. Free slots have radius 0 and come out Invalid.
ACUITY_SIMD_CLONES void Scheduler::Impl::look_block(const EyeCache& eye, std::uint32_t first,
                                                    std::uint32_t count, Block* out) const {
  const double* px = &position_[0][first];
  const double* py = &position_[1][first];
  const double* pz = &position_[2][first];
  const float* qx = &rotation_[0][first];
  const float* qy = &rotation_[1][first];
  const float* qz = &rotation_[2][first];
  const float* qw = &rotation_[3][first];
  const float* vx = &velocity_[0][first];
  const float* vy = &velocity_[1][first];
  const float* vz = &velocity_[2][first];
  const float* sx = &sphere_[0][first];
  const float* sy = &sphere_[1][first];
  const float* sz = &sphere_[2][first];
  const float* sr = &sphere_[3][first];
  const std::uint8_t* bias_tables = &bias_tables_[first];
  const double ex = eye.position[0], ey = eye.position[1], ez = eye.position[2];
  const float eye_test = eye.valid ? 0.0f : kNaN;  // NaN fails every object
  Block& b = *out;
  float* out_d = b.d;
  float* out_r = b.r;
  float* out_radius = b.radius_deg;
  float* out_ln = b.ln_diam;
  float* out_test = b.test;
  float rx[Block::kSize], ry[Block::kSize], rz[Block::kSize];
  for (std::uint32_t j = 0; j < count; ++j) {
    rx[j] = static_cast<float>(px[j] - ex);
    ry[j] = static_cast<float>(py[j] - ey);
    rz[j] = static_cast<float>(pz[j] - ez);
  }
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < count; ++j) {
    const Vec3 centre = rotate(qx[j], qy[j], qz[j], qw[j], Vec3{sx[j], sy[j], sz[j]});
    const Vec3 rel{rx[j] + centre.x, ry[j] + centre.y, rz[j] + centre.z};
    const float r = sr[j];
    const float qn = qx[j] * qx[j] + qy[j] * qy[j] + qz[j] * qz[j] + qw[j] * qw[j];
    const float bias_test = bias_tables[j] == kInvalidBias ? kNaN : 0.0f;
    // x - x is 0 for a finite x, NaN otherwise; one sum tests them all.
    const float nan_test = (rel.x - rel.x) + (rel.y - rel.y) + (rel.z - rel.z) + (vx[j] - vx[j]) +
                           (vy[j] - vy[j]) + (vz[j] - vz[j]) + (r - r) + bias_test + eye_test;
    // Every test folded into one comparison (the loop stays branch-free): r > 0, |q| = 1.
    const float margin = std::min(r, kUnitQuaternionRoom - std::abs(qn - 1.0f));
    const float test = nan_test + (margin > 0.0f ? 0.0f : kNaN);  // 0: valid
    out_d[j] = std::sqrt(dot(rel, rel));
    out_r[j] = r;
    out_test[j] = test;
    rx[j] = rel.x;
    ry[j] = rel.y;
    rz[j] = rel.z;
  }
  if (!perceptual()) return;  // Distance and ScreenSize need no angles
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < count; ++j) {
    const float radius_deg = angular_radius_deg(out_d[j], out_r[j]);
    out_radius[j] = radius_deg;
    out_ln[j] = ln_angular_diameter(radius_deg);
  }
  const Vec3 eye_velocity = eye.velocity, omega = eye.omega, forward = eye.forward;
  // Which motion the eye must follow to hold the object on the retina (image_to_track()):
  // measured, its motion in the world; else the slower of its motion in the world and in the head.
  const bool world_only = eye.gaze_moving;
  const Vec3 gaze = eye.gaze ? eye.gaze_dir : eye.forward;
  const float offset = eye.gaze ? config_.gaze_uncertainty_deg : config_.no_gaze_radius_deg;
  const float half_focal = 0.5f * eye.focal_px * kRad;
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < count; ++j) {
    const float inv_d = b.d[j] > 0.0f ? 1.0f / b.d[j] : 0.0f;
    const Vec3 u = inv_d * Vec3{rx[j], ry[j], rz[j]};
    const Vec3 v_rel = Vec3{vx[j], vy[j], vz[j]} - eye_velocity;
    const Vec3 image =
        image_to_track(kDeg * inv_d * (v_rel - dot(v_rel, u) * u), kDeg * cross(omega, u), world_only);
    const Vec3 to_eye = rotate(-qx[j], -qy[j], -qz[j], qw[j], -1.0f * u);  // the inverse rotation
    b.u[0][j] = u.x;
    b.u[1][j] = u.y;
    b.u[2][j] = u.z;
    b.image[0][j] = image.x;
    b.image[1][j] = image.y;
    b.image[2][j] = image.z;
    b.to_eye[0][j] = to_eye.x;
    b.to_eye[1][j] = to_eye.y;
    b.to_eye[2][j] = to_eye.z;
    b.nyquist[j] = nyquist_cpd(half_focal, dot(u, forward));
    b.e[j] = nearest_eccentricity(angle_deg(u, gaze), b.radius_deg[j], offset);
  }
}

// The second pass for one object: the view lookup and retinal slip, what branches.
Scheduler::Impl::Look Scheduler::Impl::sight(ObjectId id, const EyeCache& eye, const Block& b,
                                             std::uint32_t j, Sight* s) const {
  if (const Look state = b.state(j); state != Look::Ok) return state;
  s->d = b.d[j];
  s->r = b.r[j];
  s->focal_px = eye.focal_px;
  if (!perceptual()) return Look::Ok;
  s->radius_deg = b.radius_deg[j];
  s->diameter_deg = 2.0f * b.radius_deg[j];
  s->ln_diam = b.ln_diam[j];
  const ProfileCache& pc = profiles_[profile_of_[id]];
  const Profile& p = pc.profile;
  s->u = Vec3{b.u[0][j], b.u[1][j], b.u[2][j]};
  s->image = Vec3{b.image[0][j], b.image[1][j], b.image[2][j]};
  s->e = b.e[j];
  s->nyquist_cpd = b.nyquist[j];
  s->flags = eye.gaze ? std::uint8_t(0) : std::uint8_t(kFlagNoGaze);
  s->slip = retinal_slip(s->image, eye.gaze_moving, eye.gaze_velocity, config_.params);
  // The lookup cell of the direction from the object to the eye; aim() picks the nearest view.
  s->to_eye = Vec3{b.to_eye[0][j], b.to_eye[1][j], b.to_eye[2][j]};
  s->cand = lookup_candidates(p, b, j);
  ACUITY_PREFETCH(s->cand);
  return Look::Ok;
}

// The candidate views' directions prefetched (between sight() and aim(), a pass apart).
void Scheduler::Impl::prefetch_views(ObjectId id, const Sight& s) const {
  const Profile& p = profiles_[profile_of_[id]].profile;
  for (std::uint32_t k = 0; k < kLookupCandidates; ++k) ACUITY_PREFETCH(&p.views[s.cand[k]]);
}

// The profile's view nearest to the direction from the object to the eye, and the retinal slip in
// that snapshot's image axes, so it meets the profile's orientations in one frame.
void Scheduler::Impl::aim(ObjectId id, Sight* s) const {
  s->view = aim(id, s->cand, s->to_eye, s->slip, &s->vx, &s->vy);
  s->moving = s->vx != 0.0f || s->vy != 0.0f;
}

void object_retinal_slip(const float world[3], const float turn[3], const float* gaze_velocity,
                         const ModelParams& p, float slip[3]) {
  const Vec3 w{world[0], world[1], world[2]}, t{turn[0], turn[1], turn[2]};
  const bool tracked = gaze_velocity != nullptr;
  const Vec3 gaze = tracked ? Vec3{gaze_velocity[0], gaze_velocity[1], gaze_velocity[2]} : Vec3{0, 0, 0};
  const Vec3 s = internal::retinal_slip(internal::image_to_track(w, t, tracked), tracked, gaze, p);
  slip[0] = s.x;
  slip[1] = s.y;
  slip[2] = s.z;
}

}  // namespace acuity
