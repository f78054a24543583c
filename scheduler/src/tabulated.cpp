// The tabulated path, a block at a time (update()): table positions, the decision over every view,
// the decision through the view, and the memos it keeps (docs/design.md section 6).
#include "memory.hpp"

namespace acuity {

// Whether x passes `entry` (x <= entry), narrowing (*lo, *hi] to the x where the outcome is the same.
[[gnu::always_inline]] inline bool passes_narrowing(std::int32_t x, std::int32_t entry, std::int32_t* lo,
                                                    std::int32_t* hi) {
  const bool passes = x <= entry;
  *lo = passes ? *lo : std::max(*lo, entry);
  *hi = passes ? std::min(*hi, entry) : *hi;
  return passes;
}

// The level the bounds over every view decide for one object (set 0: score <= 1, set 1: <= 1 - margin),
// or -1 where its view would matter. A view's bound between its cell's two nodes lies between the
// least and the most of them, so for a still object the coarsest level passing the least bound
// passes in its view too, and no coarser one passes where it fails the most: when the two agree,
// that is the level. A moving one (or one whose view's image axes see no slip) is decided only where
// the least still and slow bound passes the coarsest level. Integers: x [ln deg] rounded up to the
// tables' step passes an entry exactly where x does.
// The row of the cell's lower node (the upper node's follows it).
[[gnu::always_inline]] inline const std::int16_t* Scheduler::Impl::any_view_row(const ProfileCache& pc,
                                                                                std::uint32_t L,
                                                                                std::uint32_t bands,
                                                                                std::uint32_t ec, int set) {
  return &pc.tables.sets[set].any_view[((std::size_t(bands) - 1) * kStillE + ec) * (2 * std::size_t(L) + 1)];
}
// row: any_view_row()'s for a profile of L coarser levels; x: the object's ln angular diameter
// rounded up to the tables' step [1/1024 ln deg]. Over the whole cell: each entry the least (or most)
// of its two nodes'. (*lo, *hi] narrows to the x where each entry compared keeps its outcome (lo the
// largest below x, hi the least at or above it): there the result is the same, so a memo of it
// stands there.
[[gnu::always_inline]] inline int Scheduler::Impl::any_view_level(const std::int16_t* row, std::uint32_t L,
                                                                  std::int32_t x, bool still,
                                                                  std::int32_t* lo, std::int32_t* hi) {
  const std::int16_t* upper = row + 2 * L + 1;
  if (!still)
    return passes_narrowing(x, std::min(row[2 * L], upper[2 * L]), lo, hi) ? static_cast<int>(L) : -1;
  int passes = 0, may_pass = 0;
  for (std::uint32_t k = 1; k <= L; ++k) {
    passes = passes_narrowing(x, std::min(row[k - 1], upper[k - 1]), lo, hi) ? static_cast<int>(k) : passes;
    may_pass = passes_narrowing(x, std::max(row[L + k - 1], upper[L + k - 1]), lo, hi) ? static_cast<int>(k)
                                                                                       : may_pass;
  }
  return passes == may_pass ? passes : -1;
}
namespace {
// between() rounds: a few float steps at |bound| <= 32 ln deg; this much more keeps the bounds' sides
// at an object's place in the any-view cell (the views' own bounds are rounded too).
constexpr float kAnyViewRounding = 1.0f / 4096;
// The lines any_view_level_at() compares x against (stand_at_place()'s `lines`), for a row as there.
template <class Line>
void any_view_lines(const std::int16_t* row, std::uint32_t L, bool still, const Line& line) {
  const std::int16_t* upper = row + 2 * L + 1;
  if (!still) return line(row[2 * L], upper[2 * L], -kAnyViewRounding);
  for (std::uint32_t k = 1; k <= L; ++k) {
    line(row[k - 1], upper[k - 1], -kAnyViewRounding);
    line(row[L + k - 1], upper[L + k - 1], kAnyViewRounding);
  }
}
}  // namespace

// The same at the object's place in the cell: the nodes' least (and most) interpolated at the upper
// node's weight w, as each view's bound is. Each view's bound is linear in w between its nodes, so
// the least (most) over the views is at least (at most) the line between the nodes' least (most):
// still a bound over every view, and a closer one. x: the object's ln angular diameter [ln deg].
// Decides more objects than any_view_level(), for this eccentricity (stand_at_place() finds how far
// around it the decision stands).
[[gnu::always_inline]] inline int Scheduler::Impl::any_view_level_at(const std::int16_t* row, std::uint32_t L,
                                                                     float x, float w, bool still) {
  const std::int16_t* upper = row + 2 * L + 1;
  const auto at = [&](std::uint32_t i) { return between(row[i], upper[i], w); };
  if (!still) return x <= at(2 * L) - kAnyViewRounding ? static_cast<int>(L) : -1;
  int passes = 0, may_pass = 0;
  for (std::uint32_t k = 1; k <= L; ++k) {
    passes = x <= at(k - 1) - kAnyViewRounding ? static_cast<int>(k) : passes;
    may_pass = x <= at(L + k - 1) + kAnyViewRounding ? static_cast<int>(k) : may_pass;
  }
  return passes == may_pass ? passes : -1;
}

// The level that table_choice() would give wherever the object is in its cells (its still or slow
// cell's two eccentricity nodes and, moving, each orientation's moving cell's four corners) for table
// set o.tables + set, or -1 where its place in them matters; `quartered`: wherever it is in the
// quarters of its cells it lies in (quarter_of() of each weight; a moving object's). Each bound
// table_choice() interpolates lies between the least and the most of its values at the ends of the
// weights' ranges (interpolation rounds monotonically), so the coarsest level passing the least
// passes there too, and none failing the most does. Integers, x and (*lo, *hi] as in
// any_view_level(): a bound in table steps rounded down for the least, up for the most (entries,
// the whole cells' corners, are exact). A moving object's cells must be set (o.cells).
int Scheduler::Impl::view_cell_level(const ProfileCache& pc, const Probe& o, std::int32_t x, int set,
                                     bool quartered, std::int32_t* lo, std::int32_t* hi) {
  const ProfileMeta& m = pc.profile.meta;
  const std::uint32_t T = m.orientation_count, B = m.band_count, L = m.level_count - 1;
  const ProfileTableSets::Tables& tables = pc.tables.sets[o.tables + set];
  const std::vector<std::int16_t>& near = o.moving ? tables.slow : tables.still;
  float ec_from, ec_to, em_from = 0.0f, em_to = 1.0f;
  weight_range(quartered, o.ec.w, &ec_from, &ec_to);
  if (o.moving) weight_range(quartered, o.em.w, &em_from, &em_to);
  // A bound in table steps, rounded down (up).
  const auto step_below = [](float v) { return std::int32_t(std::floor(v * kSizeSteps)); };
  const auto step_above = [](float v) { return std::int32_t(std::ceil(v * kSizeSteps)); };
  for (std::uint32_t k = L; k >= 1; --k) {
    bool least = true, most = true;  // every view passes its least (most) bound
    for (std::uint32_t c = 0; c < o.view_count && most; ++c) {
      const std::int16_t* row = &near[o.still_row(c, B, L) + (k - 1)];
      std::int32_t near_least = std::min(row[0], row[L]), near_most = std::max(row[0], row[L]);
      if (quartered) {
        const float near_from = between(row[0], row[L], ec_from), near_to = between(row[0], row[L], ec_to);
        near_least = step_below(std::min(near_from, near_to));
        near_most = step_above(std::max(near_from, near_to));
      }
      bool view_least = passes_narrowing(x, near_least, lo, hi);
      bool view_most = view_least || passes_narrowing(x, near_most, lo, hi);
      if (o.moving && !view_least) {  // the moving bound: its least (most) over the orientations
        bool moving_least = true, moving_most = !view_most;
        for (std::uint32_t t = 0; t < T && (moving_least || moving_most); ++t) {
          const std::int16_t* r0 = &tables.moving[o.moving_row(c, t, pc.moving_orientations, L) + (k - 1)];
          const std::int16_t* r1 = r0 + std::size_t(kMovingE) * L;
          // Over whole cells the corners are the four entries (between() at weights 0 and 1 gives
          // them exactly): their least and most in integers, as the floats below would give them.
          std::int32_t least_corner = std::min(std::min(r0[0], r0[L]), std::min(r1[0], r1[L]));
          std::int32_t most_corner = std::max(std::max(r0[0], r0[L]), std::max(r1[0], r1[L]));
          if (quartered) {
            float s_from, s_to;
            weight_range(quartered, o.speed_w[t], &s_from, &s_to);
            float corners[4];
            for (int e = 0; e < 2; ++e) {  // at each eccentricity end, the speed interpolation's ends
              const float w = e ? em_to : em_from;
              const float slow_node = between(r0[0], r0[L], w), fast_node = between(r1[0], r1[L], w);
              corners[2 * e] = slow_node + s_from * (fast_node - slow_node);
              corners[2 * e + 1] = slow_node + s_to * (fast_node - slow_node);
            }
            least_corner =
                step_below(std::min(std::min(corners[0], corners[1]), std::min(corners[2], corners[3])));
            most_corner =
                step_above(std::max(std::max(corners[0], corners[1]), std::max(corners[2], corners[3])));
          }
          // A step of room: inside the box, the speed interpolation of two interpolated floats can
          // round an ulp past its corners.
          if (moving_least) moving_least = passes_narrowing(x, least_corner - 1, lo, hi);
          if (moving_most) moving_most = passes_narrowing(x, most_corner + 1, lo, hi);
        }
        view_least = moving_least;
        view_most = view_most || moving_most;
      }
      least = least && view_least;
      most = most && view_most;
    }
    if (least) return static_cast<int>(k);
    if (most) return -1;
  }
  return 0;
}

// The inputs of the tables for a block's objects (tabulate()'s pass 1), branch-free so that it
// vectorises: the tables' x and eccentricity cell and whether the image is still on the retina (as
// retinal_slip() finds it); with these, whether each object's memo stands (never with use_memo false).
struct Scheduler::Impl::Inputs {
  std::int32_t x_step[kBlock];  // ln angular diameter in table steps, rounded up
  std::uint32_t ec_j[kBlock];
  float ec_w[kBlock], inv_diam[kBlock];
  std::uint32_t still[kBlock];      // 0 or 1, as wide as the loop's floats (so it vectorises)
  std::uint32_t memo_hit[kBlock];   // 0 or 1: decided by its memo
  std::uint32_t view_memo[kBlock];  // 0 or 1: by its memo if the view and speed cells are the same
};
ACUITY_SIMD_CLONES void Scheduler::Impl::table_inputs(const EyeCache& eye, std::uint32_t first,
                                                      std::uint32_t n, const Block& b, const Memo& memo,
                                                      bool use_memo, Inputs* out) const {
  const Vec3 tracked = eye.gaze_moving ? eye.gaze_velocity : Vec3{0, 0, 0};
  const std::uint16_t* memo_key = &memo.key[first];
  const std::int16_t *x_from = &memo.x_from[first], *x_to = &memo.x_to[first];
  const std::uint16_t *w_from = &memo.w_from[first], *w_to = &memo.w_to[first];
  const float *f_lo = &memo.f_lo[first], *f_hi = &memo.f_hi[first];
  const std::uint8_t* bias_tables = &bias_tables_[first];
  const std::uint32_t check = use_memo;
  Inputs& o = *out;
  ACUITY_NO_ALIAS
  for (std::uint32_t j = 0; j < n; ++j) {
    const std::int32_t x = size_steps_above(b.ln_diam[j]);
    o.x_step[j] = x;
    const Cell ec = e_cell<kStillE>(b.e[j]);
    o.ec_j[j] = ec.j;
    o.ec_w[j] = ec.w;
    const std::uint32_t still = no_retinal_slip(Vec3{b.image[0][j], b.image[1][j], b.image[2][j]}, tracked);
    o.still[j] = still;
    const float inv_diam = 1.0f / (2.0f * b.radius_deg[j]);  // as the exact path computes each frequency
    o.inv_diam[j] = inv_diam;
    const std::uint32_t seen = (b.test[j] == 0.0f) & (b.d[j] > b.r[j]);
    const std::uint32_t same_bands =
        (f_lo[j] * inv_diam <= b.nyquist[j]) & !(f_hi[j] * inv_diam <= b.nyquist[j]);
    const std::uint32_t key = memo_key[j], through_view = (key & Memo::kThroughView) != 0;
    const std::uint32_t stands =
        check & seen &
        ((key & ~std::uint32_t(Memo::kThroughView)) == Memo::key_of(ec.j, still, bias_tables[j])) &
        same_bands & (x_from[j] <= x) & (x <= x_to[j]) & (float(w_from[j]) <= ec.w * kWeightSteps) &
        (ec.w * kWeightSteps <= float(w_to[j]));
    o.memo_hit[j] = stands & (through_view ^ 1u);
    o.view_memo[j] = stands & through_view;
  }
}

// One eye, the objects of a block, in passes that each prefetch what the next reads, so a block's
// cache misses overlap: the inputs of the bounds over every view and the objects the memo decides
// (pass 1, table_inputs()), the objects decided without tables and the any-view rows of the rest
// (2), the any-view decisions, over the whole cell or at the object's place, remembered where they
// stand (3); for the objects they leave, the view, slip and grid cell, with which a memo made
// through the view decides (4), the moving rows (5) and the decision, over the whole cells or at
// the object's place in them, remembered where it stands (6). Objects not seen (invalid input, eye
// inside) take the fallback or finest level; an object whose bias has no tables (not a tabulated
// bias) is evaluated exactly. Writes out[j], and with `scores` (kMaxLevels per object) each level's
// score (no memo then).
// tabulate()'s passes share one block's state: what each pass leaves the next (objects by their
// index j in the block).
struct Scheduler::Impl::Tabulation {
  Inputs in;                            // pass 1: table positions and memo hits
  std::uint32_t decided[kBlock];        // by a memo
  std::uint32_t bands[kBlock];          // the lowest bands the display shows
  std::uint8_t miss[kBlock];            // the objects no memo decided ...
  std::uint32_t miss_count = 0;         // ... and their count
  std::uint8_t todo[kBlock];            // 2: the bounds over every view first; 1: through the object's view
  std::uint8_t tables[kBlock];          // the object's bias's first table set (kTableSets)
  const std::int16_t* rows[2][kBlock];  // the any-view rows, per margin set
  std::uint8_t standing[kBlock];        // decided by a memo that stands now: its rest may be set
  const std::uint16_t* cand[kBlock];    // the lookup cell's candidate views
  static_assert(kBlock <= 256, "left[] holds block indices in bytes");
  std::uint8_t left[kBlock];     // the objects left for passes 4 to 6 ...
  std::uint32_t left_count = 0;  // ... and their count
  Probe probe[kBlock];
  std::uint8_t gaze_flag;
  int sets;    // the hysteresis margin's tables too
  bool holds;  // holds of the view are set (a steady eye: EyeCache::steady)
};

void Scheduler::Impl::tabulate_memos(const EyeCache& eye, std::uint32_t first, std::uint32_t n,
                                     const Block& b, const Memo& memo, bool scores, Tabulation& tb) const {
  auto& decided = tb.decided;
  auto& bands = tb.bands;
  auto& miss = tb.miss;
  const float* inv_diam = tb.in.inv_diam;
  const std::uint32_t *memo_hit = tb.in.memo_hit, *view_memo = tb.in.view_memo;
  // Pass 1: the tables' x and eccentricity cell, still or moving, whether the memo stands.
  table_inputs(eye, first, n, b, memo, !scores, &tb.in);
  // Objects whose memo through the view stands keep its decision while the view and cells are
  // the same, which they are within its hold (Memo::Hold; only these holds are read, and none
  // before the memo has set one: until then each reads turn < 0).
  std::uint8_t viewed[kBlock];
  std::uint32_t viewed_count = 0;
  for (std::uint32_t j = 0; j < n; ++j) decided[j] = memo_hit[j];
  if (memo.any_hold)
    for (std::uint32_t j = 0; j < n; ++j) {
      viewed[viewed_count] = static_cast<std::uint8_t>(j);
      viewed_count += view_memo[j];
    }
  for (std::uint32_t i = 0; i < viewed_count; ++i) {
    const std::uint32_t j = viewed[i];
    const Memo::Hold& h = memo.hold[first + j];
    const Vec3 image{b.image[0][j], b.image[1][j], b.image[2][j]};
    const Vec3 turned = b.to_eye_at(j) - load(h.direction);
    const Vec3 slipped =
        retinal_slip(image, eye.gaze_moving, eye.gaze_velocity, config_.params) - load(h.slip);
    decided[j] = std::uint32_t(h.turn >= 0.0f) & std::uint32_t(dot(turned, turned) <= h.turn * h.turn) &
                 std::uint32_t(dot(slipped, slipped) <= h.reach * h.reach) &
                 std::uint32_t(h.e_from <= b.e[j]) & std::uint32_t(b.e[j] <= h.e_to);
  }
  // The bands the display shows of the rest (the lowest n: the rest are invisible whatever the eye).
  // Counted in a local: a count kept in tb would be stored and loaded again after each byte
  // written to miss[] (bytes may alias it).
  std::uint32_t miss_count = 0;
  for (std::uint32_t j = 0; j < n; ++j) {
    miss[miss_count] = static_cast<std::uint8_t>(j);
    miss_count += decided[j] ^ 1u;
  }
  tb.miss_count = miss_count;
  for (std::uint32_t i = 0; i < miss_count; ++i) {
    const std::uint32_t j = miss[i];
    const float* frequency = &band_frequency_[std::size_t(std::max(profile_of_[first + j], 0)) * kMaxBands];
    std::uint32_t shown = 0;
    for (std::uint32_t k = 0; k < max_band_count_; ++k) shown += frequency[k] * inv_diam[j] <= b.nyquist[j];
    bands[j] = shown;
  }
}

void Scheduler::Impl::tabulate_rows(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b,
                                    Memo& memo, Choice* out, float (*scores)[kMaxLevels],
                                    Tabulation& tb) const {
  auto& decided = tb.decided;
  auto& bands = tb.bands;
  auto& miss = tb.miss;
  const std::uint32_t miss_count = tb.miss_count;
  auto& todo = tb.todo;
  auto& tables = tb.tables;
  auto& rows = tb.rows;
  auto& standing = tb.standing;
  const int sets = tb.sets;
  const std::uint8_t gaze_flag = tb.gaze_flag;
  const std::uint32_t *ec_j = tb.in.ec_j, *view_memo = tb.in.view_memo;
  // Pass 2: objects decided by their memo; of the rest, those not seen, of a bias without tables or
  // with nothing to choose; the any-view rows of the others found (per table set) and prefetched, so
  // that pass 3 decides without reading a profile.
  const std::uint8_t *memo_fine = &memo.fine[first], *memo_coarse = &memo.coarse[first];
  for (std::uint32_t j = 0; j < n; ++j) {  // the memo's decision for every object: misses overwrite it
    standing[j] = static_cast<std::uint8_t>(decided[j]);
    todo[j] = 0;
    out[j] = {memo_fine[j], memo_coarse[j], gaze_flag};
  }
  for (std::uint32_t i = 0; i < miss_count; ++i) {
    const std::uint32_t j = miss[i];
    const ObjectId id = first + j;
    const int p = profile_of_[id];
    if (p < 0) continue;
    const Look look = b.state(j);
    if (look != Look::Ok || bias_tables_[id] == kExactBias) {
      Sight s;
      if (look == Look::Ok) {
        sight(id, eye, b, j, &s);
        aim(id, &s);
      }
      out[j] = evaluate(id, look, s, scores ? scores[j] : nullptr, nullptr);
      memo.forget(id);
      continue;
    }
    const ProfileCache& pc = profiles_[p];
    const std::uint32_t L = pc.profile.meta.level_count - 1;
    if (L == 0 || bands[j] == 0) {  // one level, or none of it shown: no tables to read
      memo.forget(id);
      const auto top = static_cast<std::uint8_t>(bands[j] == 0 ? L : 0);
      out[j] = {top, top, gaze_flag};
      if (scores) std::fill(scores[j], scores[j] + L + 1, 0.0f);
      continue;
    }
    todo[j] = 1;
    tables[j] = static_cast<std::uint8_t>(2 * bias_tables_[id]);
    if (scores) continue;                      // every level's score: the view's tables
    if (view_memo[j] || !pc.has_any_view()) {  // its memo through the view decides if the view and
      ACUITY_PREFETCH(&memo.view_key[id]);     // cells are the same; no bounds over every view yet
      ACUITY_PREFETCH(&memo.speed_key[id]);
      continue;
    }
    todo[j] = 2;
    for (int set = 0; set < sets; ++set) {
      const std::int16_t* row = any_view_row(pc, L, bands[j], ec_j[j], tables[j] + set);
      rows[set][j] = row;
      ACUITY_PREFETCH(row);
      ACUITY_PREFETCH(row + 4 * L + 1);  // the upper node's row ends here
    }
  }
}

void Scheduler::Impl::tabulate_any_view(std::uint32_t first, const Block& b, Memo& memo, Choice* out,
                                        Tabulation& tb) const {
  auto& bands = tb.bands;
  auto& miss = tb.miss;
  const std::uint32_t miss_count = tb.miss_count;
  auto& todo = tb.todo;
  auto& rows = tb.rows;
  auto& standing = tb.standing;
  const int sets = tb.sets;
  const std::uint8_t gaze_flag = tb.gaze_flag;
  auto& cand = tb.cand;
  const std::int32_t* x_step = tb.in.x_step;
  const std::uint32_t *ec_j = tb.in.ec_j, *still = tb.in.still;
  const float* ec_w = tb.in.ec_w;
  // Pass 3: the any-view decisions, over the cell or else at the object's place in it, remembered with
  // the x and eccentricity where they stand; the rest have their lookup cell (of the direction to the
  // eye) found and its candidates prefetched.
  for (std::uint32_t i = 0; i < miss_count; ++i) {
    const std::uint32_t j = miss[i];
    if (!todo[j]) continue;
    const ObjectId id = first + j;
    if (todo[j] == 2) {
      const std::uint32_t L = level_count_[profile_of_[id]] - 1u;
      Stand stand;  // the whole cell
      int fine = any_view_level(rows[0][j], L, x_step[j], still[j], &stand.lo, &stand.hi);
      int coarse = sets > 1 && fine >= 0
                       ? any_view_level(rows[1][j], L, x_step[j], still[j], &stand.lo, &stand.hi)
                       : fine;
      bool remembered = coarse >= 0;
      if (coarse < 0) {  // not over the whole cell: at the object's place in it, remembered around it
        const float x = b.ln_diam[j], w = ec_w[j];
        fine = any_view_level_at(rows[0][j], L, x, w, still[j]);
        coarse = sets > 1 && fine >= 0 ? any_view_level_at(rows[1][j], L, x, w, still[j]) : fine;
        const auto lines = [&](const auto& line) {
          for (int set = 0; set < sets; ++set) any_view_lines(rows[set][j], L, still[j], line);
        };
        remembered = coarse >= 0 && stand_at_place(x, x_step[j], w, lines, &stand);
      }
      todo[j] = coarse < 0;
      if (coarse >= 0)
        out[j] = {static_cast<std::uint8_t>(fine), static_cast<std::uint8_t>(coarse), gaze_flag};
      standing[j] = remembered;
      if (remembered)
        memo.remember(id, Memo::key_of(ec_j[j], still[j], bias_tables_[id]), stand,
                      &band_frequency_[std::size_t(profile_of_[id]) * kMaxBands], bands[j], fine, coarse);
    }
    if (todo[j]) {
      cand[j] = lookup_candidates(profiles_[profile_of_[id]].profile, b, j);
      ACUITY_PREFETCH(cand[j]);
    }
  }
}

void Scheduler::Impl::tabulate_views(const EyeCache& eye, std::uint32_t first, std::uint32_t n,
                                     const Block& b, Memo& memo, Choice* out, float (*scores)[kMaxLevels],
                                     std::uint16_t* want, Tabulation& tb) const {
  auto& bands = tb.bands;
  auto& todo = tb.todo;
  auto& tables = tb.tables;
  auto& standing = tb.standing;
  const int sets = tb.sets;
  auto& cand = tb.cand;
  auto& left = tb.left;
  auto& probe = tb.probe;
  const std::uint32_t *ec_j = tb.in.ec_j, *still = tb.in.still, *view_memo = tb.in.view_memo;
  const float* ec_w = tb.in.ec_w;
  // The objects left for passes 4 to 6, listed without branches (which ones remain is
  // unpredictable), counted in a local (as tabulate_memos()'s misses).
  std::uint32_t left_count = 0;
  for (std::uint32_t j = 0; j < n; ++j) {
    left[left_count] = static_cast<std::uint8_t>(j);
    left_count += todo[j] != 0;
  }
  tb.left_count = left_count;
  // Pass 4: the nearest view, the slip in its image axes; the objects whose memo through the view
  // stands decided, those of a view without tables yet (add_profile_deferred) decided exactly and
  // the view wanted, the still (or slow) rows of the others prefetched.
  const bool max3 = config_.view_blend == ViewBlend::Max3;
  for (std::uint32_t i = 0; i < left_count; ++i) {
    const std::uint32_t j = left[i];
    const ObjectId id = first + j;
    const ProfileCache& pc = profiles_[profile_of_[id]];
    const Profile& p = pc.profile;
    const std::uint32_t B = p.meta.band_count, L = p.meta.level_count - 1;
    Probe& o = probe[j];
    o.x = b.ln_diam[j];
    o.tables = tables[j];
    o.bands = bands[j];
    o.ec = {ec_j[j], ec_w[j]};
    const Vec3 image{b.image[0][j], b.image[1][j], b.image[2][j]};
    const Vec3 slip = retinal_slip(image, eye.gaze_moving, eye.gaze_velocity, config_.params);
    const std::uint32_t view = aim(id, cand[j], b.to_eye_at(j), slip, &o.vx, &o.vy);
    o.moving = o.vx != 0.0f || o.vy != 0.0f;
    o.cells = false;
    o.em = {0, 0.0f};
    o.view_count = max3 ? std::uint8_t(kLookupCandidates) : std::uint8_t(1);
    o.where = max3 ? static_cast<std::uint32_t>((cand[j] - p.lookup) / kLookupCandidates) : view;
    o.nearest = view;
    pc.note_read(o.where, max3, frame_);
    o.slip = slip;
    o.decided = o.at_place = false;
    const std::uint32_t T = p.meta.orientation_count;
    if (view_memo[j] && Memo::keyable(o.moving, T)) {  // the same view and cells?
      if (o.moving) speed_cells(pc, b.e[j], &o);
      const bool quartered = (memo.view_key[id] & Memo::kQuartered) != 0;
      const bool same = memo.view_key[id] == Memo::view_key_of(o, quartered) &&
                        memo.speed_key[id] == Memo::speed_key_of(o, T, quartered);
      o.at_place = same && memo.fine[id] == Memo::kAtPlace;
      o.decided = same && !o.at_place;
      standing[j] = o.decided;
      if (o.decided) {  // out[j] holds its memo's decision; its hold moves here (else the one
                        // it had, made for the same memo, stays)
        if (tb.holds) hold_view(memo, id, pc, o, cand[j], b, j, quartered, still[j]);
        continue;
      }
    }
    std::uint32_t lacking = 0;  // 1 + a view without tables
    for (std::uint32_t c = 0; c < o.view_count; ++c) {
      const std::uint16_t v = max3 ? cand[j][c] : static_cast<std::uint16_t>(view);
      o.rows[c] = pc.slot[v];
      if (o.rows[c] == ProfileCache::kNoRow) lacking = v + 1u;
    }
    if (lacking) {
      want[j] = static_cast<std::uint16_t>(lacking);
      Sight s;
      sight(id, eye, b, j, &s);
      aim(id, &s);
      out[j] = evaluate(id, Look::Ok, s, scores ? scores[j] : nullptr, nullptr);
      memo.forget(id);
      o.decided = true;
      continue;
    }
    for (std::uint32_t c = 0; c < o.view_count; ++c) {
      for (int set = 0; set < sets; ++set) {  // the two nodes' rows, which may cross a line
        const ProfileTableSets::Tables& ts = pc.tables.sets[o.tables + set];
        const std::int16_t* row = &(o.moving ? ts.slow : ts.still)[o.still_row(c, B, L)];
        ACUITY_PREFETCH(row);
        ACUITY_PREFETCH(row + 2 * L - 1);
      }
    }
  }
  // Pass 5: moving objects whose slow bound (read a pass after its prefetch) does not pass the coarsest
  // level: their grid cells, and the moving tables' rows they read prefetched (most never read them).
  for (std::uint32_t i = 0; i < left_count; ++i) {
    const std::uint32_t j = left[i];
    Probe& o = probe[j];
    if (!o.moving || o.decided) continue;
    const ProfileCache& pc = profiles_[profile_of_[first + j]];
    const std::uint32_t B = pc.profile.meta.band_count, T = pc.profile.meta.orientation_count,
                        L = pc.profile.meta.level_count - 1;
    for (std::uint32_t c = 0; c < o.view_count; ++c) {
      const std::int16_t* slow =
          &pc.tables.sets[o.tables].slow[o.still_row(c, B, L) + (L - 1)];  // the coarsest level
      if (o.x <= between(slow[0], slow[L], o.ec.w)) continue;
      if (!o.cells) speed_cells(pc, b.e[j], &o);
      // At its place, table_choice() mostly decides within the first orientations; over the whole
      // cells (view_cell_level()), it reads them all.
      const std::uint32_t read = o.at_place ? std::min(T, 2u) : T;
      for (std::uint32_t t = 0; t < read; ++t) {
        const std::int16_t* r0 =
            &pc.tables.sets[o.tables].moving[o.moving_row(c, t, pc.moving_orientations, L)];
        ACUITY_PREFETCH_L2(r0);
        ACUITY_PREFETCH_L2(r0 + std::size_t(kMovingE) * L);
      }
    }
  }
}

void Scheduler::Impl::tabulate_through_view(std::uint32_t first, const Block& b, Memo& memo, Choice* out,
                                            float (*scores)[kMaxLevels], Tabulation& tb) const {
  auto& bands = tb.bands;
  auto& standing = tb.standing;
  const int sets = tb.sets;
  auto& cand = tb.cand;
  auto& left = tb.left;
  const std::uint32_t left_count = tb.left_count;
  auto& probe = tb.probe;
  const std::uint8_t gaze_flag = tb.gaze_flag;
  const std::int32_t* x_step = tb.in.x_step;
  const std::uint32_t *ec_j = tb.in.ec_j, *still = tb.in.still;
  // Pass 6: the decisions through the objects' views: over their whole cells where those decide, else
  // at their place in the cells; remembered where they stand (a moving image: over whole cells or over
  // the quarters of its cells it lies in).
  for (std::uint32_t i = 0; i < left_count; ++i) {
    const std::uint32_t j = left[i];
    Probe& o = probe[j];
    if (o.decided) continue;
    const ObjectId id = first + j;
    const ProfileCache& pc = profiles_[profile_of_[id]];
    const std::uint32_t T = pc.profile.meta.orientation_count;
    if (!scores && !o.at_place && Memo::keyable(o.moving, T)) {
      if (o.moving && !o.cells) speed_cells(pc, b.e[j], &o);
      Stand stand;  // the whole cells
      int fine = view_cell_level(pc, o, x_step[j], 0, false, &stand.lo, &stand.hi);
      int coarse =
          sets > 1 && fine >= 0 ? view_cell_level(pc, o, x_step[j], 1, false, &stand.lo, &stand.hi) : fine;
      bool stands = coarse >= 0, quartered = false;
      if (!stands && o.moving && Memo::quarterable(T)) {  // a moving image: over its cells' quarters
        stand = Stand{};
        float w_from, w_to;
        weight_range(true, o.ec.w, &w_from, &w_to);
        stand.w_from = static_cast<std::uint16_t>(w_from * kWeightSteps);
        stand.w_to = static_cast<std::uint16_t>(w_to * kWeightSteps);
        fine = view_cell_level(pc, o, x_step[j], 0, true, &stand.lo, &stand.hi);
        coarse =
            sets > 1 && fine >= 0 ? view_cell_level(pc, o, x_step[j], 1, true, &stand.lo, &stand.hi) : fine;
        stands = quartered = coarse >= 0;
      }
      if (!stands && !o.moving) {  // a still image: decided at its place in the cell, remembered around it
        const Choice at = table_choice(pc, b.e[j], o, nullptr);
        fine = at.fine;
        coarse = at.coarse;
        const std::uint32_t B = pc.profile.meta.band_count, L = pc.profile.meta.level_count - 1;
        const auto lines = [&](const auto& line) {  // table_choice()'s: each set's, view's and level's
          for (int set = 0; set < sets; ++set)
            for (std::uint32_t c = 0; c < o.view_count; ++c) {
              const std::int16_t* row = &pc.tables.sets[o.tables + set].still[o.still_row(c, B, L)];
              for (std::uint32_t k = 1; k <= L; ++k) line(row[k - 1], row[L + k - 1], 0.0f);
            }
        };
        stands = stand_at_place(o.x, x_step[j], o.ec.w, lines, &stand);
      }
      // Where it stands nowhere, the memo says so: next time at its place. Its hold, if any, is set below.
      memo.end_hold(id);
      memo.remember(id, Memo::key_of(ec_j[j], still[j], bias_tables_[id]) | Memo::kThroughView, stand,
                    &band_frequency_[std::size_t(profile_of_[id]) * kMaxBands], bands[j],
                    stands ? fine : Memo::kAtPlace, stands ? coarse : Memo::kAtPlace);
      memo.view_key[id] = Memo::view_key_of(o, quartered);
      memo.speed_key[id] = Memo::speed_key_of(o, T, quartered);
      if (stands && tb.holds) hold_view(memo, id, pc, o, cand[j], b, j, quartered, still[j]);
      standing[j] = stands;
      if (coarse >= 0) {
        out[j] = {static_cast<std::uint8_t>(fine), static_cast<std::uint8_t>(coarse), gaze_flag};
        continue;
      }
    }
    out[j] = table_choice(pc, b.e[j], o, scores ? scores[j] : nullptr);
    out[j].flags |= gaze_flag;
  }
}

void Scheduler::Impl::tabulate(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b,
                               Memo& memo, Choice* out, float (*scores)[kMaxLevels],
                               std::uint16_t* want) const {
  Tabulation tb;
  tb.gaze_flag = eye.gaze ? std::uint8_t(0) : std::uint8_t(kFlagNoGaze);
  tb.sets = margin_sets(config_);
  tb.holds = eye.steady;
  tabulate_memos(eye, first, n, b, memo, scores != nullptr, tb);
  tabulate_rows(eye, first, n, b, memo, out, scores, tb);
  tabulate_any_view(first, b, memo, out, tb);
  tabulate_views(eye, first, n, b, memo, out, scores, want, tb);
  tabulate_through_view(first, b, memo, out, scores, tb);
  const auto& standing = tb.standing;
  // Rests for the objects a standing memo decided, where the eye can rest (none with scores); where
  // few objects were at rest last frame, in one block of eight each frame (an eye that keeps moving
  // leaves them at once: little is spent on them).
  if (resting_ && !scores && (many_at_rest_ || (first / kBlock + frame_) % 8 == 0))
    for (std::uint32_t j = 0; j < n; ++j) {
      const std::uint32_t since = frame_ - memo.rest_frame[first + j];  // its last try
      if (standing[j] && (since >= (memo.rest_m[first + j] >= 0 ? Memo::kLeftRetry : Memo::kRetry) ||
                          (eyes_still_ && since > frame_ - still_since_)))
        set_rest(eye, memo, first + j, b, j);
    }
}

// A moving object's cells on the moving grid: eccentricity e [deg], each orientation's speed.
ACUITY_SIMD_CLONES void Scheduler::Impl::speed_cells(const ProfileCache& pc, float e, Probe* o) const {
  const float floor = pre_->floor_velocity, v0 = pre_->speed_offset, vx = o->vx, vy = o->vy;
  const float *cos_t = pc.cos_t.data(), *sin_t = pc.sin_t.data();
  const std::uint32_t T = pc.profile.meta.orientation_count;
  o->em = e_cell<kMovingE>(e);
  ACUITY_NO_ALIAS
  for (std::uint32_t t = 0; t < T; ++t)
    speed_cell(std::max(std::abs(vx * cos_t[t] + vy * sin_t[t]), floor), floor, v0, kMovingS, &o->speed_j[t],
               &o->speed_w[t]);
  o->cells = true;
}

// The perceptual rule through the tables: per level, is the object's angular size at most the largest
// invisible one at its eccentricity (and, moving, per orientation at its retinal speed)? With
// `scores` (K floats) every level's score; without, a moving object's bounds stop at the first that
// decides. For a profile of two or more levels and an object the display shows bands of (tabulate
// decides the others without tables).
Scheduler::Impl::Choice Scheduler::Impl::table_choice(const ProfileCache& pc, float e, Probe& o,
                                                      float* scores) const {
  const Profile& p = pc.profile;
  const std::uint32_t K = p.meta.level_count, T = p.meta.orientation_count, B = p.meta.band_count;
  const std::uint32_t L = K - 1;          // coarser levels per view
  const int sets = margin_sets(config_);  // [1]: the hysteresis margin's tables
  const float x = o.x;
  if (scores) std::fill(scores, scores + K, 0.0f);
  const Cell ec = o.ec;
  // Per set, view and level k, the largest invisible ln diameter from the still (or, moving, the
  // slow) tables; the level's bound is the smallest over the views. A still object needs no more.
  float bound[2][kLookupCandidates][kMaxLevels], size[2][kMaxLevels];
  for (int set = 0; set < sets; ++set)
    for (std::uint32_t c = 0; c < o.view_count; ++c) {
      const ProfileTableSets::Tables& tables = pc.tables.sets[o.tables + set];
      const std::int16_t* row = &(o.moving ? tables.slow : tables.still)[o.still_row(c, B, L)];
      for (std::uint32_t k = 1; k <= L; ++k) {
        bound[set][c][k] = between(row[k - 1], row[L + k - 1], ec.w);
        size[set][k] = c == 0 ? bound[set][c][k] : std::min(size[set][k], bound[set][c][k]);
      }
    }
  if (o.moving) {
    // Per orientation at its own speed, the moving tables' bound where the slow one does not pass;
    // per view the larger of the two holds. Without scores, from the coarsest level until one passes.
    if (!o.cells) speed_cells(pc, e, &o);
    const Cell em = o.em;
    const bool decide_only = scores == nullptr;
    for (std::uint32_t k = L; k >= 1; --k) {
      for (int set = 0; set < sets; ++set) {
        float least = -kNever;  // over the views
        for (std::uint32_t c = 0; c < o.view_count; ++c) {
          const float slow_bound = bound[set][c][k];
          if (decide_only && x <= slow_bound) {
            least = std::min(least, slow_bound);
            continue;
          }
          float m = -kNever;
          for (std::uint32_t t = 0; t < T; ++t) {
            const std::int16_t* r0 = &pc.tables.sets[o.tables + set]
                                          .moving[o.moving_row(c, t, pc.moving_orientations, L) + (k - 1)];
            const std::int16_t* r1 = r0 + std::size_t(kMovingE) * L;
            const float lo = between(r0[0], r0[L], em.w), hi = between(r1[0], r1[L], em.w);
            m = std::min(m, lo + o.speed_w[t] * (hi - lo));
            if (decide_only && m < x) break;  // this orientation alone makes the level visible
          }
          least = std::min(least, std::max(m, slow_bound));
        }
        size[set][k] = least;
      }
      if (decide_only && x <= size[sets - 1][k]) break;  // the coarsest level passing every set
    }
  }
  const float* coarse_size = size[sets - 1];  // without a margin, the same tables
  // The coarsest level that passes (levels above a moving object's break passed no set).
  Choice out{0, 0, 0};
  for (std::uint32_t k = 1; k <= L; ++k) {
    out.fine = x <= size[0][k] ? static_cast<std::uint8_t>(k) : out.fine;
    out.coarse = x <= coarse_size[k] ? static_cast<std::uint8_t>(k) : out.coarse;
    if (scores) scores[k] = std::exp(std::min(x - size[0][k], kLnCeiling));
  }
  return out;
}

// The tabulated path for a block whose geometry is done: each eye's choice, the finer need wins.
void Scheduler::Impl::choose_tabulated(std::uint32_t first, std::uint32_t n, const Block* blocks,
                                       Decisions* out) {
  Choice eye_choice[2][kBlock];
  float eye_scores[kBlock][kMaxLevels];  // the second eye's, with keep_scores
  auto* kept = config_.keep_scores
                   ? reinterpret_cast<float(*)[kMaxLevels]>(&scores_[std::size_t(first) * kMaxLevels])
                   : nullptr;
  for (std::uint32_t i = 0; i < eye_count_; ++i)
    tabulate(eyes_[i], first, n, blocks[i], memos_[i], eye_choice[i], kept && i > 0 ? eye_scores : kept,
             &want_[first]);
  // Members and pointers in locals: the bytes written below may alias them, which would load them
  // again per object.
  const int* profile = &profile_of_[first];
  const bool two_eyes = eye_count_ > 1;
  std::uint8_t *fine = out->fine, *coarse = out->coarse, *flags = out->flags;
  for (std::uint32_t j = 0; j < n; ++j) {
    const int p = profile[j];
    if (p < 0) continue;
    Choice c = eye_choice[0][j];
    if (two_eyes) {
      c = finer(c, eye_choice[1][j]);
      if (kept)
        for (std::uint32_t k = 0; k < level_count_[p]; ++k)
          kept[j][k] = std::max(kept[j][k], eye_scores[j][k]);
    }
    fine[j] = c.fine;
    coarse[j] = c.coarse;
    flags[j] = c.flags;
  }
}

}  // namespace acuity
