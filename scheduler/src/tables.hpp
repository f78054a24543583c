#pragma once
// The tabulated path's tables (scheduler/src only): the grid over eccentricity and speed, the
// entries' encoding, where a decision stands (Stand), a profile's tables (ProfileCache) and one
// object's place in them (Probe).
#include <atomic>
#include <memory>

#include "geometry.hpp"

namespace acuity::internal {

// ---- Tabulated path: grid and threshold curves ----------------------------------------------------
// Eccentricity nodes e_j = kTableMaxE (j / (n - 1))^2 (dense near the fovea), speed nodes
// s_i = floor 2^i; beyond the last node the last one (thresholds never fall with e or speed).
constexpr std::uint32_t kStillE = 24, kMovingE = 16, kMovingS = 13;
constexpr float kTableMaxE = 90.0f;
// A threshold curve: ln CT against u = ln f [cpd] on kCurveSamples points, made non-decreasing
// (a suffix minimum: a band-pass CSF counts as its low-pass envelope, which is conservative).
constexpr int kCurveSamples = 4096;
constexpr float kCurveU0 = -7.0f, kCurveU1 = 14.0f;
constexpr float kCurveStep = (kCurveU1 - kCurveU0) / float(kCurveSamples - 1);
constexpr float kNever = -1e30f;  // a table entry no size passes
// The moving tables' cells are checked at their centres only; this much more [ln deg] covers what
// the bilinear surface can still cut above the truth between centre and edges (measured: < 0.003).
constexpr float kBilinearMargin = 0.001f;
// A rise of the truth between two of a moving cell's row checks [ln deg] past twice the
// interpolation's that counts as a jump (see lower_speed_rows()).
constexpr float kRowJump = 0.02f;
// Table sets per profile: [2 i + 0] score <= 1, [2 i + 1] score <= 1 - margin, at the i-th bias with
// tables (Scheduler::Impl::table_bias_); an object whose bias has none takes the exact path.
constexpr std::uint32_t kTableSets = 2 * (1 + kMaxTabulatedBiases);
constexpr std::uint8_t kExactBias = 255;
constexpr std::uint8_t kInvalidBias = 254;  // quality x bias not finite and > 0: invalid input
// Table sets per bias: score <= 1, and score <= 1 - margin where a margin is set.
inline int margin_sets(const SchedulerConfig& c) { return c.hysteresis_margin > 0 ? 2 : 1; }
// The biases with tables: 1, then each distinct finite entry > 0 of the configuration's. Returns the count.
inline std::uint32_t table_biases(const SchedulerConfig& c, float* out) {
  std::uint32_t n = 0;
  out[n++] = 1.0f;
  for (const float b : c.tabulated_biases)
    if (std::isfinite(b) && b > 0 && std::find(out, out + n, b) == out + n) out[n++] = b;
  return n;
}

// Table entries: ln deg in steps of 1/1024, rounded down (conservative), saturating at
// kLeastEntry and kMostEntry (about +-32 ln deg; e^32 deg: every size passes; e^-32: none does).
constexpr float kSizeSteps = 1024.0f;  // per ln deg (a power of two: scaling is exact)
constexpr std::int32_t kLeastEntry = -32768, kMostEntry = 32757;
inline std::int16_t encode_size(float ln_size) {
  const float x = std::clamp(std::floor(ln_size * kSizeSteps), float(kLeastEntry), float(kMostEntry));
  return static_cast<std::int16_t>(x);
}
[[gnu::always_inline]] inline float decode_size(std::int16_t q) { return float(q) * (1.0f / kSizeSteps); }
// An object's ln size [ln deg] in table steps, rounded up (NaN: -64 ln deg): it is at most an entry
// exactly where the size is at most that entry's decoded value. Every size at most kLeastEntry is at
// most every entry and every size above kMostEntry is above all, so the steps are clamped to
// [kLeastEntry, kMostEntry + 1] (the same comparisons; an int16). Branch-free, so a loop vectorises.
[[gnu::always_inline]] inline std::int32_t size_steps_above(float ln_size) {
  const float scaled = (ln_size > -64.0f ? std::min(ln_size, 64.0f) : -64.0f) * kSizeSteps;
  const auto truncated = static_cast<std::int32_t>(scaled);
  return std::clamp(truncated + (float(truncated) < scaled), kLeastEntry, kMostEntry + 1);
}
// Between two table entries (a cell's lower and upper node) at the upper one's weight w [ln deg].
[[gnu::always_inline]] inline float between(std::int16_t lower, std::int16_t upper, float w) {
  const float a = decode_size(lower);
  return a + w * (decode_size(upper) - a);
}

constexpr float e_node(std::uint32_t j, std::uint32_t n) {
  const float t = float(j) / float(n - 1);
  return kTableMaxE * t * t;
}
inline float still_e_node(std::uint32_t j) { return e_node(j, kStillE); }
inline float moving_e_node(std::uint32_t j) { return e_node(j, kMovingE); }

// A position on a grid axis: the cell's lower node and the weight of the upper one. The weight is
// linear in the physical quantity (eccentricity, speed), where the largest invisible ln size is
// concave (ln of an affine function of e or v for the CSF's exponential fall-off), so the
// interpolation stays below it; a sqrt or log weight would cut above it.
struct Cell {
  std::uint32_t j;
  float w;
};
// The cell of eccentricity e [deg] on an n-node axis. The nodes come from e_node(), not from a table,
// so a loop over objects vectorises without gathers.
template <std::uint32_t n>
[[gnu::always_inline]] inline Cell e_cell(float e) {
  const float r = std::sqrt(e * (1.0f / kTableMaxE));
  const float x = (r < 1.0f ? r : 1.0f) * float(n - 1);  // NaN: the last cell (no NaN reaches the cast)
  const std::uint32_t j = std::min(static_cast<std::uint32_t>(x), n - 2);
  const float lower = e_node(j, n), upper = e_node(j + 1, n);
  return {j, std::clamp((e - lower) * (1.0f / (upper - lower)), 0.0f, 1.0f)};
}
// 2^e for 0 <= e < 128, from the float's bits (std::ldexp's value without its call).
[[gnu::always_inline]] inline float power_of_two(std::uint32_t e) {
  const std::uint32_t bits = (e + 127u) << 23;
  float power;
  std::memcpy(&power, &bits, sizeof power);
  return power;
}
// Speed nodes floor 2^i: the cell from the float's exponent (exact at powers of two). The weight is
// linear in g(r) = (r - 1) / (r + 1) ~ ln(r) / 2, r = (v + v0) / (v_lo + v0), v0 = 2 / c2: the CSF's
// fall-off b(v) f grows with c2 v + 2, so the largest invisible ln size is nearly linear in ln(v + v0).
// Plain arithmetic (the node and 1 / g at the cell's top computed, not looked up): a loop over
// orientations vectorises.
[[gnu::always_inline]] inline void speed_cell(float v, float floor, float v0, std::uint32_t n,
                                              std::uint32_t* j, float* w) {
  const float r = v / floor;  // >= 1
  std::uint32_t bits;
  std::memcpy(&bits, &r, sizeof bits);
  const int octave = std::min(std::max(int((bits >> 23) & 255u) - 127, 0), int(n) - 2);
  const float lo = floor * power_of_two(std::uint32_t(octave));  // the cell's lower node
  const float inv_g = (3.0f * lo + 2.0f * v0) / lo;              // 1 / g at the cell's top, 2 lo
  // g(r) = (r - 1) / (r + 1) with r = (v + v0) / (lo + v0) is (v - lo) / (v + lo + 2 v0).
  *j = static_cast<std::uint32_t>(octave);
  *w = std::clamp((v - lo) / (v + lo + 2.0f * v0) * inv_g, 0.0f, 1.0f);
}
// The speed at weight 1/2 of cell [lo, 2 lo].
inline float speed_midpoint(float lo, float v0) {
  const float half = 0.5f * ((2.0f * lo + v0) / (lo + v0) - 1.0f) / ((2.0f * lo + v0) / (lo + v0) + 1.0f);
  return (1.0f + half) / (1.0f - half) * (lo + v0) - v0;
}

// Where a decision stands: x [table steps, as size_steps_above()] in (lo, hi] and the eccentricity
// cell's upper weight w in [w_from, w_to] / kWeightSteps. Where there is no end, lo and hi start just
// past the entries (size_steps_above()'s range); a decision over the whole cell stands for every w.
constexpr float kWeightSteps = 32768.0f;  // a power of two: w * kWeightSteps is exact
struct Stand {
  static constexpr std::int32_t kNoLow = kLeastEntry - 1, kNoHigh = kMostEntry + 1;
  std::int32_t lo = kNoLow, hi = kNoHigh;
  std::uint16_t w_from = 0, w_to = 0xffff;
};
static_assert(Stand::kNoLow + 1 >= INT16_MIN && Stand::kNoHigh <= INT16_MAX, "lo + 1 and hi fit an int16");

// Where a decision made at an object's place in its cell stands. It compared x [ln deg] (x_step: in
// table steps) against lines between a cell's two entries at the weight w: x <= between(lower, upper,
// w) + offset, and `lines(f)` calls f(lower, upper, offset) for each. Half the least distance from x
// to a line goes to x, the rest to w: the box of w in which every line stays that far on its side of
// x. Then each line at the box's ends, computed as the decision computes it (between() is monotone in
// w, so its extremes are there), narrows (lo, hi], with a table step of room for rounding. Writes
// *out and returns true where x_step lies inside; else the decision stands nowhere around x.
template <class Lines>
bool stand_at_place(float x, std::int32_t x_step, float w, const Lines& lines, Stand* out) {
  float slack = kInf;
  lines([&](std::int16_t lower, std::int16_t upper, float offset) {
    slack = std::min(slack, std::abs(between(lower, upper, w) + offset - x));
  });
  const float half = 0.5f * slack;
  float w_lo = 0.0f, w_hi = 1.0f;
  lines([&](std::int16_t lower, std::int16_t upper, float offset) {
    const float a = decode_size(lower) + offset, d = decode_size(upper) - decode_size(lower);
    if (d == 0.0f) return;  // level: on its side at every w
    const bool passes = x <= between(lower, upper, w) + offset;
    const float near = ((passes ? x + half : x - half) - a) / d;  // the w where it comes that near
    if (passes == (d > 0.0f))
      w_lo = std::max(w_lo, near);
    else
      w_hi = std::min(w_hi, near);
  });
  const float from = std::ceil(w_lo * kWeightSteps), to = std::floor(w_hi * kWeightSteps);
  if (!(from <= w * kWeightSteps && w * kWeightSteps <= to)) return false;
  const float end0 = from / kWeightSteps, end1 = to / kWeightSteps;
  Stand s{Stand::kNoLow, Stand::kNoHigh, static_cast<std::uint16_t>(from), static_cast<std::uint16_t>(to)};
  lines([&](std::int16_t lower, std::int16_t upper, float offset) {
    const float b0 = between(lower, upper, end0) + offset, b1 = between(lower, upper, end1) + offset;
    if (x <= between(lower, upper, w) + offset)
      s.hi = std::min(s.hi, static_cast<std::int32_t>(std::floor(std::min(b0, b1) * kSizeSteps)) - 1);
    else
      s.lo = std::max(s.lo, static_cast<std::int32_t>(std::ceil(std::max(b0, b1) * kSizeSteps)) + 1);
  });
  if (!(s.lo < x_step && x_step <= s.hi)) return false;
  *out = s;
  return true;
}

}  // namespace acuity::internal

namespace acuity {

// A profile's tables (its ProfileCache's, or built apart from it: build_tables(), make_tables()).
struct Scheduler::Impl::ProfileTableSets {
  // Tabulated path: ln of the largest invisible angular diameter [ln deg] (see scheduler.hpp).
  // Levels are innermost, so one object's reads share cache lines.
  // still and slow [V][n][kStillE][K-1]: the n = 1..B lowest bands visible on the display, a still
  // object (the floor's terms) and one moving no faster than the floor (the velocity envelope) --
  // a bound for every moving object, since thresholds never fall with speed;
  // moving [V][Tm][kMovingS][kMovingE][K-1]: every band, one orientation at its own speed; Tm =
  // moving_orientations: T, or 1 where every orientation reads the same loss (the area law's
  // pooled L: their rows would be equal), each orientation then reading that row at its own speed.
  // Entries: encode_size(), 1/1024 ln deg, rounded down.
  // The same bounds taken over every view at each eccentricity node, so that most objects are
  // decided before their view is looked up: any_view [B][kStillE][2 (K-1) + 1], per band count
  // and eccentricity node the least and the most over the views of the still table, then the least
  // over the views of the still and slow tables at the coarsest level (every object whose image
  // moves is bounded by one of them).
  struct Tables {
    std::vector<std::int16_t> still, slow, moving, any_view;
  };
  // [2 i]: score <= 1, [2 i + 1]: score <= 1 - margin (empty when the margin is 0), at bias
  // table_bias_[i] (kTableSets). One set's four side by side: an object reads one set.
  Tables sets[kTableSets];
  // The profile's views whose tables these hold, in the order of their rows (V in the layouts above
  // counts these): every view, or those made one at a time (make_tables(p, view)). any_view is made
  // only with every view, and kept when some are dropped (a bound over every view's tables, which
  // never change once built).
  std::vector<std::uint16_t> views;
  std::size_t bytes() const {
    std::size_t n = 0;
    for (const Tables& t : sets) n += t.still.size() + t.slow.size() + t.moving.size() + t.any_view.size();
    return n * sizeof(std::int16_t);
  }
};

struct Scheduler::Impl::ProfileCache {
  Profile profile{};
  std::vector<float> ln_lost;      // [(K-1) V T B], -inf where nothing is lost
  std::vector<float> ln_lost_any;  // [(K-1) V B]: max over orientations (all a static object needs)

  // The area law's k per level, view and band (Curves::area_term(): a0 / (extent x band centre^2),
  // from the Pooled section or a bound from Detail's; area_ks()), [(K-1) V B], every orientation of
  // the band reading it; empty when the law does not apply (area_law() false).
  std::vector<float> area_k;
  std::uint32_t moving_orientations = 1;  // Tm: rows per view and level of the moving tables
  std::vector<float> ln_band;             // [B] ln of the band centre [cpod]
  std::vector<float> cos_t, sin_t;        // [T] orientation unit vectors in the snapshot plane
  std::vector<float> view_right;          // [V][3] snapshot right = -direction x up, object space
  // Tabulated path: the tables (ProfileTableSets), built by add_profile or installed a view or all
  // at a time, less those dropped (drop_idle_tables()); slot[v]: the row of view v in them (kNoRow:
  // not held, its objects decide exactly).
  ProfileTableSets tables;
  static constexpr std::uint16_t kNoRow = 0xffff;
  std::vector<std::uint16_t> slot;  // [V]
  // [V]: kWanted once an object was seen from the view without its tables, kListed once
  // wanted_tables() has listed it (0 again when its tables are dropped).
  static constexpr std::uint8_t kWanted = 1, kListed = 2;
  std::vector<std::uint8_t> wanted;
  // [V]: the frame (Impl::frame_) in which an object last read view v's tables or a memo made from
  // them (tabulate_views(), on any range's thread), or they were installed: drop_idle_tables()
  // drops views not read for long.
  std::unique_ptr<std::atomic<std::uint32_t>[]> read_frame;
  void note_read_view(std::uint32_t v, std::uint32_t frame) const {
    std::atomic<std::uint32_t>& at = read_frame[v];
    if (at.load(std::memory_order_relaxed) != frame) at.store(frame, std::memory_order_relaxed);
  }
  // The views an object read at `where` (as Probe::where and the memo's view_key hold it: the view,
  // or with Max3 the lookup cell, whose candidates are the views).
  void note_read(std::uint32_t where, bool max3, std::uint32_t frame) const {
    if (!max3) return note_read_view(where, frame);
    for (std::uint32_t k = 0; k < kLookupCandidates; ++k)
      note_read_view(profile.lookup[std::size_t(where) * kLookupCandidates + k], frame);
  }
  bool every_view() const { return tables.views.size() == slot.size(); }
  bool has_any_view() const { return !tables.sets[0].any_view.empty(); }
};

// What Scheduler::make_tables() hands to install_tables(): the tables, and for which scheduler
// and profile they were made.
struct ProfileTables::Data {
  std::uint64_t scheduler = 0;  // Scheduler::Impl::serial_
  int profile = -1;
  Scheduler::Impl::ProfileTableSets tables;
};

// One loss's area law as the tables' searches read it (Curves::with_law()): k (0: none) and the
// factor's lower bound per block of curve samples (Curves::kKnots values, Curves::area_knots()).
struct internal::AreaLaw {
  float k = 0.0f;
  const float* knots = nullptr;
};

// One object's place in its profile's tables, seen by one eye: what the decision reads.
struct Scheduler::Impl::Probe {
  float x;                                // ln angular diameter [ln deg]
  std::uint8_t tables;                    // the object's bias's first table set (kTableSets)
  float vx, vy;                           // retinal slip in the view's image axes [deg/s]
  Cell ec;                                // eccentricity cell of the still grid
  std::uint32_t bands;                    // the lowest bands the display shows (0: none)
  std::uint16_t rows[kLookupCandidates];  // the table rows (ProfileCache::slot) of the views whose
  std::uint8_t view_count;                // tables bound it (one, or Max3's three)
  std::uint32_t where;                    // the view (Max3: the lookup cell), as the memo keys it
  std::uint32_t nearest;                  // the view nearest to the eye, in whose image axes vx and vy are
  Vec3 slip;                              // retinal slip [deg/s], eye space
  bool moving;
  bool decided;                             // by its memo through the view (pass 4)
  bool at_place;                            // ... which says the whole cells do not decide
  bool cells;                               // moving: em and sc are set (where a slow bound does not pass)
  Cell em;                                  // eccentricity cell of the moving grid
  std::uint32_t speed_j[kMaxOrientations];  // each orientation's speed cell: lower node
  float speed_w[kMaxOrientations];          // and the weight of the upper one
  // Where candidate view c's rows start (profile of B bands, L coarser levels): in the still and
  // slow tables (the lower eccentricity node's levels, then the upper one's), and in the moving
  // table for orientation t (its lower speed node's two eccentricity nodes; the upper speed node's
  // are kMovingE * L further) of a table with Tm rows per view (ProfileCache::moving_orientations:
  // T, or 1 shared by every orientation). ProfileCache describes the layouts.
  std::size_t still_row(std::uint32_t c, std::uint32_t B, std::uint32_t L) const {
    return ((std::size_t(rows[c]) * B + (bands - 1)) * kStillE + ec.j) * L;
  }
  std::size_t moving_row(std::uint32_t c, std::uint32_t t, std::uint32_t Tm, std::uint32_t L) const {
    return (((std::size_t(rows[c]) * Tm + std::min(t, Tm - 1)) * kMovingS + speed_j[t]) * kMovingE + em.j) *
           L;
  }
};

namespace internal {
// The quarter q of a cell a weight w in [0, 1] lies in: w in [q / 4, (q + 1) / 4] (w * 4 is exact).
constexpr std::uint32_t kQuarters = 4;
[[gnu::always_inline]] inline std::uint32_t quarter_of(float w) {
  return std::min(static_cast<std::uint32_t>(w * float(kQuarters)), kQuarters - 1);
}
// The weights [*from, *to] of a cell a decision at weight w stands over: its quarter, or the whole
// cell [0, 1].
inline void weight_range(bool quartered, float w, float* from, float* to) {
  const float q = quartered ? float(quarter_of(w)) : 0.0f, span = quartered ? 1.0f / kQuarters : 1.0f;
  *from = q * span;
  *to = (q + 1.0f) * span;
}
}  // namespace internal

// Of object id's candidate views, the one nearest to the direction to the eye (object space), and the
// slip [deg/s] in its image axes (*vx, *vy): where the slip meets the profile's orientations.
inline std::uint32_t Scheduler::Impl::aim(ObjectId id, const std::uint16_t* cand, Vec3 to_eye, Vec3 slip,
                                          float* vx, float* vy) const {
  const ProfileCache& pc = profiles_[profile_of_[id]];
  const Profile& p = pc.profile;
  const std::uint32_t view = nearest_view(p, cand, to_eye);
  const float q[4] = {rotation_[0][id], rotation_[1][id], rotation_[2][id], rotation_[3][id]};
  slip_in_view(slip, q, &pc.view_right[3 * std::size_t(view)], p.views[view].up, vx, vy);
  return view;
}

}  // namespace acuity
