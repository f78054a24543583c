// The decision memory: the pose history a rest is measured from, rests (set, checked, decided at
// rest) and holds of the view (docs/design.md section 6).
#include "memory.hpp"

namespace acuity {

void Scheduler::Impl::Memo::observe(std::uint32_t frame, const EyeCache* eye) {
  Pose now{};
  const auto zero = [](Vec3 v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; };
  // A still image stays still only while nothing moves it: no eye velocity, no gaze velocity. The
  // head may turn: without a measured gaze the eye may hold the world (image_to_track()), so a still
  // object's image stays still on the retina; the turn moves the gaze and the view axis, which
  // `turned` measures and a rest bounds (stands_at_rest()).
  usable = eye && eye->valid && zero(eye->velocity) && !eye->gaze_moving;
  if (usable) {
    now = {{eye->position[0], eye->position[1], eye->position[2]},
           eye->gaze_dir,
           eye->forward,
           eye->focal_px,
           eye->gaze,
           true};
  }
  pose[frame % kPoses] = now;
  const auto turn_deg = [](Vec3 a, Vec3 b) {  // in double: the angle between the floats as they are
    const double x = double(a.y) * b.z - double(a.z) * b.y, y = double(a.z) * b.x - double(a.x) * b.z,
                 z = double(a.x) * b.y - double(a.y) * b.x;
    const double c = double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z;
    return std::atan2(std::sqrt(x * x + y * y + z * z), c) * (180.0 / std::numbers::pi);
  };
  recent_m = recent_deg = 0.0f;
  for (std::uint32_t k = 0; k < kPoses; ++k) {
    const Pose& p = pose[k];
    if (!(usable && p.usable && p.gaze_valid == now.gaze_valid && p.focal_px == now.focal_px)) {
      moved[k] = turned[k] = kInf;
      continue;
    }
    double dd = 0;
    for (int c = 0; c < 3; ++c) dd += (now.position[c] - p.position[c]) * (now.position[c] - p.position[c]);
    moved[k] = static_cast<float>(std::sqrt(dd) * (1.0 + kRoomPose));
    turned[k] = static_cast<float>(std::max(turn_deg(now.gaze, p.gaze), turn_deg(now.forward, p.forward)) +
                                   kRoomPose);
    if ((frame - k) % kPoses < 4) {  // frame's and the 3 before it
      recent_m = std::max(recent_m, moved[k]);
      recent_deg = std::max(recent_deg, turned[k]);
    }
  }
}

// Whether the memo of object id keeps deciding while the eye moves at most m [m] and the gaze and head
// turn at most t [deg]: each input the memo tests (table_inputs()), computed as the frame loop
// computes it at the ends of its range, stays inside the memo's box. The direction to the object
// turns by at most asin(m / d); the angular radius and x are monotone in d (a table step of room for
// the fast functions' ulps); the eccentricity cell and its weight are monotone in e.
bool Scheduler::Impl::stands_at_rest(const Memo& memo, ObjectId id, const RestProbe& h, float m,
                                     float t) const {
  const float room_d = kRoomRelative * h.d;  // float error of the distance as computed
  const float d_near = h.d - m - room_d, d_far = h.d + m + room_d;
  if (!(d_near > h.r) || !(m + room_d < h.d)) return false;
  const float alpha = std::asin((m + room_d) / h.d);  // [rad]
  if (!(alpha + kRoomRelative < h.view_margin)) return false;
  const float radius_near = angular_radius_deg(d_near, h.r), radius_far = angular_radius_deg(d_far, h.r);
  // x: one table step of room each side (the box's ends past the entries need none).
  const std::int32_t x_near = size_steps_above(ln_angular_diameter(radius_near)),
                     x_far = size_steps_above(ln_angular_diameter(radius_far));
  if (!(memo.x_from[id] == kLeastEntry || x_far > memo.x_from[id])) return false;
  if (!(memo.x_to[id] == Stand::kNoHigh || x_near < memo.x_to[id])) return false;
  // Eccentricity: at the nearest and the farthest angle to the gaze, each with room for rounding.
  const float turn = kDeg * alpha + t;
  const float room_e = kRoomEccentricity + kRoomRelative * (h.gaze_angle + radius_near);
  const Cell low = e_cell<kStillE>(nearest_eccentricity(h.gaze_angle - turn - room_e, radius_near, h.offset));
  const Cell high = e_cell<kStillE>(nearest_eccentricity(h.gaze_angle + turn + room_e, radius_far, h.offset));
  const std::uint32_t cell = memo.key[id] & 31u;
  if (low.j != cell || high.j != cell) return false;
  if (!(float(memo.w_from[id]) <= low.w * kWeightSteps && high.w * kWeightSteps <= float(memo.w_to[id])))
    return false;
  // The bands shown: f_lo / diameter <= Nyquist < f_hi / diameter over the range of both.
  const double phi_low = std::max(0.0, double(h.forward_angle) - turn - kRoomAngle) * kRad,
               phi_high = std::min(180.0, double(h.forward_angle) + turn + kRoomAngle) * kRad;
  const float nyquist_least =
                  nyquist_cpd(h.half_focal, float(std::cos(phi_low)) + kRoomCosine) * (1.0f - kRoomRelative),
              nyquist_most =
                  nyquist_cpd(h.half_focal, float(std::cos(phi_high)) - kRoomCosine) * (1.0f + kRoomRelative);
  const float inv_diam_most = 1.0f / (2.0f * radius_far) * (1.0f + kRoomRelative),
              inv_diam_least = 1.0f / (2.0f * radius_near) * (1.0f - kRoomRelative);
  return memo.f_lo[id] * inv_diam_most <= nyquist_least && memo.f_hi[id] * inv_diam_least > nyquist_most;
}

void Scheduler::Impl::end_rests(ObjectId id) {
  if (memos_)
    for (int i = 0; i < 2; ++i) memos_[i].end_rest(id);
}

namespace {
// How far [rad] a direction d (object space) may turn before it leaves its lookup cell: a cube face's
// coordinate moves at most sqrt(6) per radian (|grad (v_a / v_major)| <= sqrt(1 + s^2) / |v_major|).
// With `views` (kLookupCandidates of them), before another of them is nearer than the nearest: a dot
// product moves at most one per radian.
float view_margin(const float d[3], std::uint32_t resolution, const float (*views)[3] = nullptr) {
  const float ax = std::abs(d[0]), ay = std::abs(d[1]), az = std::abs(d[2]);
  const bool on_x = ax >= ay && ax >= az, on_y = !on_x && ay >= az;  // as cube_cell()
  const double major = on_x ? ax : on_y ? ay : az;
  const double u = on_x ? d[1] : on_y ? d[2] : d[0], v = on_x ? d[2] : on_y ? d[0] : d[1];
  const double half = 0.5 * resolution;
  double edge = 1.0;  // the least distance to a cell's edge, in cells
  for (const double s : {u, v}) {
    const double at = s / major * half + half;
    edge = std::min({edge, at - std::floor(at), std::floor(at) + 1.0 - at});
  }
  double margin = edge / half / std::sqrt(6.0);
  if (views) {
    double dots[kLookupCandidates];
    std::uint32_t best = 0;
    for (std::uint32_t k = 0; k < kLookupCandidates; ++k) {
      dots[k] = double(d[0]) * views[k][0] + double(d[1]) * views[k][1] + double(d[2]) * views[k][2];
      if (dots[k] > dots[best]) best = k;
    }
    for (std::uint32_t k = 0; k < kLookupCandidates; ++k)  // another view (a candidate may repeat)
      if (std::memcmp(views[k], views[best], sizeof views[k]) != 0)
        margin = std::min(margin, 0.5 * (dots[best] - dots[k]));
  }
  return static_cast<float>(margin) - kRoomRelative;  // the rounding of the direction as the loop computes it
}
}  // namespace

// Sets object id's rest for one eye from its geometry now (block b's j-th), where its memo decides it
// this frame and it does not move: the wider of two tries stands_at_rest() confirms, else none.
void Scheduler::Impl::set_rest(const EyeCache& eye, Memo& memo, ObjectId id, const Block& b,
                               std::uint32_t j) const {
  memo.rest_frame[id] = frame_;
  memo.end_rest(id);
  if (velocity_[0][id] != 0.0f || velocity_[1][id] != 0.0f || velocity_[2][id] != 0.0f) return;
  if ((memo.key[id] & Memo::kThroughView) && (memo.view_key[id] & 1u)) return;  // a moving image's
  if (!(memo.recent_m < b.d[j] * (1.0f / 256))) return;  // the eye moves too far: none would last
  const Vec3 u{b.u[0][j], b.u[1][j], b.u[2][j]};
  const Vec3 f = eye.forward;
  const double cos_forward = double(u.x) * f.x + double(u.y) * f.y + double(u.z) * f.z;
  RestProbe h{b.d[j],
              b.r[j],
              angle_deg(u, eye.gaze ? eye.gaze_dir : eye.forward),
              static_cast<float>(std::acos(std::clamp(cos_forward, -1.0, 1.0)) * (180.0 / std::numbers::pi)),
              kInf,
              0.5f * eye.focal_px * kRad,
              eye.gaze ? config_.gaze_uncertainty_deg : config_.no_gaze_radius_deg};
  if (memo.key[id] & Memo::kThroughView) {
    const Profile& p = profiles_[profile_of_[id]].profile;
    const float to_eye[3] = {b.to_eye[0][j], b.to_eye[1][j], b.to_eye[2][j]};
    float views[kLookupCandidates][3];
    const std::uint16_t* cand = lookup_candidates(p, b, j);
    for (std::uint32_t k = 0; k < kLookupCandidates; ++k)
      std::memcpy(views[k], p.views[cand[k]].direction, sizeof views[k]);
    h.view_margin = view_margin(to_eye, p.meta.lookup_resolution,
                                config_.view_blend == ViewBlend::Max3 ? nullptr : views);
  }
  // Wide, then narrower, but never narrower than the eye's recent moves (it would leave at once):
  // four times them, then (the last try) half as much again. Each try's m and t are at most the
  // one's before, and stands_at_rest() fails every wider box where it fails a narrower one (each of
  // its tests widens with m and t): where the eye has moved lately, the narrowest is tried first,
  // and where it fails (an eye that keeps turning), no other is. A still eye's widest mostly stands.
  constexpr float kShares[] = {1.0f / 64, 1.0f / 1024, 1.0f / (1 << 20)};
  constexpr std::size_t kTries = std::size(kShares);
  float m[kTries], t[kTries];
  for (std::size_t k = 0; k < kTries; ++k) {
    const float recent = k + 1 == kTries ? 1.5f : 4.0f;
    m[k] = std::max(kShares[k] * h.d, recent * memo.recent_m);
    t[k] = std::max(recent * memo.recent_deg, kDeg * m[k] / h.d);
  }
  const bool moved_lately = !memo.still();  // every turn has kRoomPose added: still() compares with it
  if (moved_lately && !stands_at_rest(memo, id, h, m[kTries - 1], t[kTries - 1])) return;
  for (std::size_t k = 0; k < kTries; ++k) {
    if (k > 0 && m[k] == m[k - 1] && t[k] == t[k - 1]) continue;  // the box before, which failed
    if ((moved_lately && k + 1 == kTries) || stands_at_rest(memo, id, h, m[k], t[k])) {
      memo.rest_m[id] = m[k];
      memo.rest_deg[id] = t[k];
      return;
    }
  }
}

// A block whose objects are nearly all at rest (the eye within each one's rest, every eye): those
// decided from their memos, the few runs of others through the frame loop. Returns false, deciding
// nothing, where more than kMostRuns runs are not at rest (the whole block's passes cost less then).
bool Scheduler::Impl::rest_mask(std::uint32_t first, std::uint32_t n, std::uint32_t* at_rest) const {
  for (std::uint32_t j = 0; j < n; ++j) at_rest[j] = 1;
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Memo& m = memos_[i];
    const std::uint32_t* since = &m.rest_frame[first];
    const float *rest_m = &m.rest_m[first], *rest_deg = &m.rest_deg[first];
    const float *moved = m.moved, *turned = m.turned;
    const std::uint32_t frame = frame_;
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t pose = since[j] % Memo::kPoses;
      at_rest[j] &= std::uint32_t(frame - since[j] < Memo::rest_frames(first + j)) &
                    std::uint32_t(moved[pose] <= rest_m[j]) & std::uint32_t(turned[pose] <= rest_deg[j]);
    }
  }
  std::uint32_t runs = 0, before = 1, restless = 0;  // runs of objects not at rest, and objects
  for (std::uint32_t j = 0; j < n; ++j) {
    runs += (at_rest[j] ^ 1u) & before;
    restless += at_rest[j] ^ 1u;
    before = at_rest[j];
  }
  return runs <= kMostRestlessRuns && restless <= kMostRestless;
}

// The per-object arrays the frame loop reads of the objects of a block not at rest (rest_mask()).
void Scheduler::Impl::prefetch_restless(std::uint32_t first, std::uint32_t n,
                                        const std::uint32_t* at_rest) const {
  for (std::uint32_t j = 0; j < n; ++j) {
    if (at_rest[j]) continue;
    const ObjectId id = first + j;
    for (int k = 0; k < 3; ++k) {
      ACUITY_PREFETCH(&position_[k][id]);
      ACUITY_PREFETCH(&previous_position_[k][id]);
      ACUITY_PREFETCH(&velocity_[k][id]);
    }
    for (int k = 0; k < 4; ++k) {
      ACUITY_PREFETCH(&rotation_[k][id]);
      ACUITY_PREFETCH(&sphere_[k][id]);
    }
    ACUITY_PREFETCH(&bias_tables_[id]);
    ACUITY_PREFETCH(&explicit_velocity_[id]);
    for (std::uint32_t i = 0; i < eye_count_; ++i) {
      const Memo& m = memos_[i];
      ACUITY_PREFETCH(&m.key[id]);
      ACUITY_PREFETCH(&m.x_from[id]);
      ACUITY_PREFETCH(&m.x_to[id]);
      ACUITY_PREFETCH(&m.w_from[id]);
      ACUITY_PREFETCH(&m.w_to[id]);
      ACUITY_PREFETCH(&m.f_lo[id]);
      ACUITY_PREFETCH(&m.f_hi[id]);
      ACUITY_PREFETCH(&m.view_key[id]);
    }
  }
}

void Scheduler::Impl::decide_at_rest(std::uint32_t first, std::uint32_t n, const std::uint32_t* at_rest,
                                     Decisions* out) {
  std::uint8_t* rest = &rest_[first];
  for (std::uint32_t j = 0; j < n; ++j) rest[j] = static_cast<std::uint8_t>(at_rest[j]);
  // The memo's decision, both eyes: the finer need wins.
  std::memcpy(out->fine, &memos_[0].fine[first], n);
  std::memcpy(out->coarse, &memos_[0].coarse[first], n);
  for (std::uint32_t i = 1; i < eye_count_; ++i) {
    const std::uint8_t *fine = &memos_[i].fine[first], *coarse = &memos_[i].coarse[first];
    for (std::uint32_t j = 0; j < n; ++j) {
      out->fine[j] = std::min(out->fine[j], fine[j]);
      out->coarse[j] = std::min(out->coarse[j], coarse[j]);
    }
  }
  std::uint8_t flags = 0;
  for (std::uint32_t i = 0; i < eye_count_; ++i)
    flags = static_cast<std::uint8_t>(flags | (eyes_[i].gaze ? 0 : kFlagNoGaze));
  std::memset(out->flags, flags, n);
  for (std::uint32_t j = 0; j < n;) {
    if (at_rest[j]) {
      ++j;
      continue;
    }
    std::uint32_t k = j;
    while (k < n && !at_rest[k]) ++k;
    Block blocks[2];
    Decisions run{};
    derive_velocities(first + j, k - j);
    for (std::uint32_t i = 0; i < eye_count_; ++i) look_block(eyes_[i], first + j, k - j, &blocks[i]);
    choose_tabulated(first + j, k - j, blocks, &run);
    std::copy(run.fine, run.fine + (k - j), out->fine + j);
    std::copy(run.coarse, run.coarse + (k - j), out->coarse + j);
    std::copy(run.flags, run.flags + (k - j), out->flags + j);
    j = k;
  }
}

// The holds of a block's memos made through the view (their keys, prefetched a block earlier, say
// which): the others are never read.
void Scheduler::Impl::prefetch_holds(std::uint32_t first) const {
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Memo& m = memos_[i];
    if (!m.any_hold) continue;
    std::uint8_t through[Block::kSize];  // listed without branches (which ones is unpredictable)
    std::uint32_t count = 0;
    for (std::uint32_t j = 0; j < Block::kSize; ++j) {
      through[count] = static_cast<std::uint8_t>(j);
      count += (m.key[first + j] & Memo::kThroughView) != 0;
    }
    for (std::uint32_t k = 0; k < count; ++k) {
      ACUITY_PREFETCH(&m.hold[first + through[k]]);
      ACUITY_PREFETCH(&m.hold[first + through[k]].e_to);
    }
  }
}

// Sets object id's hold (Memo::Hold) for the decision through its view just made or confirmed
// (block b's j-th; o its probe, with its cells where it moves; cand its lookup cell's candidates):
// the widest turn of the direction to the eye, change of slip and range of eccentricity within
// which view_key and speed_key stay, less room for the rounding of each as the frame loop computes
// it (a ten-thousandth of the quantity or of its cell). None where the image slips but
// not in the view's axes (then any change of slip may move it).
void Scheduler::Impl::hold_view(Memo& memo, ObjectId id, const ProfileCache& pc, const Probe& o,
                                const std::uint16_t* cand, const Block& b, std::uint32_t j, bool quartered,
                                bool still) const {
  Memo::Hold& h = memo.hold[id];
  h.turn = -1.0f;
  if (!o.moving && !still) return;
  const Profile& p = pc.profile;
  const Vec3 to_eye = b.to_eye_at(j);
  const float d[3] = {to_eye.x, to_eye.y, to_eye.z};
  // Moving, the nearest view's image axes carry the slip (Max3 too): it must stay the nearest.
  float views[kLookupCandidates][3];
  for (std::uint32_t k = 0; k < kLookupCandidates; ++k)
    std::memcpy(views[k], p.views[cand[k]].direction, sizeof views[k]);
  const bool cell_only = config_.view_blend == ViewBlend::Max3 && !o.moving;
  const float margin = std::min(view_margin(d, p.meta.lookup_resolution, cell_only ? nullptr : views), 0.5f);
  if (!(margin > 0.0f)) return;
  float reach = kInf, e_from = -kInf, e_to = kInf;
  if (o.moving) {
    // Each orientation's speed |vx cos t + vy sin t| stays in its cell (and quarter) while (vx, vy)
    // moves less than its distance to their ends, and (vx, vy) stays off 0 within its length.
    const float floor = pre_->floor_velocity, v0 = pre_->speed_offset;
    const float length_v = std::sqrt(o.vx * o.vx + o.vy * o.vy);
    float room = length_v * (1.0f - kRoomSpeed);
    const std::uint32_t T = p.meta.orientation_count;
    for (std::uint32_t t = 0; t < T; ++t) {
      const float u = std::abs(o.vx * pc.cos_t[t] + o.vy * pc.sin_t[t]);
      const std::uint32_t cell = o.speed_j[t];
      const float lo = floor * power_of_two(cell), g_top = lo / (3.0f * lo + 2.0f * v0);
      // The speed at weight w of the cell [lo, 2 lo] (speed_cell()'s weight inverted).
      const auto at = [&](float w) {
        const float g = w * g_top;
        return (lo * (1.0f + g) + 2.0f * g * v0) / (1.0f - g);
      };
      float w_from, w_to;  // past the grid's first and last cells, the ends are open
      weight_range(quartered, o.speed_w[t], &w_from, &w_to);
      const float lower = w_from == 0.0f ? (cell == 0 ? -kInf : lo) : at(w_from);
      const float upper = w_to == 1.0f ? (cell == kMovingS - 2 ? kInf : 2.0f * lo) : at(w_to);
      const float slack = kRoomSpeed * std::max(u, floor) + kRoomRelative * length_v;
      room = std::min(room, std::min(u - lower, upper - u) - slack);
    }
    if (!(room > 0.0f)) return;
    // (vx, vy) = the slip on the view's right and up axes (object space, rotated by the object's
    // rotation, which preserves them): it moves at most the largest singular value of the two
    // times the slip's move.
    const float* right = &pc.view_right[3 * std::size_t(o.nearest)];
    const float* up = p.views[o.nearest].up;
    const float rr = dot(load(right), load(right)), uu = dot(load(up), load(up)),
                ru = dot(load(right), load(up));
    const float stretch = std::sqrt(0.5f * (rr + uu) + std::sqrt(0.25f * (rr - uu) * (rr - uu) + ru * ru)) *
                          (1.0f + kRoomRelative);
    reach = room / stretch;
    // The eccentricity stays in its cell (and quarter) of the moving grid.
    const std::uint32_t cell = o.em.j;
    const float lower = e_node(cell, kMovingE), upper = e_node(cell + 1, kMovingE);
    float w_from, w_to;
    weight_range(quartered, o.em.w, &w_from, &w_to);
    const float slack = kRoomSpeed * (upper - lower) + kRoomCosine * b.e[j];
    e_from = w_from == 0.0f ? (cell == 0 ? -kInf : lower) : lower + w_from * (upper - lower);
    e_to = w_to == 1.0f ? (cell == kMovingE - 2 ? kInf : upper) : lower + w_to * (upper - lower);
    e_from += slack;
    e_to -= slack;
    if (!(e_from < b.e[j] && b.e[j] < e_to)) return;
  }
  // The chord the direction may move by (margins of at most 0.5 rad).
  std::memcpy(h.direction, d, sizeof d);
  h.slip[0] = o.slip.x;
  h.slip[1] = o.slip.y;
  h.slip[2] = o.slip.z;
  h.reach = reach;
  h.e_from = e_from;
  h.e_to = e_to;
  h.turn = kChordOfAngle * margin;
  memo.any_hold = true;
}

}  // namespace acuity
