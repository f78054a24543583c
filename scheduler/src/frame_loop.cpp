// The frame loop: begin_frame, update (a block of kBlock objects at a time, through the passes),
// clamps and hysteresis (settle), end_frame with the budget.
#include "memory.hpp"

namespace acuity {

void Scheduler::Impl::begin_frame(const Frame& frame) {
  eye_count_ = std::clamp<std::uint32_t>(frame.eye_count, 1, 2);
  dt_ = std::isfinite(frame.dt) && frame.dt > 0 ? frame.dt : 0.0f;
  hold_step_ = config_.hysteresis_seconds > 0 || both_seconds_ ? dt_ : 1.0f;  // seconds, or frames
  wait_step_ = config_.max_coarsen_wait_seconds > 0 ? dt_ : 1.0f;
  saccade_ = false;
  const std::size_t alive = config_.max_objects - free_list_.size();
  many_at_rest_ = stats_.at_rest > 0 && stats_.at_rest >= alive / 8;  // last frame's stats
  const bool looked = looking_for_rest_;
  const std::uint32_t found = stats_.at_rest;
  stats_ = FrameStats{};
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Gaze& g = frame.gaze[i];
    EyeCache& c = eyes_[i];
    const EyeCache before = c;
    pose_eye(frame.eyes[i], &c);
    const Vec3 gd = load(g.direction);
    const float gl = length(gd);
    c.gaze = g.valid && g.confidence >= config_.min_gaze_confidence && std::isfinite(gl) && gl > 0.5f;
    c.gaze_dir = c.gaze ? rotate(c.rotation, (1.0f / gl) * gd) : c.forward;
    const Vec3 gw = load(g.angular_velocity);
    c.gaze_moving = c.gaze && g.has_velocity && finite(gw);
    if (c.gaze_moving && config_.saccade_speed > 0 && length(gw) > config_.saccade_speed) {
      // A saccade: the time to switch, but its own sweep of the retina lasts a few frames while the
      // level chosen now is seen in the fixation after it. So the eye counts as fixating (Daly's
      // pursuit model), not as moving at saccade speed.
      saccade_ = true;
      c.gaze_moving = false;
    }
    if (c.gaze_moving) {
      // d(gaze)/dt in the world: eye-in-head rotation carried by the head, plus the head's own.
      const Vec3 in_head = rotate(c.rotation, cross(gw, (1.0f / gl) * gd));
      c.gaze_velocity = in_head + kDeg * cross(c.omega, c.gaze_dir);
    }
    const auto same = [](Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
    c.steady = same(c.velocity, before.velocity) && same(c.omega, before.omega) &&
               c.gaze_moving == before.gaze_moving &&
               (!c.gaze_moving || same(c.gaze_velocity, before.gaze_velocity));
    stats_.gaze_used |= c.gaze;
    if (!perceptual()) {  // level k's least distance / radius under this eye
      float* threshold = error_threshold_[i].data();
      for (std::uint32_t p = 0; p < profile_count_; ++p)
        for (std::uint32_t k = 1; k < level_count_[p]; ++k)
          threshold[p * kMaxLevels + k] = error_threshold(error_size_[p * kMaxLevels + k], c.focal_px);
    }
  }
  if (!views_.empty()) begin_views(frame);
  ++frame_;
  resting_ = memos_ != nullptr && !config_.keep_scores;
  for (std::uint32_t i = 0; memos_ && i < 2; ++i)
    memos_[i].observe(frame_, i < eye_count_ ? &eyes_[i] : nullptr);
  pause_rests(looked, found);
  // Objects are looked for at rest where an eighth were last frame, and every eighth frame.
  looking_for_rest_ = resting_ && (many_at_rest_ || frame_ % 8 == 0);
  for (std::uint32_t i = 0; memos_ && i < eye_count_; ++i) resting_ = resting_ && memos_[i].usable;
}

// Rests pay only where a later look finds objects at rest. An eye that keeps turning (a head sweeping
// with the gaze fixed in it) leaves each rest before the look after it (every eighth frame), so they
// cost a frame loop about a sixth of its time for nothing: after a look (last frame: `looked`) that
// finds none at rest (`found`), none is set or looked for during a pause of kFirstRestPause frames,
// doubling with each such look up to kLongestRestPause. A look that finds some, or an eye that stands
// still (whose rests mostly last), ends the pause, and lets objects whose rests failed while it
// moved try again at once (still_since_). Rests decide as memos do, so this changes no decision,
// only the cost; it depends on the frames alone, so it stays deterministic.
void Scheduler::Impl::pause_rests(bool looked, std::uint32_t found) {
  bool still = memos_ != nullptr;
  for (std::uint32_t i = 0; memos_ && i < eye_count_; ++i) still = still && memos_[i].still();
  if (still && !eyes_still_) still_since_ = frame_;
  eyes_still_ = still;
  if (found > 0 || still) {
    rest_pause_ = next_rest_pause_ = 0;
  } else if (looked) {
    next_rest_pause_ =
        std::min(next_rest_pause_ > 0 ? 2 * next_rest_pause_ : kFirstRestPause, kLongestRestPause);
    rest_pause_ = next_rest_pause_;
  } else if (rest_pause_ > 0) {
    --rest_pause_;
  }
  resting_ = resting_ && rest_pause_ == 0;
}

// An eye's pose, projection and validity as the frame reads them (its gaze is begin_frame's).
void Scheduler::Impl::pose_eye(const Eye& e, EyeCache* out) {
  EyeCache& c = *out;
  for (int k = 0; k < 3; ++k) c.position[k] = e.position[k];
  for (int k = 0; k < 4; ++k) c.rotation[k] = e.orientation[k];
  const float qn = quaternion_length(e.orientation);
  const float tan_l = std::tan(e.fov_deg[0] * kRad), tan_r = std::tan(e.fov_deg[1] * kRad);
  const float tan_u = std::tan(e.fov_deg[2] * kRad), tan_d = std::tan(e.fov_deg[3] * kRad);
  c.valid = std::isfinite(e.position[0]) && std::isfinite(e.position[1]) && std::isfinite(e.position[2]) &&
            unit_length(qn) && finite(load(e.velocity)) && finite(load(e.angular_velocity)) &&
            tan_r > tan_l && tan_u > tan_d && e.viewport[0] > 0 && e.viewport[1] > 0 &&
            std::isfinite(tan_r - tan_l) && std::isfinite(tan_u - tan_d);
  if (c.valid)
    for (float& q : c.rotation) q /= qn;
  c.forward = rotate(c.rotation, {0, 0, -1});
  c.velocity = load(e.velocity);
  c.omega = kRad * load(e.angular_velocity);
  c.focal_px = static_cast<float>(e.viewport[0]) / (tan_r - tan_l);
  c.center_right = 0.5f * (tan_l + tan_r);
  c.center_up = 0.5f * (tan_u + tan_d);
}

void Scheduler::Impl::update(std::uint32_t first, std::uint32_t count) {
  const std::uint32_t end =
      first >= config_.max_objects ? first : first + std::min(count, config_.max_objects - first);
  Block blocks[2];
  Sight sights[2][Block::kSize];
  Look looks[2][Block::kSize];
  Decisions decisions{};
  // At rest: which objects are, two blocks ahead, and the arrays of those that are not prefetched.
  std::uint32_t at_rest[3][Block::kSize];
  bool mostly_at_rest[3];
  const auto look_ahead = [&](std::uint32_t start) {
    if (!looking_for_rest_ || start >= end) return;
    const std::uint32_t n = std::min(Block::kSize, end - start), slot = (start - first) / Block::kSize % 3;
    mostly_at_rest[slot] = rest_mask(start, n, at_rest[slot]);
    if (mostly_at_rest[slot]) prefetch_restless(start, n, at_rest[slot]);
  };
  look_ahead(first);
  look_ahead(first + Block::kSize);
  for (std::uint32_t start = first; start < end; start += Block::kSize) {
    const std::uint32_t n = std::min(Block::kSize, end - start);
    look_ahead(start + 2 * Block::kSize);
    const std::uint32_t slot = (start - first) / Block::kSize % 3;
    if (looking_for_rest_ && mostly_at_rest[slot]) {
      decide_at_rest(start, n, at_rest[slot], &decisions);
      settle(start, n, decisions);
      continue;
    }
    if (end - start >= 3 * Block::kSize) prefetch_objects(start + 2 * Block::kSize);
    if (curves_ && end - start >= 2 * Block::kSize) prefetch_holds(start + Block::kSize);
    std::fill(rest_.begin() + start, rest_.begin() + start + n, std::uint8_t(0));
    derive_velocities(start, n);
    for (std::uint32_t i = 0; i < eye_count_; ++i) look_block(eyes_[i], start, n, &blocks[i]);
    if (!perceptual()) {
      choose_by_error(start, n, blocks, &decisions);
      settle(start, n, decisions);
      continue;
    }
    if (curves_) {
      choose_tabulated(start, n, blocks, &decisions);
      settle(start, n, decisions);
      continue;
    }
    // Passes over the block, each prefetching what the next reads: the lookup cell, the candidate
    // views. The misses of a block's objects overlap instead of queueing.
    for (std::uint32_t j = 0; j < n; ++j)
      if (profile_of_[start + j] >= 0)
        for (std::uint32_t i = 0; i < eye_count_; ++i)
          looks[i][j] = sight(start + j, eyes_[i], blocks[i], j, &sights[i][j]);
    for (std::uint32_t j = 0; j < n; ++j)
      if (profile_of_[start + j] >= 0)
        for (std::uint32_t i = 0; i < eye_count_; ++i)
          if (looks[i][j] == Look::Ok) prefetch_views(start + j, sights[i][j]);
    for (std::uint32_t j = 0; j < n; ++j)
      if (profile_of_[start + j] >= 0)
        for (std::uint32_t i = 0; i < eye_count_; ++i)
          if (looks[i][j] == Look::Ok) aim(start + j, &sights[i][j]);
    choose_perceptual(start, n, looks, sights, &decisions);
    settle(start, n, decisions);
  }
  if (!view_levels_.empty()) decide_views(first, end);
}

// The per-object arrays a frame reads, for the kBlock objects from `first`, asked for two blocks
// ahead. A frame reads some thirty of them side by side: more streams than the hardware prefetcher
// follows, so without this every block began with misses in each (measured in docs/benchmarks.md).
// An array the frame loop starts to read belongs here too. Hints only: nothing here changes a result.
void Scheduler::Impl::prefetch_objects(std::uint32_t first) const {
  constexpr std::uint32_t n = Block::kSize, kLine = 64;
  const auto lines = [](const void* p, std::size_t bytes) {
    for (std::size_t o = 0; o < bytes; o += kLine) ACUITY_PREFETCH(static_cast<const char*>(p) + o);
  };
  for (int k = 0; k < 3; ++k) lines(&position_[k][first], sizeof(double) * n);
  for (int k = 0; k < 3; ++k) lines(&velocity_[k][first], sizeof(float) * n);
  for (int k = 0; k < 4; ++k) lines(&rotation_[k][first], sizeof(float) * n);
  for (int k = 0; k < 4; ++k) lines(&sphere_[k][first], sizeof(float) * n);
  lines(&profile_of_[first], sizeof(int) * n);
  for (const auto* a : {&calm_, &wait_}) lines(&(*a)[first], sizeof(float) * n);
  for (const auto* a :
       {&explicit_velocity_, &fresh_, &min_level_, &max_level_, &flags_, &chosen_, &next_, &bias_tables_})
    lines(&(*a)[first], n);
  if (!curves_) return;
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Memo& m = memos_[i];
    for (const auto* a : {&m.x_from, &m.x_to}) lines(&(*a)[first], sizeof(std::int16_t) * n);
    for (const auto* a : {&m.key, &m.w_from, &m.w_to}) lines(&(*a)[first], sizeof(std::uint16_t) * n);
    for (const auto* a : {&m.f_lo, &m.f_hi}) lines(&(*a)[first], sizeof(float) * n);
    for (const auto* a : {&m.fine, &m.coarse}) lines(&(*a)[first], n);
  }
}

// Velocities not given are derived from the positions and dt (a given velocity stays given, so its
// object's previous position is never read again). Blocks whose velocities are all given skip it.
ACUITY_SIMD_CLONES void Scheduler::Impl::derive_velocities(std::uint32_t first, std::uint32_t n) {
  const std::uint8_t* given = &explicit_velocity_[first];
  std::uint8_t all = 1;
  for (std::uint32_t j = 0; j < n; ++j) all &= given[j];
  if (all) return;
  const double inv_dt = dt_ > 0 ? 1.0 / double(dt_) : 0.0;
  for (int k = 0; k < 3; ++k) {
    const double* pos = &position_[k][first];
    double* prev = &previous_position_[k][first];
    float* vel = &velocity_[k][first];
    for (std::uint32_t j = 0; j < n; ++j) {
      const float derived = static_cast<float>((pos[j] - prev[j]) * inv_dt);
      vel[j] = given[j] ? vel[j] : derived;
      prev[j] = pos[j];
    }
  }
}

// Clamps and hysteresis for a block, branch-free per object: a new object takes its first level at
// once; a finer level (or the fallback) applies at once; a coarser one once it has been wanted for
// the hysteresis and, with saccade gating, in a saccade or after the wait (kFlagHeld meanwhile),
// each measured in seconds of dt or in frames (SchedulerConfig's timing). Free slots keep their state.
ACUITY_SIMD_CLONES void Scheduler::Impl::settle(std::uint32_t first, std::uint32_t n, const Decisions& d) {
  const CoarsenTiming timing = coarsen_timing();
  const int* profile = &profile_of_[first];
  const std::uint8_t *max_level = &max_level_[first], *min_level = &min_level_[first];
  std::uint8_t *chosen = &chosen_[first], *next_level = &next_[first], *flags = &flags_[first],
               *fresh = &fresh_[first];
  float *calm_of = &calm_[first], *wait_of = &wait_[first];
  // Plain arithmetic and selects (no short-circuits, every load unconditional): it vectorises.
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::uint32_t alive = profile[j] >= 0;
    const std::uint32_t hi = max_level[j];  // clamped to the profile's coarsest level (set_clamps)
    const std::uint32_t lo = min_level[j] < hi ? min_level[j] : hi;
    const std::uint32_t want_fine = d.fine[j], want_coarse = d.coarse[j];
    const std::uint32_t fine = want_fine < lo ? lo : want_fine > hi ? hi : want_fine;
    const std::uint32_t coarse = want_coarse < lo ? lo : want_coarse > hi ? hi : want_coarse;
    const std::uint32_t current = chosen[j];
    const float calm = calm_of[j], wait = wait_of[j];
    const std::uint32_t refine = std::uint32_t(fresh[j] != 0) |
                                 std::uint32_t((d.flags[j] & kFlagInvalidInput) != 0) |
                                 std::uint32_t(fine < current);
    const std::uint32_t coarsen = (refine ^ 1u) & std::uint32_t(coarse > current);
    const CoarsenTiming::Step wanted = timing.step(calm, wait);
    const float calm_now = wanted.calm, wait_now = wanted.wait;
    const std::uint32_t go = coarsen & wanted.ready;
    const std::uint32_t held = coarsen & (go ^ 1u);
    const auto level = static_cast<std::uint8_t>(refine ? fine : go ? coarse : current);
    const auto flag = static_cast<std::uint8_t>(d.flags[j] | (held ? kFlagHeld : 0));
    // A free slot keeps its state: masks, not selects (GCC turns those into conditional stores).
    const auto keep = static_cast<std::uint8_t>(alive - 1u), take = static_cast<std::uint8_t>(~keep);
    chosen[j] = static_cast<std::uint8_t>((level & take) | (chosen[j] & keep));
    next_level[j] = static_cast<std::uint8_t>((level & take) | (next_level[j] & keep));
    flags[j] = static_cast<std::uint8_t>((flag & take) | (flags[j] & keep));
    fresh[j] = static_cast<std::uint8_t>(fresh[j] & keep);
    calm_of[j] = alive ? (held ? calm_now : 0.0f) : calm;
    wait_of[j] = alive ? (held ? wait_now : 0.0f) : wait;
  }
}

void Scheduler::Impl::end_frame() {
  if (config_.triangle_budget > 0) apply_budget();
  FrameStats& st = stats_;
  st.changed = st.invalid = st.budget_forced = st.at_rest = 0;
  const bool fades = config_.transition_seconds > 0;  // else every fade_ stays 1 (not read)
  constexpr std::uint32_t kChunk = 256;
  for (std::uint32_t first = 0; first < config_.max_objects; first += kChunk) {
    const std::uint32_t n = std::min(kChunk, config_.max_objects - first);
    if (count_flags(first, n, &st) == 0 && !fades) continue;  // nothing to write
    for (std::uint32_t id = first; id < first + n; ++id) {
      if (profile_of_[id] < 0) continue;
      if (next_[id] != level_[id]) {  // a change event; the cross-fade starts from the drawn level
        const std::uint32_t* triangles = &triangles_[std::size_t(profile_of_[id]) * kMaxLevels];
        drawn_triangles_ += triangles[next_[id]] - std::uint64_t(triangles[level_[id]]);
        from_level_[id] = level_[id];
        fade_[id] = fades ? 0.0f : 1.0f;
        flags_[id] |= kFlagChanged;
        level_[id] = next_[id];
      } else if (fades && fade_[id] < 1.0f) {
        fade_[id] = std::min(1.0f, fade_[id] + dt_ / config_.transition_seconds);
      }
    }
  }
  st.triangles = drawn_triangles_;
}

// Counts the flags of `count` objects from `first` into st as end_frame() leaves them (kFlagChanged
// where the next level is not the drawn one), and returns how many levels change. Reads only: it
// vectorises, and the objects whose level stays are not written. Free slots count nothing (their
// flags and rest are 0 and their next level the drawn one: remove_object()).
ACUITY_SIMD_CLONES std::uint32_t Scheduler::Impl::count_flags(std::uint32_t first, std::uint32_t n,
                                                              FrameStats* st) const {
  const std::uint8_t *next = &next_[first], *level = &level_[first], *flags = &flags_[first],
                     *rest = &rest_[first];
  std::uint32_t changes = 0, changed = 0, invalid = 0, forced = 0, at_rest = 0;
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::uint32_t change = next[j] != level[j];
    const std::uint32_t flag = flags[j];
    changes += change;
    changed += change | std::uint32_t((flag & kFlagChanged) != 0);
    invalid += (flag & kFlagInvalidInput) != 0;
    forced += (flag & kFlagBudgetForced) != 0;
    at_rest += rest[j];
  }
  st->changed += changed;
  st->invalid += invalid;
  st->budget_forced += forced;
  st->at_rest += at_rest;
  return changes;
}

// Funkhouser & Sequin: while over budget, coarsen by one level the object whose next level costs
// the least perceptual harm (its score) per triangle saved. Ties go to the lower id.
void Scheduler::Impl::apply_budget() {
  std::uint64_t total = 0;
  for (std::uint32_t id = 0; id < config_.max_objects; ++id)
    if (profile_of_[id] >= 0) total += profiles_[profile_of_[id]].profile.levels[next_[id]].triangles;
  if (total <= config_.triangle_budget) return;

  auto can_coarsen = [&](std::uint32_t id) {
    const std::uint32_t K = profiles_[profile_of_[id]].profile.meta.level_count;
    // An object with invalid input keeps its fallback level: a tracking glitch must not drop it.
    return next_[id] + 1u < std::min<std::uint32_t>(max_level_[id] + 1u, K) &&
           !(flags_[id] & (kFlagEyeInside | kFlagInvalidInput));
  };
  auto harm = [&](std::uint32_t id) {
    const Profile& p = profiles_[profile_of_[id]].profile;
    const std::uint32_t l = next_[id];
    const float saved =
        static_cast<float>(p.levels[l].triangles) - static_cast<float>(p.levels[l + 1].triangles);
    return scores_[std::size_t(id) * kMaxLevels + l + 1] / std::max(saved, 1.0f);
  };
  // Min-heap on (harm, id).
  auto later = [&](std::uint32_t x, std::uint32_t y) {
    const float hx = harm(x), hy = harm(y);
    return hx != hy ? hx > hy : x > y;
  };
  heap_.clear();
  for (std::uint32_t id = 0; id < config_.max_objects; ++id)
    if (profile_of_[id] >= 0 && can_coarsen(id)) heap_.push_back(id);
  std::make_heap(heap_.begin(), heap_.end(), later);
  while (total > config_.triangle_budget && !heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const std::uint32_t id = heap_.back();
    heap_.pop_back();
    const Profile& p = profiles_[profile_of_[id]].profile;
    const std::uint8_t l = next_[id];
    total -= p.levels[l].triangles - p.levels[l + 1].triangles;
    if (scores_[std::size_t(id) * kMaxLevels + l + 1] > 1.0f) flags_[id] |= kFlagBudgetForced;
    next_[id] = static_cast<std::uint8_t>(l + 1);
    if (can_coarsen(id)) {
      heap_.push_back(id);
      std::push_heap(heap_.begin(), heap_.end(), later);
    }
  }
}

}  // namespace acuity
