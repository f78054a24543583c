#pragma once
// The tabulated path's threshold curves on the table grid (scheduler/src only): what build_tables()
// reads the largest invisible sizes from.
#include "tables.hpp"

namespace acuity {

// The tabulated path's threshold curves on the table grid (config-dependent, profile-independent).
struct Scheduler::Impl::Curves {
  std::vector<float> still;   // [kStillE][kCurveSamples]: the floor's terms
  std::vector<float> slow;    // [kStillE][kCurveSamples]: moving at the floor (the velocity envelope)
  std::vector<float> moving;  // [kMovingS][kMovingE][kCurveSamples]
  std::vector<float> centre;  // [kMovingS - 1][kMovingE - 1][kCurveSamples]: each moving cell's midpoint
  std::vector<float> still_centre, slow_centre;  // [kStillE - 1][kCurveSamples]: each cell's midpoint
  // The Default model's largest invisible size is not concave along speed everywhere: where a band's
  // lost contrast nears the CSF's peak threshold it rises steeply, and it jumps where the band becomes
  // invisible at any size. So each moving cell's rows (at each eccentricity node) are checked at
  // kRowChecks - 1 speeds inside, at weights m / kRowChecks:
  // [kMovingS - 1][kMovingE][kRowChecks - 1][kCurveSamples] (empty for the other models, whose
  // thresholds do not depend on speed or are known in advance).
  static constexpr int kRowChecks = 8;
  std::vector<float> row_checks;
  static std::size_t row_check_at(std::uint32_t i, std::uint32_t j, int m) {
    return ((std::size_t(i) * kMovingE + j) * (kRowChecks - 1) + std::size_t(m - 1)) * kCurveSamples;
  }
  // Reddy's cutoff H(v) M(e) is separable and kinked (0.825 deg/s, 5.79 deg; -ln H steep and convex
  // towards 118 deg/s), so a cell's midpoint does not show how far interpolation rises above the
  // truth. The largest invisible ln size is ln(band) - ln H(v) - ln M(e) whatever the profile, so how
  // far each node must come down for its cells to stay below it is known in advance, per axis
  // (Lift): [kStillE - 1] and [kMovingS - 1], [kMovingE - 1] (empty for the other models).
  struct Lift {
    float lower, upper;  // [ln deg] at the cell's lower and upper node
  };
  std::vector<Lift> still_lift, speed_lift, moving_e_lift;
  // The area law (Rovamo's, stelaCSF's constants a0 [deg^2], f0 [cpd]) on a loss of extent a [fraction
  // of the squared angular diameter D] in a band of centre c [cpod], seen at f = c / D: the threshold
  // grows by sqrt(1 + A_c(f) / (a D^2)), A_c = a0 / (1 + (f / f0)^2). In u = ln f that is
  // ln-factor 0.5 ln(1 + k w(u)), k = a0 / (a c^2) (per loss: area_k(); 0 for no area law) and
  // w(u) = 1 / (e^(-2u) + f0^-2) (per curve sample: area_weight), rising with u: adding it keeps a
  // curve non-decreasing, so every search below reads curve + term as it read the curve.
  std::vector<float> area_weight;  // [kCurveSamples]
  static float area_w(float u, float f0) { return 1.0f / (std::exp(-2.0f * u) + 1.0f / (f0 * f0)); }
  static float area_term(float k, float w) { return k > 0.0f ? 0.5f * std::log1p(k * w) : 0.0f; }
  // A loss's area law as the searches read it (AreaLaw): per block of 2^kKnotShift samples the
  // factor at the block's first (a lower bound over the block, the factor rising with u:
  // conservative), so that a search (and refine()) costs no logarithm per comparison.
  static constexpr int kKnotShift = 5, kKnots = kCurveSamples >> kKnotShift;
  // The knots of k (out: kKnots values) from area_weight.
  void area_knots(float k, float* out) const {
    for (int j = 0; j < kKnots; ++j) out[j] = area_term(k, area_weight[std::size_t(j) << kKnotShift]);
  }
  static float with_law(const float* curve, int i, AreaLaw law) {
    return law.k > 0.0f ? curve[i] + law.knots[i >> kKnotShift] : curve[i];
  }
  static float speed(std::uint32_t i, float floor) { return floor * power_of_two(i); }
  // The speed at weight w of speed cell i (speed_cell()'s weight w = g inv_g, g = (v - lo) / (v + lo +
  // 2 v0), solved for v).
  static float speed_at(std::uint32_t i, float w, float floor, float v0) {
    const float lo = speed(i, floor), g = w * lo / (3.0f * lo + 2.0f * v0);
    return (lo + g * (lo + 2.0f * v0)) / (1.0f - g);
  }
  static float centre_speed(std::uint32_t i, float floor, float v0) {
    return speed_midpoint(speed(i, floor), v0);
  }
  static float centre_e(std::uint32_t j) { return 0.5f * (moving_e_node(j) + moving_e_node(j + 1)); }
  static float still_centre_e(std::uint32_t j) { return 0.5f * (still_e_node(j) + still_e_node(j + 1)); }
  // The least the ends of a cell must come down (a at w = 0, b at w = 1, both >= 0, a + b least) for
  // the chord of f to stay at or below f over the cell, at 4096 weights w in [0, 1] mapped to the axis
  // by x(w): {0, 0} where f is concave.
  template <class F, class X>
  static Lift chord_lift(F f, X x) {
    constexpr int kSteps = 4096;
    const float f0 = f(x(0.0f)), f1 = f(x(1.0f));
    float rise[kSteps + 1];
    float most_a = 0;  // a with b = 0
    for (int i = 0; i <= kSteps; ++i) {
      const float w = float(i) / float(kSteps);
      rise[i] = f0 + w * (f1 - f0) - f(x(w));
      if (i < kSteps) most_a = std::max(most_a, rise[i] / (1.0f - w));
    }
    auto least_b = [&](float a) {  // the least b >= 0 that covers every sample given a
      float b = 0;
      for (int i = 1; i <= kSteps; ++i) {
        const float w = float(i) / float(kSteps);
        b = std::max(b, (rise[i] - a * (1.0f - w)) / w);
      }
      return b;
    };
    float lo = 0, hi = most_a;  // a + least_b(a) is convex in a: ternary search
    for (int it = 0; it < 60; ++it) {
      const float m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (m1 + least_b(m1) <= m2 + least_b(m2))
        hi = m2;
      else
        lo = m1;
    }
    return {hi, least_b(hi)};
  }
  // Reddy's lifts (see still_lift): per axis, -ln M(e) and -ln H(v) against the weights the frame
  // loop interpolates with (e_cell, speed_cell).
  void reddy_lifts(float floor, float v0) {
    auto ln_size_e = [](float e) { return -std::log(reddy_eccentricity(e)); };
    auto ln_size_v = [](float v) { return -std::log(reddy_velocity(v)); };
    auto e_axis = [](float lower, float upper) {
      return [=](float w) { return lower + w * (upper - lower); };
    };
    for (std::uint32_t j = 0; j + 1 < kStillE; ++j)
      still_lift.push_back(chord_lift(ln_size_e, e_axis(still_e_node(j), still_e_node(j + 1))));
    for (std::uint32_t j = 0; j + 1 < kMovingE; ++j)
      moving_e_lift.push_back(chord_lift(ln_size_e, e_axis(moving_e_node(j), moving_e_node(j + 1))));
    for (std::uint32_t i = 0; i + 1 < kMovingS; ++i) {
      speed_lift.push_back(chord_lift(ln_size_v, [=](float w) { return speed_at(i, w, floor, v0); }));
    }
  }
  // Samples ln CT over the curve's range and makes it non-decreasing from the top (suffix minimum).
  static void sample(const Precomputed& pre, const SchedulerConfig& c, float e, float v, bool moving,
                     float* out) {
    const VelocityTerms own = pre.own_terms(v, moving);
    for (int i = 0; i < kCurveSamples; ++i)
      out[i] = pre.ln_ct(c, kCurveU0 + kCurveStep * float(i), e, v, moving, own);
    for (int i = kCurveSamples - 2; i >= 0; --i) out[i] = std::min(out[i], out[i + 1]);
  }
  // ln of the largest angular diameter [ln deg] at which a component of band ln_band [ln cpod] with
  // ln lost contrast y (already divided by q) stays at or below threshold: ln_band - u*, u* the
  // smallest ln f above which the curve stays >= y. Bisection on the model itself refines the sampled
  // bracket; the upper end is kept, so the result errs small (conservative).
  // The same from the samples alone: ln_band - (the upper end of the sampled bracket), at most one
  // sample step below the largest size (that refined by refine()). `bracket` receives the sample
  // index of that upper end (-1: the curve's ends decided, nothing to refine).
  // `hint` (a sample index, e.g. the bracket at the neighbouring grid node) starts a galloping search
  // there: the same bracket in a few steps where neighbouring nodes' answers lie close.
  // With an area law the curve read is curve + its knots (with_law()).
  static float sampled_size(const float* curve, float y, float ln_band, int* bracket,
                            int hint = kCurveSamples / 2, AreaLaw law = {}) {
    *bracket = -1;
    const auto at = [&](int i) { return with_law(curve, i, law); };
    if (!(y > at(0))) return ln_band - kCurveU0;
    if (y > at(kCurveSamples - 1)) return ln_band - kCurveU1;
    int lo = 0, hi = kCurveSamples - 1;  // at(lo) < y <= at(hi)
    hint = std::clamp(hint, 1, kCurveSamples - 1);
    if (at(hint) >= y) {  // gallop down from the hint
      hi = hint;
      for (int step = 1; hi - step > 0; step *= 2) {
        if (at(hi - step) < y) {
          lo = hi - step;
          break;
        }
        hi -= step;
      }
    } else {  // gallop up
      lo = hint;
      for (int step = 1; lo + step < kCurveSamples - 1; step *= 2) {
        if (at(lo + step) >= y) {
          hi = lo + step;
          break;
        }
        lo += step;
      }
    }
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (at(mid) >= y ? hi : lo) = mid;
    }
    *bracket = hi;
    return ln_band - (kCurveU0 + kCurveStep * float(hi));
  }
  static float refine(const Precomputed& pre, const SchedulerConfig& c, int bracket, float y, float ln_band,
                      float e, float v, bool moving, AreaLaw law = {}) {
    float ulo = kCurveU0 + kCurveStep * float(bracket - 1), uhi = kCurveU0 + kCurveStep * float(bracket);
    const VelocityTerms own = pre.own_terms(v, moving);
    // The area law's lower bound over the bracket: its block's knot (the bracket's lower sample).
    const float lift = law.k > 0.0f ? law.knots[(bracket - 1) >> kKnotShift] : 0.0f;
    for (int i = 0; i < 6; ++i) {
      const float mid = 0.5f * (ulo + uhi);
      (pre.ln_ct(c, mid, e, v, moving, own) + lift >= y ? uhi : ulo) = mid;
    }
    return ln_band - uhi;
  }
  // min(bound, the largest size), the largest size being sampled_size() refined by refine() where
  // the samples leave a bracket: searched only where the samples leave the size possibly below bound
  // (sampled_at_least()), and refined only where they put it below (refine() raises a sampled value
  // by less than a step, never lowers it), so the same value for a fraction of the work. *hint as
  // sampled_size() leaves it where it searches (a hint changes only how fast a search is).
  static float largest_size_within(float bound, const Precomputed& pre, const SchedulerConfig& c,
                                   const float* curve, float y, float ln_band, float e, float v, bool moving,
                                   int* hint, AreaLaw law = {}) {
    if (sampled_at_least(curve, y, ln_band, bound, false, law)) return bound;
    int bracket;
    const float sampled = sampled_size(curve, y, ln_band, &bracket, *hint, law);
    if (bracket >= 0) *hint = bracket;
    if (bracket < 0 || sampled >= bound) return std::min(bound, sampled);
    return std::min(bound, refine(pre, c, bracket, y, ln_band, e, v, moving, law));
  }
  // Whether sampled_size(curve, y, ln_band) is at least s (strict: above s), exactly as that computes
  // it but without its search: its value ln_band - (kCurveU0 + kCurveStep hi) falls as the bracket's
  // upper end hi rises (float rounding is monotone), so it is at least s where hi is at most the
  // last index c whose value is: where curve[c] >= y (hi is the first index whose sample is).
  static bool sampled_at_least(const float* curve, float y, float ln_band, float s, bool strict,
                               AreaLaw law = {}) {
    const auto passes = [&](float v) { return strict ? v > s : v >= s; };
    const auto at = [&](int i) { return with_law(curve, i, law); };
    if (!(y > at(0))) return passes(ln_band - kCurveU0);
    if (y > at(kCurveSamples - 1)) return passes(ln_band - kCurveU1);
    const auto value = [&](int i) { return ln_band - (kCurveU0 + kCurveStep * float(i)); };
    const float guess = std::floor((ln_band - s - kCurveU0) / kCurveStep);  // c, give or take a step
    int c = guess >= 0.0f ? static_cast<int>(std::min(guess, float(kCurveSamples - 1))) : -1;
    while (c + 1 < kCurveSamples && passes(value(c + 1))) ++c;
    while (c >= 0 && !passes(value(c))) --c;
    return c >= 1 && at(c) >= y;  // here at(0) < y <= at(last): hi >= 1
  }
  // min over bands of sampled_size(): one search for the band `*lead` (in: the least band at a
  // neighbouring node, out: the least here), and for each other band one comparison at an index
  // (sampled_at_least()), searched only where it lies below. The same value as a search per band,
  // in a fraction of the work (one band is usually least over a region of the grid).
  // laws: per band, or null for none.
  static float least_sampled(const float* curve, const float* y, const float* ln_band, std::uint32_t bands,
                             int* hint, std::uint32_t* lead, const AreaLaw* laws = nullptr) {
    if (bands == 0) return -kNever;
    int bracket;
    const std::uint32_t first = std::min(*lead, bands - 1);
    *lead = first;
    const auto law = [&](std::uint32_t b) { return laws ? laws[b] : AreaLaw{}; };
    float least = sampled_size(curve, y[first], ln_band[first], &bracket, hint[first], law(first));
    if (bracket >= 0) hint[first] = bracket;
    for (std::uint32_t b = 0; b < bands; ++b) {
      if (b == first || sampled_at_least(curve, y[b], ln_band[b], least, false, law(b))) continue;
      least = sampled_size(curve, y[b], ln_band[b], &bracket, hint[b], law(b));  // below the least so far
      if (bracket >= 0) hint[b] = bracket;
      *lead = b;
    }
    return least;
  }
  // min over bands of the largest size: sampled for every band, refined only where it can be the minimum
  // (a refinement raises a value by less than one sample step); the bands above that are not
  // searched (sampled_at_least()): they cannot be the minimum. Same result, a fraction of the work.
  static float smallest_size(const Precomputed& pre, const SchedulerConfig& c, const float* curve,
                             const float* y, const float* ln_band, std::uint32_t bands, float e, float v,
                             bool moving, int* hint, std::uint32_t* lead, const AreaLaw* laws = nullptr) {
    const float near = least_sampled(curve, y, ln_band, bands, hint, lead, laws) + 1.01f * kCurveStep;
    float m = -kNever;
    for (std::uint32_t b = 0; b < bands; ++b) {
      const AreaLaw law = laws ? laws[b] : AreaLaw{};
      if (sampled_at_least(curve, y[b], ln_band[b], near, true, law)) continue;
      int bracket;
      const float sampled = sampled_size(curve, y[b], ln_band[b], &bracket, hint[b], law);
      if (bracket >= 0) hint[b] = bracket;
      m = std::min(m, bracket >= 0 ? refine(pre, c, bracket, y[b], ln_band[b], e, v, moving, law) : sampled);
    }
    return m;
  }
};

}  // namespace acuity
