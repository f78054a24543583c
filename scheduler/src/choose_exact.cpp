// The perceptual rules (Perceptual, Reddy) evaluated exactly: every band and orientation through
// the threshold model (Evaluation::Exact, explain(), and objects the tables do not cover).
#include "curves.hpp"

namespace acuity {

// One eye's view of one object (sight() and aim() done) through the configured rule, exactly.
// scores_out (K floats) and ex are optional.
Scheduler::Impl::Choice Scheduler::Impl::evaluate(ObjectId id, Look look, const Sight& s, float* scores_out,
                                                  ObjectExplain* ex) const {
  const Profile& p = profiles_[profile_of_[id]].profile;
  const std::uint32_t K = p.meta.level_count;
  if (scores_out) std::fill(scores_out, scores_out + K, 0.0f);
  switch (look) {
    case Look::Invalid: {
      const auto fallback = static_cast<std::uint8_t>(std::min<std::uint32_t>(config_.fallback_level, K - 1));
      return {fallback, fallback, kFlagInvalidInput};
    }
    case Look::Inside:
      return {0, 0, kFlagEyeInside};
    case Look::Ok:
      break;
  }
  switch (config_.rule) {
    case SelectionRule::Distance:
    case SelectionRule::ScreenSize:
      return choose_by_error(id, s);
    case SelectionRule::Reddy:
      return choose_exact(id, s, scores_out, ex);
    case SelectionRule::Perceptual:
      return choose_exact(id, s, scores_out, ex);
  }
  return {0, 0, 0};
}

// ln CT per (orientation, band) of one object seen as s (ln_ct: [rows][B]; Reddy: each row's visible
// limit [cpod]). A static object's velocity is the drift floor in every orientation, so one row serves
// all of them, whatever the model. Returns the number of rows: T, or 1.
std::uint32_t Scheduler::Impl::exact_thresholds(const ProfileCache& pc, const Sight& s, float* ln_ct) const {
  const Profile& p = pc.profile;
  const std::uint32_t T = p.meta.orientation_count, B = p.meta.band_count;
  const float nyquist_cpd = s.nyquist_cpd, diameter_deg = s.diameter_deg, e = s.e;
  const bool moving = s.moving;
  const float vx = s.vx, vy = s.vy;
  const Precomputed& pre = *pre_;
  const float inv_diam = 1.0f / diameter_deg, ln_diam = s.ln_diam;
  const float a = pre.ecc_slope * e;  // ln CT grows by a per cpd with eccentricity
  float v_t[kMaxOrientations];
  const std::uint32_t rows = moving ? T : 1;
  for (std::uint32_t t = 0; t < rows; ++t) {
    v_t[t] = moving ? std::max(std::abs(vx * pc.cos_t[t] + vy * pc.sin_t[t]), pre.floor_velocity)
                    : pre.floor_velocity;
    float* row = ln_ct + t * B;
    if (config_.rule == SelectionRule::Reddy) {  // the visible limit per orientation, in cpod
      row[0] = std::min(reddy_cutoff(v_t[t], e), nyquist_cpd) * diameter_deg;
      continue;
    }
    band_thresholds(p.bands, pc.ln_band.data(), B, inv_diam, ln_diam, nyquist_cpd, e, a, v_t[t], moving, row);
  }
  return rows;
}

bool Scheduler::Impl::uses_detail(const Profile& p) const {
  return p.detail && config_.rule == SelectionRule::Perceptual && config_.model == ThresholdModel::StelaCsf &&
         !area_law(p);
}

// StelaCsf on a profile with a Detail section: ln CT per (orientation, band) [T][B] of level k's loss
// seen from `view`, at the loss's own frequency (the band's centre shifted by its offset) and its
// own area (the smaller of the measured extent, times the squared angular diameter, and
// ModelParams::area). What a channel misses of a grating off its centre, its neighbour reads:
// pooled_excess() adds them. The Nyquist cut stays the band centre's, as without Detail. An entry at
// its band's centre (frequency code 0, every entry of a cell-bounded profile) reuses
// exact_thresholds()' ln CT there (`centre_ln_ct`, rows of `stride`).
void Scheduler::Impl::detail_thresholds(const ProfileCache& pc, const Sight& s, std::uint32_t k,
                                        std::uint32_t view, const float* centre_ln_ct, std::uint32_t stride,
                                        float* ln_ct) const {
  const Profile& p = pc.profile;
  const std::uint32_t V = p.meta.view_count, T = p.meta.orientation_count, B = p.meta.band_count;
  const ProfileDetail* detail = &p.detail[((k - 1) * std::size_t(V) + view) * T * B];
  const float inv_diam = 1.0f / s.diameter_deg, diam2 = s.diameter_deg * s.diameter_deg;
  const auto config_area = static_cast<float>(config_.params.area);
  const StelaConstants& c = config_.params.stela;
  const float floor_v = pre_->floor_velocity;
  for (std::uint32_t t = 0; t < T; ++t) {
    const float v = s.moving ? std::max(std::abs(s.vx * pc.cos_t[t] + s.vy * pc.sin_t[t]), floor_v) : floor_v;
    for (std::uint32_t b = 0; b < B; ++b) {
      const ProfileDetail d = detail[t * B + b];
      const float centre = p.bands[b] * inv_diam, offset = detail_frequency_octaves(d);
      const float base = centre_ln_ct[t * stride + b];
      if (base >= kInf) {  // above the display's Nyquist frequency
        ln_ct[t * B + b] = kInf;
        continue;
      }
      const float f = d.frequency_code ? centre * std::exp2(offset) : centre;
      const float area = detail_area(d) * diam2;
      const float penalty =
          area < config_area ? stela_log_area_penalty(f, area, c) - stela_log_area_penalty(f, config_area, c)
                             : 0.0f;
      const float at_f = d.frequency_code ? log_threshold(f, s.e, v, config_.model, config_.params) : base;
      ln_ct[t * B + b] = at_f + penalty;
    }
  }
}

// The area law (SchedulerConfig::area_law) on exact_thresholds()' rows (`rows` of them, `stride`
// apart): ln CT per (orientation, band) [rows][B] of level k's loss seen from `view`, each band
// raised by Curves::area_term() of its k at `weight` (area_weights()), the tables' arithmetic.
void Scheduler::Impl::area_thresholds(const ProfileCache& pc, std::uint32_t k, std::uint32_t view,
                                      const float* weight, const float* ln_ct, std::uint32_t rows,
                                      std::uint32_t stride, float* out) const {
  const std::uint32_t V = pc.profile.meta.view_count, B = pc.profile.meta.band_count;
  const float* ks = &pc.area_k[((k - 1) * std::size_t(V) + view) * B];
  float lift[kMaxBands];
  for (std::uint32_t b = 0; b < B; ++b) lift[b] = Curves::area_term(ks[b], weight[b]);
  for (std::uint32_t t = 0; t < rows; ++t)
    for (std::uint32_t b = 0; b < B; ++b) out[t * B + b] = ln_ct[t * stride + b] + lift[b];
}

// ln CT of B bands (centres bands[b] [cpod], ln_band their ln) of an object of angular diameter
// 1 / inv_diam [deg] (ln_diam its ln) at eccentricity e [deg] (a = the model's ln CT slope x e) and
// one retinal speed v [deg/s] (floored), still or moving; bands above nyquist_cpd are invisible
// (+inf). The one evaluation the exact path and the cluster cut share.
void Scheduler::Impl::band_thresholds(const float* bands, const float* ln_band, std::uint32_t B,
                                      float inv_diam, float ln_diam, float nyquist_cpd, float e, float a,
                                      float v, bool moving, float* row) const {
  const Precomputed& pre = *pre_;
  if (config_.model == ThresholdModel::Default) {
    const VelocityTerms own = moving ? pre.terms_at(v) : pre.static_terms;
    for (std::uint32_t b = 0; b < B; ++b) {
      const float f = bands[b] * inv_diam;
      const float ln_f = ln_band[b] - ln_diam;
      row[b] = f > nyquist_cpd ? kInf : pre.default_ln_ct(pre.band_terms(own, v, ln_f, moving), ln_f, f, a);
    }
  } else {
    for (std::uint32_t b = 0; b < B; ++b) {
      const float f = bands[b] * inv_diam;
      row[b] = f > nyquist_cpd ? kInf : log_threshold(f, e, v, config_.model, config_.params);
    }
  }
}

// explain()'s pass over the same arithmetic: level k's score (ln_excess = ln(score)) and the component
// that limits it, found again from choose_exact()'s thresholds (ln_ct, rows of `stride`).
void Scheduler::Impl::explain_level(const ProfileCache& pc, std::uint32_t view, std::uint32_t k,
                                    const float* ln_ct, std::uint32_t stride, float inv_diam, float ln_excess,
                                    LevelExplain* out) const {
  const Profile& p = pc.profile;
  const std::uint32_t V = p.meta.view_count, T = p.meta.orientation_count, B = p.meta.band_count;
  const std::size_t TB = std::size_t(T) * B;
  LevelExplain& le = *out;
  le.score = std::exp(ln_excess);
  std::uint32_t arg = 0;  // the limiting component, found again (explain is not the hot path)
  if (config_.rule == SelectionRule::Reddy) {
    float best_ratio = -kInf;
    for (std::uint32_t j = 0; j < k; ++j)
      for (std::uint32_t t = 0; t < T; ++t) {
        const float F = p.feature_frequency(j, view, t);
        if (F > 0 && ln_ct[t * stride] / F > best_ratio) {
          best_ratio = ln_ct[t * stride] / F;
          arg = t * B;
        }
      }
  } else {
    const float* lost = &pc.ln_lost[((k - 1) * std::size_t(V) + view) * TB];
    float best_x = -kInf;
    for (std::uint32_t i = 0; i < T * B; ++i) {
      const float x = lost[i] - ln_ct[(i / B) * stride + i % B];
      if (x > best_x) {
        best_x = x;
        arg = i;
      }
    }
  }
  le.orientation = static_cast<std::uint8_t>(arg / B);
  le.band = static_cast<std::uint8_t>(arg % B);
  le.frequency_cpd = p.bands[le.band] * inv_diam;
  le.threshold = config_.rule == SelectionRule::Reddy
                     ? 0.0f
                     : std::exp(std::min(ln_ct[(arg / B) * stride + arg % B], kLnCeiling));
}

// The perceptual rule evaluated in full (and Reddy's rule):
//   per band b: f = f_b / D [cpd]; ln CT(t, b) from the threshold model (bands above the display's
//   Nyquist frequency are invisible); level k's score = max_tb lost_k / (q CT) (stela-csf with a
//   Detail section: the channels pooled, pooled_excess()).
Scheduler::Impl::Choice Scheduler::Impl::choose_exact(ObjectId id, const Sight& s, float* scores_out,
                                                      ObjectExplain* ex) const {
  const ProfileCache& pc = profiles_[profile_of_[id]];
  const Profile& p = pc.profile;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count;
  Choice out{0, 0, s.flags};
  const float diameter_deg = s.diameter_deg, e = s.e;
  const std::uint32_t view = s.view;
  const std::uint16_t* cand = s.cand;
  const Precomputed& pre = *pre_;
  const float inv_diam = 1.0f / diameter_deg;
  const float ln_q = pre.ln_quality_at(bias_[id]);
  const float ln_q_coarse = ln_q + pre.ln_margin;
  const bool all_levels = scores_out || ex;

  // ln CT per (orientation, band). A static object's velocity is the drift floor in every
  // orientation, so one row serves all of them (rows = 1).
  float ln_ct[kMaxOrientations * kMaxBands];
  const std::uint32_t rows = exact_thresholds(pc, s, ln_ct);
  const std::uint32_t stride = rows == 1 ? 0 : B;  // a static object's one row serves every orientation
  const bool detail = uses_detail(p);              // StelaCsf with Detail: per level (detail_thresholds)
  const bool area = area_law(p);                   // the other models' area law: per level (area_thresholds)
  float weight[kMaxBands];                         // its w(ln f) per band (Curves::area_w), this object's
  if (area)
    for (std::uint32_t b = 0; b < B; ++b)
      weight[b] = Curves::area_w(pc.ln_band[b] - s.ln_diam, static_cast<float>(config_.params.stela.f0));
  float ln_ct_detail[kMaxOrientations * kMaxBands];

  // ln(score_k q) = max over (t, b) of ln lost - ln CT. Levels are scanned from the coarsest; without
  // scores or explain, the scan stops at the first level that passes even the hysteresis margin.
  // Reddy: a finer level's smallest feature F is visible when it lies at or below the limit, so
  // level k's score is the largest limit / F over the levels j < k and every orientation.
  float reddy_prefix[kMaxLevels] = {};
  if (config_.rule == SelectionRule::Reddy)
    for (std::uint32_t j = 0; j + 1 < K; ++j) {
      float worst = reddy_prefix[j];
      for (std::uint32_t t = 0; t < T; ++t) {
        const float F = p.feature_frequency(j, view, t);
        if (F > 0) worst = std::max(worst, ln_ct[t * stride] / F);
      }
      reddy_prefix[j + 1] = worst;
    }
  bool fine_found = false;
  for (std::uint32_t k = K - 1; k >= 1; --k) {
    float m = -kInf;
    if (config_.rule == SelectionRule::Reddy) {
      m = reddy_prefix[k] > 0 ? std::log(reddy_prefix[k]) : -kInf;
    } else {
      // A static object's thresholds do not depend on orientation: its per-band maxima suffice.
      const std::vector<float>& lost = stride ? pc.ln_lost : pc.ln_lost_any;
      const std::uint32_t t_count = stride ? T : 1;
      const std::size_t per_view = std::size_t(t_count) * B;
      const std::uint32_t blended = config_.view_blend == ViewBlend::Max3 ? kLookupCandidates : 1;
      for (std::uint32_t j = 0; j < blended; ++j) {
        const std::uint32_t w = blended == 1 ? view : cand[j];
        if (detail) {  // thresholds per level, view and orientation; the channels pooled
          detail_thresholds(pc, s, k, w, ln_ct, stride, ln_ct_detail);
          m = std::max(
              m, pooled_excess(&pc.ln_lost[((k - 1) * std::size_t(V) + w) * T * B], ln_ct_detail, T, B));
          continue;
        }
        if (area) {  // thresholds per level and view
          area_thresholds(pc, k, w, weight, ln_ct, t_count, stride, ln_ct_detail);
          m = std::max(
              m, max_excess(&lost[((k - 1) * std::size_t(V) + w) * per_view], ln_ct_detail, t_count, B, B));
          continue;
        }
        m = std::max(m,
                     max_excess(&lost[((k - 1) * std::size_t(V) + w) * per_view], ln_ct, t_count, B, stride));
      }
    }
    if (!fine_found && m <= ln_q) {
      out.fine = static_cast<std::uint8_t>(k);
      fine_found = true;
    }
    if (out.coarse == 0 && m <= ln_q_coarse) out.coarse = static_cast<std::uint8_t>(k);
    if (scores_out) scores_out[k] = std::exp(m - ln_q);
    if (ex && detail) {
      detail_thresholds(pc, s, k, view, ln_ct, stride, ln_ct_detail);
      explain_level(pc, view, k, ln_ct_detail, B, inv_diam, m - ln_q, &ex->levels[k]);
    } else if (ex && area) {
      area_thresholds(pc, k, view, weight, ln_ct, stride ? T : 1, stride, ln_ct_detail);
      explain_level(pc, view, k, ln_ct_detail, stride ? B : 0, inv_diam, m - ln_q, &ex->levels[k]);
    } else if (ex) {
      explain_level(pc, view, k, ln_ct, stride, inv_diam, m - ln_q, &ex->levels[k]);
    }
    if (out.coarse != 0 && !all_levels) break;
  }
  if (ex) {
    ex->distance_m = s.d;
    ex->angular_diameter_deg = diameter_deg;
    ex->eccentricity_deg = e;
    ex->image_velocity_deg_s = length(s.image);
    ex->retinal_velocity_deg_s = length(s.slip);
    ex->view = view;
    ex->level_count = static_cast<std::uint8_t>(K);
    ex->levels[0] = LevelExplain{0, 0, 0, 0, 0};
  }
  return out;
}

// The perceptual rules for a block whose passes are done: each eye's choice, the finer need wins.
void Scheduler::Impl::choose_perceptual(std::uint32_t first, std::uint32_t n, const Look (*looks)[kBlock],
                                        const Sight (*sights)[kBlock], Decisions* out) {
  for (std::uint32_t j = 0; j < n; ++j) {
    const ObjectId id = first + j;
    if (profile_of_[id] < 0) continue;
    const std::uint32_t K = level_count_[profile_of_[id]];
    Choice both{255, 255, 0};
    float* kept = config_.keep_scores ? &scores_[std::size_t(id) * kMaxLevels] : nullptr;
    float eye_scores[kMaxLevels];
    for (std::uint32_t i = 0; i < eye_count_; ++i) {  // both eyes agree: the finer need wins
      both = finer(both, evaluate(id, looks[i][j], sights[i][j], kept ? eye_scores : nullptr, nullptr));
      if (kept)
        for (std::uint32_t k = 0; k < K; ++k)
          kept[k] = i == 0 ? eye_scores[k] : std::max(kept[k], eye_scores[k]);
    }
    out->fine[j] = both.fine;
    out->coarse[j] = both.coarse;
    out->flags[j] = both.flags;
  }
}

}  // namespace acuity
