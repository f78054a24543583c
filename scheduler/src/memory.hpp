#pragma once
// The decision memory (scheduler/src only): per eye and object, the memo of the last decision made
// over whole cells or at the object's place, its hold of the view, and its rest.
#include "tables.hpp"

namespace acuity::internal {

// The rounding rooms of the memory's checks (memory.cpp): how far an input the check computes may
// lie from the frame loop's own computation of it, so that a memo, hold or rest is only trusted where
// the loop would decide the same. Each is named once; the checks say which they spend where.
constexpr float kRoomRelative = 1e-5f;      // a float of a few operations (and the fast functions), relative
constexpr float kRoomEccentricity = 1e-3f;  // an eccentricity [deg], besides its relative room
constexpr double kRoomAngle = 1e-3;         // an angle from the fast atan2 [deg]
constexpr float kRoomCosine = 1e-6f;        // a cosine, and an eccentricity's weight per degree
constexpr float kRoomSpeed = 1e-4f;         // a hold's speeds and cell weights, relative
constexpr double kRoomPose = 1e-6;          // a pose's distance (relative) and turn [deg] in double
// A chord c between unit vectors spans 2 asin(c / 2) rad: at most the angle for c up to this fraction
// of it (angles of at most 0.5 rad).
constexpr float kChordOfAngle = 0.98f;

}  // namespace acuity::internal

namespace acuity {

// Per eye and object, the last decision made over whole cells or around the object's place in them:
// by the bounds over every view (tabulate()'s pass 3), or through the object's view (pass 6,
// kThroughView in the key; at its place, a still image's; over its cells' quarters, a moving one's),
// with the inputs under which it stands:
// the same key (eccentricity cell, still or not, table set), the same bands shown (f_lo * inv_diam
// <= Nyquist < f_hi * inv_diam: the lowest shown band and the next one, +inf past the profile's), x
// and the cell's weight in the Stand, where no line it compared against lies; through the view also
// the same view_key and speed_key. Tables never change once built, so within these the decision is
// the one the rows would give again: an object kept still, or moving steadily, is decided from its
// own memo without reading a table. Object slots start (add_object) with no memo.
struct Scheduler::Impl::Memo {
  static constexpr std::uint16_t kNone = 0xffff;  // a key no object has
  static constexpr std::uint16_t kThroughView = 1 << 14;
  static std::uint32_t key_of(std::uint32_t ec, std::uint32_t still, std::uint32_t tables) {
    return ec | still << 5 | tables << 6;
  }
  static_assert(kStillE - 1 < 32 && ((kStillE - 1) | 1 << 5 | 255 << 6) < kThroughView,
                "the key's fields (bias_tables_ is a byte) fit under kThroughView (and so kNone)");
  // Through the view: the view (Max3: the lookup cell, whose candidates are the views), whether the
  // image slips in the view's axes, and then its eccentricity cell on the moving grid and each
  // orientation's speed cell, 4 bits each (profiles of at most kSpeedKeyOrientations orientations:
  // a moving object of a profile with more is not remembered through its view). A moving image's
  // decision that its whole cells leave open may stand over the quarters of its cells it lies in
  // (kQuartered; the eccentricity cell of the still grid too, in w_from and w_to): the keys then
  // also hold the moving eccentricity cell's quarter and each orientation's speed quarter, 2 bits
  // each (profiles of at most kQuarterKeyOrientations orientations).
  static constexpr std::uint32_t kSpeedKeyOrientations = 16, kQuarterKeyOrientations = 10;
  static constexpr std::uint32_t kQuartered = 1 << 7;
  // A decision through the view that stands only at the object's place (the whole cells left it
  // open, and it moves, or no box around its place keeps it): its fine and coarse level in the memo.
  static constexpr std::uint8_t kAtPlace = 255;
  static_assert(kMovingE - 2 < 16 && kMovingS - 2 < 16, "cells fit 4 bits");
  static_assert(6 * kMaxLookupResolution * kMaxLookupResolution < (1u << 24) && kMaxViews < (1u << 24),
                "view_key's fields fit 32 bits");
  static_assert(6 * kQuarterKeyOrientations <= 64, "speed_key's cells and quarters fit 64 bits");
  static bool keyable(bool moving, std::uint32_t T) { return !moving || T <= kSpeedKeyOrientations; }
  static bool quarterable(std::uint32_t T) { return T <= kQuarterKeyOrientations; }
  // The keys of a probe's view and cells (o.cells set where it moves), with the quarters or not.
  static std::uint32_t view_key_of(const Probe& o, bool quartered);
  static std::uint64_t speed_key_of(const Probe& o, std::uint32_t T, bool quartered);
  // A decision stands for x [1/1024 ln deg] in [x_from, x_to] (Stand's (lo, hi]) and for the
  // eccentricity cell's weight w in [w_from, w_to] / kWeightSteps (every w for a decision made over
  // the whole cell).
  std::vector<std::uint16_t> key;
  std::vector<std::int16_t> x_from, x_to;
  std::vector<std::uint16_t> w_from, w_to;
  std::vector<float> f_lo, f_hi;  // band centres [cpod]
  std::vector<std::uint8_t> fine, coarse;
  std::vector<std::uint32_t> view_key;  // read only where the key has kThroughView
  std::vector<std::uint64_t> speed_key;
  // Where a decision through the view (not kAtPlace) keeps its view_key and speed_key, so that the
  // frame loop need not find the view and the slip in its axes again: while the direction from the
  // object to the eye (object space) stays within `turn` [chord of unit vectors] of `direction`, the
  // retinal slip [deg/s] within `reach` of `slip`, and the eccentricity [deg] in [e_from, e_to], and
  // the object's rotation is the same (set_transform ends it otherwise). turn < 0: none.
  struct Hold {
    float direction[3];
    float turn;
    float slip[3];
    float reach;
    float e_from, e_to;
  };
  std::vector<Hold> hold;
  // Whether any hold was ever set (hold_view()): until one is, none is read or prefetched (an eye
  // never steady, as along a head track, sets none).
  bool any_hold = false;
  // Rests: while the eye stays within rest_m [m] of where it was in frame rest_frame, and its gaze
  // and head turn at most rest_deg from where they pointed, every input the memo tests stays inside
  // its box (stands_at_rest()), so the memo decides without the object's geometry. rest_m < 0: none.
  // A rest lasts fewer than kPoses frames (staggered by id, so they do not all end in one frame). One
  // the eye left is set again after kLeftRetry frames, and where none could be set, after kRetry (an
  // eye that keeps moving sets few).
  static constexpr std::uint32_t kPoses = 256, kLeftRetry = 8, kRetry = 64;
  static std::uint32_t rest_frames(ObjectId id) { return kPoses / 2 + (id & (kPoses / 2 - 1)); }
  std::vector<std::uint32_t> rest_frame;
  std::vector<float> rest_m, rest_deg;
  // The eye of the last kPoses frames (by frame % kPoses) and how far it is from each now: moved [m]
  // and turned [deg] (gaze or head, the larger), +inf where either frame could not rest (the eye
  // moved by a velocity, an image slipped, no valid eye, another gaze state or focal length).
  struct Pose {
    double position[3];
    Vec3 gaze, forward;
    float focal_px;
    bool gaze_valid, usable;
  };
  Pose pose[kPoses]{};
  float moved[kPoses], turned[kPoses];
  float recent_m = 0, recent_deg = 0;  // the most moved and turned over the last 4 frames that could rest
  bool usable = false;                 // this frame's pose can rest
  // The eye has neither moved nor turned over the last 4 frames (each turn has kRoomPose added).
  bool still() const { return usable && recent_m == 0.0f && recent_deg <= float(kRoomPose); }
  void end_rest(ObjectId id) { rest_m[id] = -1.0f; }
  // Forgets object id's memo (and so its rest and hold): for a decision made without it (exactly, or
  // with nothing to read), after which it stands on nothing and keeps no view's tables from being
  // dropped (drop_idle_tables() counts the views that memos through a view stand on as read).
  void forget(ObjectId id) {
    if (key[id] == kNone) return;
    key[id] = kNone;
    end_rest(id);
  }
  void end_hold(ObjectId id) { hold[id].turn = -1.0f; }
  explicit Memo(std::size_t n = 0)
      : key(n, kNone),
        x_from(n, 0),
        x_to(n, 0),
        w_from(n, 0),
        w_to(n, 0),
        f_lo(n, kInf),
        f_hi(n, kInf),
        fine(n, 0),
        coarse(n, 0),
        view_key(n, 0),
        speed_key(n, 0),
        hold(n, Hold{{0, 0, 0}, -1.0f, {0, 0, 0}, 0.0f, 0.0f, 0.0f}),
        rest_frame(n, 0u - kPoses),
        rest_m(n, -1.0f),
        rest_deg(n, -1.0f) {
    std::fill(moved, moved + kPoses, kInf);
    std::fill(turned, turned + kPoses, kInf);
  }
  // Frame `frame`'s pose of an eye (nullptr: an eye not used this frame).
  void observe(std::uint32_t frame, const EyeCache* eye);
  // Remembers object id's decision (fine, coarse) where it stands, with `bands` of the profile's
  // band centres `frequency` shown. Its rest ends (a rest is set for the decision it stands with);
  // its hold is read only under a key with kThroughView, so a memo through the view ends it (or
  // sets it anew) as it is made, and others leave it unread (not written: a cache line less per
  // object where many memos are made again each frame, as when the head turns).
  void remember(ObjectId id, std::uint32_t key_bits, const Stand& stand, const float* frequency,
                std::uint32_t bands, int fine_level, int coarse_level) {
    key[id] = static_cast<std::uint16_t>(key_bits);
    end_rest(id);
    x_from[id] = static_cast<std::int16_t>(stand.lo + 1);
    x_to[id] = static_cast<std::int16_t>(stand.hi);
    w_from[id] = stand.w_from;
    w_to[id] = stand.w_to;
    f_lo[id] = frequency[bands - 1];
    f_hi[id] = bands < kMaxBands ? frequency[bands] : kInf;
    fine[id] = static_cast<std::uint8_t>(fine_level);
    coarse[id] = static_cast<std::uint8_t>(coarse_level);
  }
};

// What a rest's check reads of an object and one eye now.
struct Scheduler::Impl::RestProbe {
  float d, r;                       // distance, radius [m]
  float gaze_angle, forward_angle;  // from the direction to the object to the gaze's and the head's [deg]
  float view_margin;                // how far [rad] the direction may turn before its view can change
  float half_focal, offset;         // as look_block() reads them
};

inline std::uint32_t Scheduler::Impl::Memo::view_key_of(const Probe& o, bool quartered) {
  if (!o.moving) return o.where << 8;
  const std::uint32_t quarter = quartered ? kQuartered | quarter_of(o.em.w) << 5 : 0u;
  return o.where << 8 | quarter | o.em.j << 1 | 1u;
}

inline std::uint64_t Scheduler::Impl::Memo::speed_key_of(const Probe& o, std::uint32_t T, bool quartered) {
  std::uint64_t k = 0;
  for (std::uint32_t t = 0; o.moving && t < T; ++t) {
    k |= std::uint64_t(o.speed_j[t]) << (4 * t);
    if (quartered) k |= std::uint64_t(quarter_of(o.speed_w[t])) << (4 * T + 2 * t);
  }
  return k;
}

}  // namespace acuity
