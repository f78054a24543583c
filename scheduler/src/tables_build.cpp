// Building the tabulated path's tables of one profile (add_profile) and their size.
#include "curves.hpp"

namespace acuity {

// The threshold curves the tables are read from, on the table grid (Curves): at creation, once for
// every profile.
void Scheduler::Impl::build_curves() {
  const Precomputed& pre = *pre_;
  curves_ = std::make_unique<Curves>();
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
    curves_->centre.resize(std::size_t(kMovingS - 1) * (kMovingE - 1) * kCurveSamples);
    for (std::uint32_t i = 0; i + 1 < kMovingS; ++i)
      for (std::uint32_t j = 0; j + 1 < kMovingE; ++j)
        Curves::sample(pre, config_, Curves::centre_e(j),
                       Curves::centre_speed(i, pre.floor_velocity, pre.speed_offset), true,
                       &curves_->centre[(i * (kMovingE - 1) + j) * std::size_t(kCurveSamples)]);
  }
}

// Fills the tabulated path's tables of one profile (see ProfileCache).
void Scheduler::Impl::build_tables(ProfileCache& c) const {
  const Profile& p = c.profile;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count, L = K - 1;
  const Precomputed& pre = *pre_;
  const auto margins = static_cast<std::uint32_t>(margin_sets(config_));
  for (std::uint32_t set = 0; set < 2 * table_bias_count_; ++set) {
    if (set % 2 >= margins) continue;
    const float ln_bias_q = pre.ln_quality_at(table_bias_[set / 2]);
    const float ln_q = set % 2 ? ln_bias_q + pre.ln_margin : ln_bias_q;
    c.sets[set].still.assign(std::size_t(V) * L * B * kStillE, 0);
    c.sets[set].slow.assign(std::size_t(V) * L * B * kStillE, 0);
    c.sets[set].moving.assign(std::size_t(V) * L * T * kMovingS * kMovingE, 0);
    for (std::uint32_t w = 0; w < V; ++w)
      for (std::uint32_t k = 1; k < K; ++k) {
        build_still(c, set, ln_q, w, k);
        build_moving(c, set, ln_q, w, k);
      }
    build_any_view(c, set);
  }
}

// The still and slow tables of view w and level k in table set `set` (ln_q: its ln q).
void Scheduler::Impl::build_still(ProfileCache& c, std::uint32_t set, float ln_q, std::uint32_t w,
                                  std::uint32_t k) const {
  const Profile& p = c.profile;
  const std::uint32_t V = p.meta.view_count, B = p.meta.band_count, L = p.meta.level_count - 1;
  const Precomputed& pre = *pre_;
  const bool midpoints = curves_->still_lift.empty();  // each cell checked at its midpoint (not Reddy)
  const std::size_t kv = std::size_t(k - 1) * V + w;
  std::vector<std::int16_t>& still = c.sets[set].still;
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
        prefix = std::min(prefix, Curves::largest_size(pre, config_, curve, y, c.ln_band[b], still_e_node(j),
                                                       pre.floor_velocity, slow, &hint[b]));
        node[j][b] = prefix;
        if (j + 1 < kStillE && midpoints) {
          const float* centre =
              &(slow ? curves_->slow_centre : curves_->still_centre)[j * std::size_t(kCurveSamples)];
          mid_prefix = std::min(mid_prefix, Curves::largest_size(pre, config_, centre, y, c.ln_band[b],
                                                                 Curves::still_centre_e(j),
                                                                 pre.floor_velocity, slow, &mid_hint[b]));
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
    std::vector<std::int16_t>& table = slow ? c.sets[set].slow : still;
    for (std::uint32_t j = 0; j < kStillE; ++j)
      for (std::uint32_t b = 0; b < B; ++b)
        table[((std::size_t(w) * B + b) * kStillE + j) * L + (k - 1)] = encode_size(node[j][b] - lower[j][b]);
  }
}

// The moving tables of view w and level k in table set `set` (ln_q: its ln q).
void Scheduler::Impl::build_moving(ProfileCache& c, std::uint32_t set, float ln_q, std::uint32_t w,
                                   std::uint32_t k) const {
  const Profile& p = c.profile;
  const std::uint32_t V = p.meta.view_count, T = p.meta.orientation_count, B = p.meta.band_count,
                      L = p.meta.level_count - 1;
  const Precomputed& pre = *pre_;
  const bool midpoints = curves_->still_lift.empty();  // each cell checked at its midpoint (not Reddy)
  const std::size_t kv = std::size_t(k - 1) * V + w;
  std::vector<std::int16_t>& moving = c.sets[set].moving;
  // Moving: per orientation, every band.
  for (std::uint32_t t = 0; t < T; ++t) {
    float y[kMaxBands];
    for (std::uint32_t b = 0; b < B; ++b) y[b] = c.ln_lost[(kv * T + t) * B + b] - ln_q;
    int hint[kMaxBands], centre_hint[kMaxBands];  // each band's bracket at the previous node
    std::fill(hint, hint + kMaxBands, kCurveSamples / 2);
    std::fill(centre_hint, centre_hint + kMaxBands, kCurveSamples / 2);
    auto largest = [&](const float* curve, float e, float v, int* h) {
      return Curves::smallest_size(pre, config_, curve, y, c.ln_band.data(), B, e, v, true, h);
    };
    float node[kMovingS * kMovingE];
    for (std::uint32_t i = 0; i < kMovingS; ++i)
      for (std::uint32_t j = 0; j < kMovingE; ++j)
        node[i * kMovingE + j] = largest(&curves_->moving[(i * kMovingE + j) * std::size_t(kCurveSamples)],
                                         moving_e_node(j), Curves::speed(i, pre.floor_velocity), hint);
    // Concave along each axis keeps the cell's edges below; where the midpoint shows the
    // bilinear surface above the truth, the cell's corners come down by the excess.
    float lower[kMovingS * kMovingE] = {};
    for (std::uint32_t i = 0; i + 1 < kMovingS; ++i)
      for (std::uint32_t j = 0; j + 1 < kMovingE; ++j) {
        float* corner[4] = {&node[i * kMovingE + j], &node[i * kMovingE + j + 1],
                            &node[(i + 1) * kMovingE + j], &node[(i + 1) * kMovingE + j + 1]};
        if (*corner[0] <= kNever || *corner[3] >= -kNever) continue;
        if (!midpoints) {  // Reddy: known in advance
          const Curves::Lift v = curves_->speed_lift[i], e = curves_->moving_e_lift[j];
          const float lift[4] = {v.lower + e.lower, v.lower + e.upper, v.upper + e.lower, v.upper + e.upper};
          for (int n = 0; n < 4; ++n) lower[corner[n] - node] = std::max(lower[corner[n] - node], lift[n]);
          continue;
        }
        const float mean = 0.25f * (*corner[0] + *corner[1] + *corner[2] + *corner[3]);
        const float truth = largest(
            &curves_->centre[(i * (kMovingE - 1) + j) * std::size_t(kCurveSamples)], Curves::centre_e(j),
            Curves::centre_speed(i, pre.floor_velocity, pre.speed_offset), centre_hint);
        const float excess = mean - truth;
        if (excess > 0)
          for (float* q : corner) lower[q - node] = std::max(lower[q - node], excess);
      }
    for (std::uint32_t i = 0; i < kMovingS * kMovingE; ++i)
      moving[((std::size_t(w) * T + t) * kMovingS * kMovingE + i) * L + (k - 1)] =
          encode_size(node[i] - lower[i] - kBilinearMargin);
  }
}

// The bounds over every view of table set `set` (its still and slow tables built).
void Scheduler::Impl::build_any_view(ProfileCache& c, std::uint32_t set) const {
  const Profile& p = c.profile;
  const std::uint32_t V = p.meta.view_count, B = p.meta.band_count, L = p.meta.level_count - 1;
  const std::vector<std::int16_t>& still = c.sets[set].still;
  std::vector<std::int16_t>& any = c.sets[set].any_view;
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
          if (k + 1 == L) row[2 * L] = std::min({row[2 * L], still[at], c.sets[set].slow[at]});
        }
    }
}

std::size_t Scheduler::Impl::table_bytes(const ProfileMeta& m, const SchedulerConfig& config) {
  if (!tabulated(config) || m.level_count < 2) return 0;
  const std::size_t per_set =
      std::size_t(m.view_count) * (m.level_count - 1) *
      (2 * std::size_t(m.band_count) * kStillE + std::size_t(m.orientation_count) * kMovingS * kMovingE);
  const std::size_t any_view = std::size_t(m.band_count) * kStillE * (2 * (m.level_count - 1) + 1);
  float biases[1 + kMaxTabulatedBiases];
  return (per_set + any_view) * std::size_t(margin_sets(config)) * table_biases(config, biases) *
         sizeof(std::int16_t);
}

std::size_t Scheduler::Impl::table_bytes(int profile) const {
  if (profile < 0 || profile >= static_cast<int>(profile_count_)) return 0;
  const ProfileCache& c = profiles_[profile];
  std::size_t n = 0;
  for (std::uint32_t set = 0; set < kTableSets; ++set)
    n += c.sets[set].still.size() + c.sets[set].slow.size() + c.sets[set].moving.size() +
         c.sets[set].any_view.size();
  return n * sizeof(std::int16_t);
}

}  // namespace acuity
