// Building the tabulated path's tables of one profile (add_profile) and their size.
#include "curves.hpp"
#include "memory.hpp"

namespace acuity {

// The threshold curves the tables are read from, on the table grid (Curves): at creation, once for
// every profile.
void Scheduler::Impl::build_curves() {
  const Precomputed& pre = *pre_;
  curves_ = std::make_unique<Curves>();
  curves_->area_weight.resize(kCurveSamples);
  for (int i = 0; i < kCurveSamples; ++i)
    curves_->area_weight[i] =
        Curves::area_w(kCurveU0 + kCurveStep * float(i), static_cast<float>(config_.params.stela.f0));
  curves_->still.resize(std::size_t(kStillE) * kCurveSamples);
  curves_->slow.resize(std::size_t(kStillE) * kCurveSamples);
  for (std::uint32_t j = 0; j < kStillE; ++j) {
    Curves::sample(pre, config_, still_e_node(j), pre.floor_velocity, false,
                   &curves_->still[j * std::size_t(kCurveSamples)]);
    Curves::sample(pre, config_, still_e_node(j), pre.floor_velocity, true,
                   &curves_->slow[j * std::size_t(kCurveSamples)]);
  }
  curves_->moving.resize(std::size_t(kMovingS) * kMovingE * kCurveSamples);
  for (std::uint32_t i = 0; i < kMovingS; ++i)
    for (std::uint32_t j = 0; j < kMovingE; ++j)
      Curves::sample(pre, config_, moving_e_node(j), Curves::speed(i, pre.floor_velocity), true,
                     &curves_->moving[(i * kMovingE + j) * std::size_t(kCurveSamples)]);
  // Each cell's interpolation is checked against the truth: Reddy's per axis in advance, the other
  // models' at the cell's midpoint (curves there).
  if (config_.model == ThresholdModel::Reddy) {
    curves_->reddy_lifts(pre.floor_velocity, pre.speed_offset);
  } else {
    curves_->still_centre.resize(std::size_t(kStillE - 1) * kCurveSamples);
    curves_->slow_centre.resize(std::size_t(kStillE - 1) * kCurveSamples);
    for (std::uint32_t j = 0; j + 1 < kStillE; ++j) {
      Curves::sample(pre, config_, Curves::still_centre_e(j), pre.floor_velocity, false,
                     &curves_->still_centre[j * std::size_t(kCurveSamples)]);
      Curves::sample(pre, config_, Curves::still_centre_e(j), pre.floor_velocity, true,
                     &curves_->slow_centre[j * std::size_t(kCurveSamples)]);
    }
    if (config_.model == ThresholdModel::Default) {
      curves_->row_checks.resize(std::size_t(kMovingS - 1) * kMovingE * (Curves::kRowChecks - 1) *
                                 kCurveSamples);
      for (std::uint32_t i = 0; i + 1 < kMovingS; ++i)
        for (std::uint32_t j = 0; j < kMovingE; ++j)
          for (int m = 1; m < Curves::kRowChecks; ++m)
            Curves::sample(
                pre, config_, moving_e_node(j),
                Curves::speed_at(i, float(m) / Curves::kRowChecks, pre.floor_velocity, pre.speed_offset),
                true, &curves_->row_checks[Curves::row_check_at(i, j, m)]);
    }
    curves_->centre.resize(std::size_t(kMovingS - 1) * (kMovingE - 1) * kCurveSamples);
    for (std::uint32_t i = 0; i + 1 < kMovingS; ++i)
      for (std::uint32_t j = 0; j + 1 < kMovingE; ++j)
        Curves::sample(pre, config_, Curves::centre_e(j),
                       Curves::centre_speed(i, pre.floor_velocity, pre.speed_offset), true,
                       &curves_->centre[(i * (kMovingE - 1) + j) * std::size_t(kCurveSamples)]);
  }
}

// Fills the tabulated path's tables of one profile (see ProfileCache): of views [first, first + count)
// (rows 0 .. count - 1), and the bounds over every view when that is all of them.
void Scheduler::Impl::build_tables(const ProfileCache& c, ProfileTableSets* sets, std::uint32_t first,
                                   std::uint32_t count) const {
  const Profile& p = c.profile;
  const std::uint32_t K = p.meta.level_count, B = p.meta.band_count, L = K - 1, V = count;
  sets->views.resize(count);
  for (std::uint32_t r = 0; r < count; ++r) sets->views[r] = static_cast<std::uint16_t>(first + r);
  const Precomputed& pre = *pre_;
  const auto margins = static_cast<std::uint32_t>(margin_sets(config_));
  // The area law's knots per level, view and band (Curves::area_knots()), once for every table set
  // (those of the views made).
  std::vector<float> knots(c.area_k.size() * Curves::kKnots);
  const std::uint32_t all_views = p.meta.view_count;
  for (std::size_t i = 0; i < c.area_k.size(); ++i) {
    const std::size_t w = i / B % all_views;  // i = ((k - 1) V + w) B + b
    if (c.area_k[i] > 0.0f && w >= first && w < first + count)
      curves_->area_knots(c.area_k[i], &knots[i * Curves::kKnots]);
  }
  const float* law_knots = c.area_k.empty() ? nullptr : knots.data();
  for (std::uint32_t set = 0; set < 2 * table_bias_count_; ++set) {
    if (set % 2 >= margins) continue;
    const float ln_bias_q = pre.ln_quality_at(table_bias_[set / 2]);
    const float ln_q = set % 2 ? ln_bias_q + pre.ln_margin : ln_bias_q;
    sets->sets[set].still.assign(std::size_t(V) * L * B * kStillE, 0);
    sets->sets[set].slow.assign(std::size_t(V) * L * B * kStillE, 0);
    sets->sets[set].moving.assign(std::size_t(V) * L * c.moving_orientations * kMovingS * kMovingE, 0);
    for (std::uint32_t r = 0; r < V; ++r)
      for (std::uint32_t k = 1; k < K; ++k) build_still(c, sets, set, ln_q, first + r, r, k, law_knots);
    build_moving(c, sets, set, ln_q, first, count, law_knots);
    if (count == p.meta.view_count) build_any_view(c, sets, set);
  }
}

// The still and slow tables of view w (in row `row`) and level k in table set `set` (ln_q: its ln q).
void Scheduler::Impl::build_still(const ProfileCache& c, ProfileTableSets* sets, std::uint32_t set,
                                  float ln_q, std::uint32_t w, std::uint32_t row, std::uint32_t k,
                                  const float* knots) const {
  const Profile& p = c.profile;
  const std::uint32_t V = p.meta.view_count, B = p.meta.band_count, L = p.meta.level_count - 1;
  const Precomputed& pre = *pre_;
  const bool midpoints = curves_->still_lift.empty();  // each cell checked at its midpoint (not Reddy)
  const std::size_t kv = std::size_t(k - 1) * V + w;
  AreaLaw laws[kMaxBands];  // each band's area law
  for (std::uint32_t b = 0; b < B && knots; ++b)
    laws[b] = {c.area_k[kv * B + b], &knots[(kv * B + b) * Curves::kKnots]};
  std::vector<std::int16_t>& still = sets->sets[set].still;
  // Still and slow: per band, then the minimum over the bands the display shows (prefix minima).
  // Where a cell's midpoint shows the interpolation above the truth (a convex kink: the CSF's
  // peak, a model's eccentricity step), the cell's two nodes come down by the excess.
  for (int moving_floor = 0; moving_floor < 2; ++moving_floor) {
    const bool slow = moving_floor != 0;
    float node[kStillE][kMaxBands], mid[kStillE][kMaxBands];
    int hint[kMaxBands], mid_hint[kMaxBands];  // each band's bracket at the previous node
    std::fill(hint, hint + kMaxBands, kCurveSamples / 2);
    std::fill(mid_hint, mid_hint + kMaxBands, kCurveSamples / 2);
    for (std::uint32_t j = 0; j < kStillE; ++j) {
      const float* curve = &(slow ? curves_->slow : curves_->still)[j * std::size_t(kCurveSamples)];
      float prefix = -kNever, mid_prefix = -kNever;
      for (std::uint32_t b = 0; b < B; ++b) {
        const float y = c.ln_lost_any[kv * B + b] - ln_q;
        prefix = Curves::largest_size_within(prefix, pre, config_, curve, y, c.ln_band[b], still_e_node(j),
                                             pre.floor_velocity, slow, &hint[b], laws[b]);
        node[j][b] = prefix;
        if (j + 1 < kStillE && midpoints) {
          const float* centre =
              &(slow ? curves_->slow_centre : curves_->still_centre)[j * std::size_t(kCurveSamples)];
          mid_prefix = Curves::largest_size_within(mid_prefix, pre, config_, centre, y, c.ln_band[b],
                                                   Curves::still_centre_e(j), pre.floor_velocity, slow,
                                                   &mid_hint[b], laws[b]);
        }
        mid[j][b] = mid_prefix;
      }
    }
    float lower[kStillE][kMaxBands] = {};
    for (std::uint32_t j = 0; j + 1 < kStillE; ++j)
      for (std::uint32_t b = 0; b < B; ++b) {
        if (node[j][b] <= kNever || node[j + 1][b] >= -kNever) continue;
        if (!midpoints) {  // Reddy: known in advance
          lower[j][b] = std::max(lower[j][b], curves_->still_lift[j].lower);
          lower[j + 1][b] = std::max(lower[j + 1][b], curves_->still_lift[j].upper);
          continue;
        }
        const float excess = 0.5f * (node[j][b] + node[j + 1][b]) - mid[j][b];
        if (excess > 0) {
          lower[j][b] = std::max(lower[j][b], excess);
          lower[j + 1][b] = std::max(lower[j + 1][b], excess);
        }
      }
    std::vector<std::int16_t>& table = slow ? sets->sets[set].slow : still;
    for (std::uint32_t j = 0; j < kStillE; ++j)
      for (std::uint32_t b = 0; b < B; ++b)
        table[((std::size_t(row) * B + b) * kStillE + j) * L + (k - 1)] =
            encode_size(node[j][b] - lower[j][b]);
  }
}

// The moving tables of table set `set` (ln_q: its ln q) for views [first, first + count), every
// view, level and orientation row at once (a row each; one per view and level where every
// orientation reads the same loss): each curve is read for every row in turn while it is in the
// cache (built per view and level, every curve was read again for each). Each row's entries are
// what they were when built one at a time: a row's nodes, lowerings and checks come in the same
// order, and a search's hint or lead band changes only how fast it finds its value
// (Curves::least_sampled()).
void Scheduler::Impl::build_moving(const ProfileCache& c, ProfileTableSets* sets, std::uint32_t set,
                                   float ln_q, std::uint32_t first, std::uint32_t count,
                                   const float* knots) const {
  const Profile& p = c.profile;
  const std::uint32_t V = p.meta.view_count, T = p.meta.orientation_count, Tm = c.moving_orientations,
                      B = p.meta.band_count, L = p.meta.level_count - 1;
  const Precomputed& pre = *pre_;
  const bool midpoints = curves_->still_lift.empty();  // each cell checked at its midpoint (not Reddy)
  const std::size_t N = std::size_t(kMovingS) * kMovingE, R = std::size_t(count) * L * Tm;
  // Row r = (w L + (k - 1)) Tm + t: view first + w, level k, orientation t at its own speed, every band.
  std::vector<float> y(R * kMaxBands), nodes(R * N), lowers(R * N, 0.0f);
  std::vector<AreaLaw> laws(R * kMaxBands);  // each row's and band's area law (its level, view and band's)
  std::vector<int> hints(R * kMaxBands, kCurveSamples / 2);  // each row's brackets at the previous node
  std::vector<std::uint32_t> leads(R, 0);                    // and its least band there
  for (std::uint32_t w = 0; w < count; ++w)
    for (std::uint32_t k = 1; k <= L; ++k)
      for (std::uint32_t t = 0; t < Tm; ++t) {
        const std::size_t r = (std::size_t(w) * L + (k - 1)) * Tm + t,
                          kv = std::size_t(k - 1) * V + first + w;
        for (std::uint32_t b = 0; b < B; ++b) {
          y[r * kMaxBands + b] = c.ln_lost[(kv * T + t) * B + b] - ln_q;
          if (knots) laws[r * kMaxBands + b] = {c.area_k[kv * B + b], &knots[(kv * B + b) * Curves::kKnots]};
        }
      }
  for (std::uint32_t i = 0; i < kMovingS; ++i)
    for (std::uint32_t j = 0; j < kMovingE; ++j) {
      const float* curve = &curves_->moving[(i * kMovingE + j) * std::size_t(kCurveSamples)];
      for (std::size_t r = 0; r < R; ++r)
        nodes[r * N + i * kMovingE + j] =
            Curves::smallest_size(pre, config_, curve, &y[r * kMaxBands], c.ln_band.data(), B,
                                  moving_e_node(j), Curves::speed(i, pre.floor_velocity), true,
                                  &hints[r * kMaxBands], &leads[r], &laws[r * kMaxBands]);
    }
  if (!curves_->row_checks.empty())
    lower_speed_rows(nodes.data(), y.data(), laws.data(), c.ln_band.data(), B, static_cast<std::uint32_t>(R),
                     lowers.data());
  // Concave along eccentricity keeps the cell's rows' blend below; where the midpoint shows the
  // bilinear surface above the truth, the cell's corners come down by the excess.
  std::fill(hints.begin(), hints.end(), kCurveSamples / 2);  // now each row's brackets at the previous cell
  for (std::uint32_t i = 0; i + 1 < kMovingS; ++i)
    for (std::uint32_t j = 0; j + 1 < kMovingE; ++j) {
      const std::uint32_t corner[4] = {i * kMovingE + j, i * kMovingE + j + 1, (i + 1) * kMovingE + j,
                                       (i + 1) * kMovingE + j + 1};
      const float* centre =
          midpoints ? &curves_->centre[(i * (kMovingE - 1) + j) * std::size_t(kCurveSamples)] : nullptr;
      for (std::size_t r = 0; r < R; ++r) {
        const float* node = &nodes[r * N];
        float* lower = &lowers[r * N];
        if (node[corner[0]] <= kNever || node[corner[3]] >= -kNever) continue;
        if (!midpoints) {  // Reddy: known in advance
          const Curves::Lift v = curves_->speed_lift[i], e = curves_->moving_e_lift[j];
          const float lift[4] = {v.lower + e.lower, v.lower + e.upper, v.upper + e.lower, v.upper + e.upper};
          for (int n = 0; n < 4; ++n) lower[corner[n]] = std::max(lower[corner[n]], lift[n]);
          continue;
        }
        const float mean = 0.25f * (node[corner[0]] + node[corner[1]] + node[corner[2]] + node[corner[3]]);
        const float truth = Curves::smallest_size(
            pre, config_, centre, &y[r * kMaxBands], c.ln_band.data(), B, Curves::centre_e(j),
            Curves::centre_speed(i, pre.floor_velocity, pre.speed_offset), true, &hints[r * kMaxBands],
            &leads[r], &laws[r * kMaxBands]);
        const float excess = mean - truth;
        if (excess > 0)
          for (const std::uint32_t q : corner) lower[q] = std::max(lower[q], excess);
      }
    }
  std::vector<std::int16_t>& moving = sets->sets[set].moving;
  for (std::size_t r = 0; r < R; ++r) {  // r = (w L + k - 1) Tm + t; entries [w][t][i][k - 1] (row w)
    const std::size_t t = r % Tm, k = (r / Tm) % L, w = r / (std::size_t(Tm) * L);
    for (std::size_t n = 0; n < N; ++n)
      moving[((w * Tm + t) * N + n) * L + k] =
          encode_size(nodes[r * N + n] - lowers[r * N + n] - kBilinearMargin);
  }
}

// At a cell's weight w, the interpolation must come down by e [ln deg].
struct Scheduler::Impl::Need {
  float w, e;
  int check;  // the row check whose truth it compares with
};

// Lowers the moving table's nodes of T rows (build_moving()'s: a view, level and orientation each;
// row t: nodes[t N ..] less lowers[t N ..], as build_moving() stores them, for ln lost contrast
// ys[t kMaxBands ..] over q per band; N = kMovingS kMovingE) so that along speed, at each
// eccentricity node, the interpolation stays at or below the truth (the largest invisible size) at
// the row checks' speeds inside each cell. The truth there is first read from the samples alone (at
// most one sample step low); where that shows a need, refined on the model. Between two checks the
// truth is taken to bend no more than their grid shows, except where it rises more than twice the
// interpolation does (a band becoming invisible at any size, or nearly): there only monotonicity is
// assumed (thresholds never fall with speed), so the interpolation's larger end of that step must
// stay at or below the truth at its lower end. A cell's two nodes come down by the least total that
// does it (least_lowering()); a node shared by two cells may come down for either (which only lowers
// the other's).
void Scheduler::Impl::lower_speed_rows(const float* nodes, const float* ys, const AreaLaw* laws,
                                       const float* ln_band, std::uint32_t B, std::uint32_t T,
                                       float* lowers) const {
  const Precomputed& pre = *pre_;
  constexpr int M = Curves::kRowChecks;
  const std::size_t N = std::size_t(kMovingS) * kMovingE;
  // Each row's and check's brackets at the previous cell.
  std::vector<int> hints(std::size_t(T) * M * kMaxBands, kCurveSamples / 2);
  std::vector<std::uint32_t> leads(std::size_t(T) * M, 0);  // and their least bands there
  // Cells outside, rows inside: a cell's check curves stay in the cache for all of them.
  for (std::uint32_t i = 0; i + 1 < kMovingS; ++i)
    for (std::uint32_t j = 0; j < kMovingE; ++j)
      for (std::uint32_t t = 0; t < T; ++t) {
        const float* node = &nodes[t * N];
        const float* y = &ys[t * kMaxBands];
        const AreaLaw* law = &laws[t * kMaxBands];
        float* lower = &lowers[t * N];
        int* hint = &hints[std::size_t(t) * M * kMaxBands];
        std::uint32_t* lead = &leads[std::size_t(t) * M];
        const std::uint32_t at0 = i * kMovingE + j, at1 = (i + 1) * kMovingE + j;
        if (node[at0] <= kNever || node[at1] >= -kNever) continue;  // no size passes, or every size does
        const float a0 = node[at0] - lower[at0], a1 = node[at1] - lower[at1], rise = (a1 - a0) / M;
        float truth[M + 1];
        truth[0] = node[at0];
        truth[M] = node[at1];
        for (int m = 1; m < M; ++m)
          truth[m] = Curves::least_sampled(&curves_->row_checks[Curves::row_check_at(i, j, m)], y, ln_band, B,
                                           &hint[m * kMaxBands], &lead[m], law);
        Need needs[3 * M];  // what the row needs (only where it must come down)
        int count = 0;
        const auto gather = [&] {
          count = 0;
          const auto add = [&](int at, int check) {
            const float e = a0 + rise * float(at) - truth[check];
            if (e > 0.0f) needs[count++] = {float(at) / M, e, check};
          };
          for (int m = 0; m < M; ++m) {
            add(m + 1, m + 1);
            if (truth[m + 1] - truth[m] > 2.0f * std::max(rise, 0.0f) + kRowJump) {
              add(m, m);
              add(m + 1, m);
            }
          }
          return count;
        };
        if (gather() == 0) continue;
        bool refined[M + 1] = {};
        for (int n = 0; n < count; ++n) {
          const int m = needs[n].check;
          if (m == 0 || m == M || refined[m]) continue;
          refined[m] = true;
          int refine_hint[kMaxBands];
          std::copy(&hint[m * kMaxBands], &hint[(m + 1) * kMaxBands], refine_hint);
          std::uint32_t refine_lead = lead[m];
          truth[m] = Curves::smallest_size(
              pre, config_, &curves_->row_checks[Curves::row_check_at(i, j, m)], y, ln_band, B,
              moving_e_node(j), Curves::speed_at(i, float(m) / M, pre.floor_velocity, pre.speed_offset), true,
              refine_hint, &refine_lead, law);
        }
        if (gather() == 0) continue;
        const Lowering d = least_lowering(needs, count);
        lower[at0] += d.lower;
        lower[at1] += d.upper;
      }
}

// The least lowering of a cell's two nodes (lower + upper least, both >= 0) under which the
// interpolation at each weight needs[n].w comes down by at least needs[n].e > 0: (1 - w) lower + w
// upper >= e. The optimum lies where one node alone, or two of the needs, decide; the largest e on
// both nodes is always enough.
Scheduler::Impl::Lowering Scheduler::Impl::least_lowering(const Need* needs, int count) {
  float most = 0.0f, only_upper = 0.0f, only_lower = 0.0f;
  for (int n = 0; n < count; ++n) {
    most = std::max(most, needs[n].e);
    only_upper = needs[n].w > 0.0f ? std::max(only_upper, needs[n].e / needs[n].w) : kInf;
    only_lower = needs[n].w < 1.0f ? std::max(only_lower, needs[n].e / (1.0f - needs[n].w)) : kInf;
  }
  Lowering best{most, most};
  const auto consider = [&](float a, float b) {
    if (!(a >= 0.0f && b >= 0.0f && a + b < best.lower + best.upper)) return;
    for (int n = 0; n < count; ++n)
      if ((1.0f - needs[n].w) * a + needs[n].w * b < needs[n].e) return;
    best = {a, b};
  };
  consider(0.0f, only_upper);
  consider(only_lower, 0.0f);
  for (int p = 0; p < count; ++p)
    for (int q = p + 1; q < count; ++q) {
      const Need& u = needs[p];
      const Need& v = needs[q];
      const float det = v.w - u.w;  // (1 - u.w) v.w - (1 - v.w) u.w
      if (det == 0.0f) continue;
      const float a = (u.e * v.w - v.e * u.w) / det, b = ((1.0f - u.w) * v.e - (1.0f - v.w) * u.e) / det;
      consider(a + 1e-6f, b + 1e-6f);  // a hair more: rounding must not leave the pair uncovered
    }
  return best;
}

// The bounds over every view of table set `set` (its still and slow tables built).
void Scheduler::Impl::build_any_view(const ProfileCache& c, ProfileTableSets* sets, std::uint32_t set) const {
  const Profile& p = c.profile;
  const std::uint32_t V = p.meta.view_count, B = p.meta.band_count, L = p.meta.level_count - 1;
  const std::vector<std::int16_t>& still = sets->sets[set].still;
  std::vector<std::int16_t>& any = sets->sets[set].any_view;
  const std::size_t width = 2 * std::size_t(L) + 1;
  any.assign(L > 0 ? std::size_t(B) * kStillE * width : 0, 0);
  for (std::uint32_t n = 0; n < B && L > 0; ++n)
    for (std::uint32_t j = 0; j < kStillE; ++j) {
      std::int16_t* row = &any[(std::size_t(n) * kStillE + j) * width];
      std::fill(row, row + L, std::numeric_limits<std::int16_t>::max());
      std::fill(row + L, row + 2 * L, std::numeric_limits<std::int16_t>::min());
      row[2 * L] = std::numeric_limits<std::int16_t>::max();
      for (std::uint32_t w = 0; w < V; ++w)
        for (std::uint32_t k = 0; k < L; ++k) {
          const std::size_t at = ((std::size_t(w) * B + n) * kStillE + j) * L + k;
          row[k] = std::min(row[k], still[at]);
          row[L + k] = std::max(row[L + k], still[at]);
          if (k + 1 == L) row[2 * L] = std::min({row[2 * L], still[at], sets->sets[set].slow[at]});
        }
    }
}

std::size_t Scheduler::Impl::table_bytes(const Profile& p, const SchedulerConfig& config, int view) {
  const ProfileMeta& m = p.meta;
  if (!tabulated(config) || m.level_count < 2 || view < kAllViews || view >= static_cast<int>(m.view_count))
    return 0;
  const std::size_t views = view == kAllViews ? m.view_count : 1;
  const std::size_t per_set = views * (m.level_count - 1) *
                              (2 * std::size_t(m.band_count) * kStillE +
                               std::size_t(moving_orientations(p, config)) * kMovingS * kMovingE);
  const std::size_t any_view =
      view == kAllViews ? std::size_t(m.band_count) * kStillE * (2 * (m.level_count - 1) + 1) : 0;
  float biases[1 + kMaxTabulatedBiases];
  return (per_set + any_view) * std::size_t(margin_sets(config)) * table_biases(config, biases) *
         sizeof(std::int16_t);
}

std::size_t Scheduler::Impl::table_bytes(int profile) const {
  if (profile < 0 || profile >= static_cast<int>(profile_count_)) return 0;
  return profiles_[profile].tables.bytes();
}

bool Scheduler::Impl::make_tables(int profile, int view, ProfileTableSets* out) const {
  if (!curves_ || profile < 0 || profile >= static_cast<int>(profile_count_)) return false;
  const ProfileCache& c = profiles_[profile];
  const auto V = static_cast<int>(c.profile.meta.view_count);
  if (view >= V || view < kAllViews) return false;
  if (view == kAllViews)
    build_tables(c, out, 0, static_cast<std::uint32_t>(V));
  else
    build_tables(c, out, static_cast<std::uint32_t>(view), 1);
  return true;
}

void Scheduler::Impl::note_want(ObjectId id) {
  if (want_[id] == 0) return;
  std::uint8_t& wanted = profiles_[profile_of_[id]].wanted[want_[id] - 1u];
  wanted = std::max(wanted, ProfileCache::kWanted);
  want_[id] = 0;
}

std::uint32_t Scheduler::Impl::wanted_tables(std::span<TablesWanted> out) {
  for (ObjectId id = 0; id < config_.max_objects; ++id)
    if (profile_of_[id] >= 0) note_want(id);
  std::uint32_t n = 0;
  for (std::uint32_t p = 0; p < profile_count_; ++p) {
    ProfileCache& c = profiles_[p];
    for (std::uint32_t v = 0; v < c.wanted.size() && n < out.size(); ++v)
      if (c.wanted[v] == ProfileCache::kWanted && c.slot[v] == ProfileCache::kNoRow) {
        c.wanted[v] = ProfileCache::kListed;
        out[n++] = {static_cast<std::int32_t>(p), v};
      }
  }
  return n;
}

std::size_t Scheduler::Impl::drop_idle_tables(std::uint32_t frames) {
  bool held = false;  // any view's tables (else nothing to drop, nor to look for)
  for (std::uint32_t p = 0; p < profile_count_; ++p) held = held || !profiles_[p].tables.views.empty();
  if (!held) return 0;
  // A view that an object's remembered decision stands on counts as read now: in a still scene the
  // memos and rests decide without reading a table, and would want their views again as they end.
  const bool max3 = config_.view_blend == ViewBlend::Max3;
  for (std::uint32_t e = 0; memos_ && frames > 0 && e < 2; ++e) {
    const Memo& m = memos_[e];
    for (ObjectId id = 0; id < config_.max_objects; ++id)
      if (profile_of_[id] >= 0 && m.key[id] != Memo::kNone && (m.key[id] & Memo::kThroughView))
        profiles_[profile_of_[id]].note_read(m.view_key[id] >> 8, max3, frame_);  // where << 8
  }
  std::size_t freed = 0;
  for (std::uint32_t p = 0; p < profile_count_; ++p) {
    ProfileCache& c = profiles_[p];
    ProfileTableSets& t = c.tables;
    const std::size_t rows = t.views.size(), before = t.bytes();
    std::size_t kept = 0;  // rows kept so far, moved down in place over those dropped
    for (std::size_t r = 0; r < rows; ++r) {
      const std::uint16_t v = t.views[r];
      if (frame_ - c.read_frame[v].load(std::memory_order_relaxed) >= frames) {
        c.slot[v] = ProfileCache::kNoRow;
        c.wanted[v] = 0;  // may be wanted and listed again
        continue;
      }
      if (kept != r)
        for (ProfileTableSets::Tables& set : t.sets)
          for (std::vector<std::int16_t>* table : {&set.still, &set.slow, &set.moving}) {
            const std::size_t row = table->size() / rows;  // a view's entries are contiguous
            std::copy_n(table->begin() + std::ptrdiff_t(r * row), row,
                        table->begin() + std::ptrdiff_t(kept * row));
          }
      t.views[kept] = v;
      c.slot[v] = static_cast<std::uint16_t>(kept++);
    }
    if (kept == rows) continue;
    for (ProfileTableSets::Tables& set : t.sets)
      for (std::vector<std::int16_t>* table : {&set.still, &set.slow, &set.moving}) {
        table->resize(table->size() / rows * kept);
        table->shrink_to_fit();
      }
    t.views.resize(kept);
    t.views.shrink_to_fit();
    freed += before - t.bytes();
  }
  return freed;
}

bool Scheduler::Impl::install_tables(int profile, ProfileTableSets* sets) {
  if (!curves_ || profile < 0 || profile >= static_cast<int>(profile_count_) || sets->views.empty())
    return false;
  ProfileCache& c = profiles_[profile];
  for (const std::uint16_t v : sets->views)
    if (v >= c.slot.size() || c.slot[v] != ProfileCache::kNoRow) return false;
  take_tables(c, sets);
  return true;
}

// Moves in tables of views the profile has none of, after those it has (a view's rows in each table
// are contiguous: its layout's outermost index); with the last view, the bounds over every view.
void Scheduler::Impl::take_tables(ProfileCache& c, ProfileTableSets* sets) const {
  const std::size_t had = c.tables.views.size(), added = sets->views.size();
  if (had == 0) {
    // Bounds over every view that a drop left stay (sets has its own only when made with every view).
    for (std::uint32_t set = 0; set < kTableSets; ++set)
      if (sets->sets[set].any_view.empty()) sets->sets[set].any_view = std::move(c.tables.sets[set].any_view);
    c.tables = std::move(*sets);
  } else {
    const auto append = [&](std::vector<std::int16_t>& to, const std::vector<std::int16_t>& from) {
      to.reserve(to.size() + from.size());  // exactly: table_bytes() counts sizes
      to.insert(to.end(), from.begin(), from.end());
    };
    for (std::uint32_t set = 0; set < kTableSets; ++set) {
      append(c.tables.sets[set].still, sets->sets[set].still);
      append(c.tables.sets[set].slow, sets->sets[set].slow);
      append(c.tables.sets[set].moving, sets->sets[set].moving);
    }
    c.tables.views.insert(c.tables.views.end(), sets->views.begin(), sets->views.end());
  }
  for (std::size_t r = had; r < had + added; ++r) {
    c.slot[c.tables.views[r]] = static_cast<std::uint16_t>(r);
    c.note_read_view(c.tables.views[r], frame_);  // installed: read from now on (not idle yet)
  }
  if (c.every_view() && c.tables.sets[0].any_view.empty() && c.profile.meta.level_count > 1)
    for (std::uint32_t set = 0; set < 2 * table_bias_count_; ++set)
      if (set % 2 < static_cast<std::uint32_t>(margin_sets(config_))) build_any_view(c, &c.tables, set);
}

}  // namespace acuity
