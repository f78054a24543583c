// Vision models: see acuity/models.hpp for the contract and vision-models.md for the sources.
#include "acuity/models.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>

namespace acuity {
namespace {

template <class T>
constexpr T kNaN = std::numeric_limits<T>::quiet_NaN();
template <class T>
constexpr T kInf = std::numeric_limits<T>::infinity();
template <class T>
constexpr T kPi = std::numbers::pi_v<T>;

template <class T>
T log_max() {
  static const T value = std::log(std::numeric_limits<T>::max());
  return value;
}

// exp(x) that saturates at the largest finite T instead of overflowing.
template <class T>
T saturating_exp(T x) {
  if (std::isnan(x)) return x;
  return x >= log_max<T>() ? std::numeric_limits<T>::max() : std::exp(x);
}

// Kelly's velocity factor k(v) = 6.1 + 7.3 |log10(v / 3)|^3, v > 0 finite.
template <class T>
T kelly_k(T v) {
  const T l = std::abs(std::log10(v / T(3)));
  return T(6.1) + T(7.3) * l * l * l;
}

// Velocity magnitude with the drift floor applied; NaN stays NaN.
template <class T>
T floored_velocity(T v, double floor) {
  v = std::abs(v);
  return v < T(floor) ? T(floor) : v;  // NaN compares false and is kept
}

// ln of Daly's CSF at frequency rho [cpd] and floored velocity v [deg/s]; -inf where S = 0.
template <class T>
T log_daly_csf(T rho, T v, const DalyFitConstants& c) {
  const T x = T(c.c2) * v;
  if (rho == T(0) || std::isinf(rho) || std::isinf(x)) return -kInf<T>;
  // Each term stays finite for finite input; only the exponent may reach -inf (then S = 0).
  const T decay = T(4) * kPi<T> * T(c.c1) * rho * (x + T(2)) / T(45.9);
  return std::log(T(c.prefactor)) + std::log(v) + T(2) * (std::log(T(2) * kPi<T> * T(c.c1)) + std::log(rho)) -
         decay + std::log(kelly_k(x));
}

template <class T>
T daly_peak(T v, const DalyFitConstants& c) {
  return T(45.9) / (T(2) * kPi<T> * T(c.c1) * (T(c.c2) * v + T(2)));
}

template <class T>
T daly_velocity(T v, const ModelParams& p, const DalyFitConstants& c) {
  return floored_velocity(v, std::max(p.drift, c.v_floor));
}

// Geisler-Perry eccentricity exponent alpha f e / e2 (0 when f or e is 0, so 0 * inf never occurs).
template <class T>
T eccentricity_exponent(T f, T e, const ModelParams& p) {
  if (f == T(0) || e == T(0)) return T(0);
  return T(p.alpha) * f * e / T(p.e2);
}

// Newton's method on h(x) = ln CT(e^x) - ln c for the Daly-based models, where
// ln CT(rho) = -ln S(rho, v) + a rho is convex and increasing in x = ln rho above x_lo.
// Starting to the right of the root, the iterates decrease monotonically onto it.
template <class T>
T solve_above(T rho_lo, T log_c, T v, T a, const DalyFitConstants& c) {
  const T b = T(4) * kPi<T> * T(c.c1) * (T(c.c2) * v + T(2)) / T(45.9);
  auto h = [&](T x) {
    const T rho = std::exp(x);
    return -log_daly_csf(rho, v, c) + a * rho - log_c;
  };
  T x_lo = std::log(rho_lo);
  T step = T(1);
  T x = x_lo + step;
  for (int i = 0; i < 64 && h(x) <= T(0); ++i) {  // bracket: h grows like e^x, so this is short
    x_lo = x;
    step *= T(2);
    x = x_lo + step;
  }
  for (int i = 0; i < 200; ++i) {
    const T hx = h(x);
    if (hx <= T(0)) break;  // on the root (to rounding)
    const T slope = (a + b) * std::exp(x) - T(2);
    const T next = x - hx / slope;
    if (!(next < x)) break;  // no more progress
    x = std::max(next, x_lo);
  }
  return std::exp(x);
}

}  // namespace

// ---- Geisler & Perry ------------------------------------------------------------------------------

template <class T>
T geisler_perry_threshold(T f, T e, const ModelParams& p) {
  f = std::abs(f);
  e = std::abs(e);
  if (std::isnan(f) || std::isnan(e)) return kNaN<T>;
  const T exponent = (f == T(0)) ? T(0) : T(p.alpha) * f * (e + T(p.e2)) / T(p.e2);
  return saturating_exp(std::log(T(p.ct0)) + exponent);
}

template <class T>
T geisler_perry_cutoff(T e, T contrast, const ModelParams& p) {
  e = std::abs(e);
  contrast = std::abs(contrast);
  if (std::isnan(e) || std::isnan(contrast)) return kNaN<T>;
  if (contrast <= T(p.ct0) || std::isinf(e)) return T(0);
  if (std::isinf(contrast)) return kInf<T>;
  return T(p.e2) * (std::log(contrast) - std::log(T(p.ct0))) / (T(p.alpha) * (e + T(p.e2)));
}

// ---- Kelly ----------------------------------------------------------------------------------------

template <class T>
T kelly_csf(T f, T v, const ModelParams& p) {
  f = std::abs(f);
  v = floored_velocity(v, p.drift);
  if (std::isnan(f) || std::isnan(v)) return kNaN<T>;
  if (f == T(0) || std::isinf(f) || std::isinf(v)) return T(0);
  const T decay = T(4) * kPi<T> * f * (v + T(2)) / T(45.9);  // 2 alpha / alpha_max
  return std::exp(std::log(kelly_k(v)) + std::log(v) + T(2) * (std::log(T(2) * kPi<T>) + std::log(f)) -
                  decay);
}

template <class T>
T kelly_peak_frequency(T v, const ModelParams& p) {
  v = floored_velocity(v, p.drift);
  return T(45.9) / (T(2) * kPi<T> * (v + T(2)));
}

// ---- Daly -----------------------------------------------------------------------------------------

template <class T>
T daly_eye_velocity(T v_image, const ModelParams& p) {
  v_image = std::abs(v_image);
  if (std::isnan(v_image)) return v_image;
  return std::min(T(p.pursuit_gain) * v_image + T(p.pursuit_min), T(p.pursuit_max));
}

template <class T>
T daly_retinal_velocity(T v_image, const ModelParams& p) {
  v_image = std::abs(v_image);
  const T v_r = std::abs(v_image - daly_eye_velocity(v_image, p));
  return floored_velocity(v_r, p.drift);
}

template <class T>
T daly_csf(T f, T v, const ModelParams& p) {
  const DalyFitConstants c = daly_fit_constants(p.fit);
  f = std::abs(f);
  v = daly_velocity(v, p, c);
  if (std::isnan(f) || std::isnan(v)) return kNaN<T>;
  return std::exp(log_daly_csf(f, v, c));
}

template <class T>
T daly_peak_frequency(T v, const ModelParams& p) {
  const DalyFitConstants c = daly_fit_constants(p.fit);
  return daly_peak(daly_velocity(v, p, c), c);
}

DalyFitConstants daly_fit_constants(CsfFit fit) {
  switch (fit) {
    case CsfFit::Laird2006:
      return {0.6329, 0.8404, 0.7986, 0.6329 * 0.8404 * 0.7986, 0.1};
    case CsfFit::Daly1998:
      break;
  }
  return {1.14, 0.67, 1.7, 1.14 * 1.7, 0.0};
}

// ---- Reddy ----------------------------------------------------------------------------------------

template <class T>
T reddy_eccentricity(T e) {
  e = std::abs(e);
  if (std::isnan(e)) return e;
  if (e <= T(5.79)) return T(1);
  const T d = T(0.3) * e + T(1);
  return T(7.49) / (d * d);
}

template <class T>
T reddy_velocity(T v) {
  v = std::abs(v);
  if (std::isnan(v)) return v;
  if (v <= T(0.825)) return T(60);
  if (v <= T(118.3)) return T(57.69) - T(27.78) * std::log10(v);
  return T(0.1);
}

template <class T>
T reddy_cutoff(T v, T e) {
  return reddy_velocity(v) * reddy_eccentricity(e);
}

// ---- stelaCSF ------------------------------------------------------------------------------------

namespace {
// The fit's luminance range (CSF_stelaCSF.m Y_min, Y_max): outside it the transient S_max grows
// without bound and the sustained one falls to 0, so luminance is clamped to it.
constexpr double kStelaMinLuminance = 0.001, kStelaMaxLuminance = 10000.0;

// ln(x + y) from ln x and ln y (either may be -inf).
template <class T>
T log_add(T a, T b) {
  const T hi = std::max(a, b), lo = std::min(a, b);
  if (hi == -kInf<T>) return hi;
  return hi + std::log1p(std::exp(lo - hi));
}

// ln of one mechanism's S_LP(rho): the log-parabola around ln_fmax, truncated at 1 - a below it.
template <class T>
T log_stela_parabola(T ln_rho, T ln_fmax, T bw, T a) {
  constexpr T kLn10 = std::numbers::ln10_v<T>;
  const T d = (ln_rho - ln_fmax) / kLn10;          // log10(rho / f_max)
  const T ln_lp = -d * d / std::exp2(bw) * kLn10;  // ln 10^(-d^2 / 2^bw)
  return d < T(0) ? std::max(ln_lp, std::log1p(-a)) : ln_lp;
}

// ln S before the eccentricity drop: rho finite > 0, omega >= 0, luminance in the fit's range.
template <class T>
T log_stela_foveal(T rho, T omega, T luminance, T area, const StelaConstants& c) {
  const T ln_rho = std::log(rho), L = luminance;
  // Luminance dependences (CSF_base.m get_lum_dep): 5, 3, 2 and 1 parameters.
  const T ln_s_sust = std::log(T(c.sust_s_max[0])) - T(c.sust_s_max[2]) * std::log1p(T(c.sust_s_max[1]) / L) +
                      std::log(-std::expm1(-T(c.sust_s_max[4]) * std::log1p(T(c.sust_s_max[3]) / L)));
  const T ln_f_sust = std::log(T(c.sust_f_max[0])) - T(c.sust_f_max[2]) * std::log1p(T(c.sust_f_max[1]) / L);
  const T ln_s_trans = std::log(T(c.trans_s_max[1])) + T(c.trans_s_max[0]) * std::log(L);
  const T ln_f_trans = std::log(T(c.trans_f_max));
  // Temporal responses (ln R): 0^beta = 0 at omega = 0; omega = +inf gives -inf.
  const T ln_r_sust = -std::pow(omega, T(c.beta_sust)) / T(c.sigma_sust);
  const T dt = std::pow(omega, T(c.beta_trans)) - std::pow(T(c.omega0), T(c.beta_trans));
  const T ln_r_trans = -dt * dt / T(c.sigma_trans);
  const T sust = ln_r_sust + ln_s_sust + log_stela_parabola(ln_rho, ln_f_sust, T(c.sust_bw), T(c.sust_a));
  const T trans =
      ln_r_trans + ln_s_trans + log_stela_parabola(ln_rho, ln_f_trans, T(c.trans_bw), T(c.trans_a));
  // Both mechanisms share Rovamo's area term sqrt(A_c A / (A_c + A)) and the factor rho: finite or -inf.
  const T x = rho / T(c.f0);
  const T inv_area = (T(1) + x * x) / T(c.a0) + T(1) / area;  // 1 / A_c + 1 / A (may be +inf)
  return log_add(sust, trans) - T(0.5) * std::log(inv_area) + ln_rho;
}

// Magnitudes of a stimulus' inputs; false when any is NaN.
template <class T>
bool stela_inputs(T* rho, T* omega, T* luminance, T* area, T* e) {
  *rho = std::abs(*rho);
  *omega = std::abs(*omega);
  *area = std::abs(*area);
  *e = std::abs(*e);
  *luminance = std::clamp(std::abs(*luminance), T(kStelaMinLuminance), T(kStelaMaxLuminance));  // NaN kept
  return !(std::isnan(*rho) || std::isnan(*omega) || std::isnan(*luminance) || std::isnan(*area) ||
           std::isnan(*e));
}

// ln S with the eccentricity drop (d + rho d_f) e, d and d_f > 0. NaN-free inputs (stela_inputs).
template <class T>
T log_stela(T rho, T omega, T luminance, T area, T e, T d, T d_f, const StelaConstants& c) {
  if (rho == T(0) || std::isinf(rho) || area == T(0)) return -kInf<T>;
  const T drop = e == T(0) ? T(0) : std::numbers::ln10_v<T> * (d + rho * d_f) * e;  // never 0 * inf
  return log_stela_foveal(rho, omega, luminance, area, c) - drop;
}

// The threshold model's ln CT: the most sensitive meridian's drop, omega = f (max(v, drift) - drift).
template <class T>
T log_stela_threshold(T f, T e, T v_retinal, const ModelParams& p) {
  // f = 0 keeps omega at 0 (never 0 * inf); f = 0 is invisible anyway (log_stela).
  T omega = f == T(0) ? T(0) : f * (floored_velocity(v_retinal, p.drift) - T(p.drift));
  T luminance = T(p.luminance), area = T(p.area);
  if (!stela_inputs(&f, &omega, &luminance, &area, &e)) return kNaN<T>;
  const StelaConstants& c = p.stela;
  const T temporal = T(c.ecc_drop) + f * T(c.ecc_drop_f),
          nasal = T(c.ecc_drop_nasal) + f * T(c.ecc_drop_f_nasal);
  const bool use_nasal = nasal < temporal;
  return -log_stela(f, omega, luminance, area, e, use_nasal ? T(c.ecc_drop_nasal) : T(c.ecc_drop),
                    use_nasal ? T(c.ecc_drop_f_nasal) : T(c.ecc_drop_f), c);
}

// Highest f with ln CT(f) <= ln c for StelaCsf (see max_visible_frequency in models.hpp): works on
// h(x) = ln CT(e^x) - ln c, x = ln f.
template <class T>
T stela_max_visible_frequency(T log_c, T e, T v_retinal, const ModelParams& p) {
  auto h = [&](T x) { return log_stela_threshold(std::exp(x), e, v_retinal, p) - log_c; };
  const T step = std::log(T(2)) / T(4), bottom = std::log(T(2)) * T(-10);
  T x_hi = std::log(T(64)), h_hi = h(x_hi);
  if (std::isnan(h_hi)) return kNaN<T>;  // a NaN luminance or area
  while (h_hi <= T(0)) {                 // ln CT grows without bound in f (the log-parabola), so this ends
    if (x_hi > std::log(std::numeric_limits<T>::max()) - T(1)) return std::exp(x_hi);
    x_hi += std::log(T(2));
    h_hi = h(x_hi);
  }
  T x_lo = x_hi - step, h_lo = h(x_lo);
  while (h_lo > T(0)) {  // down in quarter octaves to the first visible frequency
    if (x_lo < bottom) return T(0);
    x_hi = x_lo;
    h_hi = h_lo;
    x_lo -= step;
    h_lo = h(x_lo);
  }
  // Illinois (regula falsi that halves the stale end's value): keeps h(x_lo) <= 0 < h(x_hi) and
  // converges superlinearly; h_hi may be +inf (S = 0), which falls back to bisection.
  const T tol = T(16) * std::numeric_limits<T>::epsilon();
  int side = 0;
  for (int i = 0; i < 100 && x_hi - x_lo > tol * std::max(T(1), std::abs(x_lo)); ++i) {
    T x = x_hi - h_hi * (x_hi - x_lo) / (h_hi - h_lo);
    if (!(x > x_lo && x < x_hi)) x = T(0.5) * (x_lo + x_hi);
    const T hx = h(x);
    if (hx <= T(0)) {
      x_lo = x;
      h_lo = hx;
      if (side == -1) h_hi *= T(0.5);
      side = -1;
    } else {
      x_hi = x;
      h_hi = hx;
      if (side == 1) h_lo *= T(0.5);
      side = 1;
    }
  }
  return std::exp(x_lo);
}
}  // namespace

template <class T>
T stela_log_area_penalty(T rho, T area, const StelaConstants& c) {
  if (std::isnan(rho) || std::isnan(area)) return kNaN<T>;
  const T x = std::abs(rho) / T(c.f0);
  const T critical = T(c.a0) / (T(1) + x * x);            // A_c [deg^2]
  return T(0.5) * std::log1p(critical / std::abs(area));  // area 0: +inf; +inf: 0
}

template <class T>
T stela_csf(T rho, T omega, T luminance, T area, T e, T vis_field, const StelaConstants& c) {
  if (!stela_inputs(&rho, &omega, &luminance, &area, &e) || std::isnan(vis_field)) return kNaN<T>;
  const T alpha = std::min(T(1), std::abs(vis_field - T(180)) / T(90));  // 1: temporal constants
  const T d = alpha * T(c.ecc_drop) + (T(1) - alpha) * T(c.ecc_drop_nasal);
  const T d_f = alpha * T(c.ecc_drop_f) + (T(1) - alpha) * T(c.ecc_drop_f_nasal);
  return std::exp(log_stela(rho, omega, luminance, area, e, d, d_f, c));
}

// ---- MAR ------------------------------------------------------------------------------------------

template <class T>
T mar(T e, T slope, T omega0) {
  return slope * std::abs(e) + omega0;
}

// ---- Combined models ------------------------------------------------------------------------------

namespace {
template <class T>
T log_threshold_unsaturated(T f, T e, T v_retinal, ThresholdModel model, const ModelParams& p) {
  f = std::abs(f);
  e = std::abs(e);
  if (std::isnan(f) || std::isnan(e) || std::isnan(v_retinal)) return kNaN<T>;
  switch (model) {
    case ThresholdModel::GeislerPerry: {
      const T exponent = (f == T(0)) ? T(0) : T(p.alpha) * f * (e + T(p.e2)) / T(p.e2);
      return std::log(T(p.ct0)) + exponent;
    }
    case ThresholdModel::Reddy:
      return f <= reddy_cutoff(v_retinal, e) ? std::log(T(p.reddy_contrast)) : log_max<T>();
    case ThresholdModel::KellyDaly:
    case ThresholdModel::Default: {
      const DalyFitConstants c = daly_fit_constants(p.fit);
      const T v = daly_velocity(v_retinal, p, c);
      const T rho = model == ThresholdModel::Default ? std::max(f, daly_peak(v, c)) : f;
      return -log_daly_csf(rho, v, c) + eccentricity_exponent(f, e, p);
    }
    case ThresholdModel::StelaCsf:
      return log_stela_threshold(f, e, v_retinal, p);
  }
  return kNaN<T>;
}
}  // namespace

template <class T>
T log_threshold(T f, T e, T v_retinal, ThresholdModel model, const ModelParams& p) {
  return std::min(log_threshold_unsaturated(f, e, v_retinal, model, p), log_max<T>());  // NaN stays
}

template <class T>
T threshold(T f, T e, T v_retinal, ThresholdModel model, const ModelParams& p) {
  return saturating_exp(log_threshold_unsaturated(f, e, v_retinal, model, p));
}

template <class T>
T max_visible_frequency(T contrast, T e, T v_retinal, ThresholdModel model, const ModelParams& p) {
  contrast = std::abs(contrast);
  e = std::abs(e);
  if (std::isnan(contrast) || std::isnan(e) || std::isnan(v_retinal)) return kNaN<T>;
  if (std::isinf(contrast)) return kInf<T>;
  if (contrast == T(0)) return T(0);

  switch (model) {
    case ThresholdModel::GeislerPerry:
      return geisler_perry_cutoff(e, contrast, p);
    case ThresholdModel::Reddy:
      return contrast >= T(p.reddy_contrast) ? reddy_cutoff(v_retinal, e) : T(0);
    case ThresholdModel::KellyDaly:
    case ThresholdModel::Default: {
      const DalyFitConstants c = daly_fit_constants(p.fit);
      const T v = daly_velocity(v_retinal, p, c);
      if (std::isinf(v) || std::isinf(e)) return T(0);  // sensitivity 0 at every f > 0
      const T log_c = std::log(contrast);
      const T a = T(p.alpha) * e / T(p.e2);  // ln CT grows by a per cpd with eccentricity
      const T b = T(4) * kPi<T> * T(c.c1) * (T(c.c2) * v + T(2)) / T(45.9);
      if (model == ThresholdModel::Default) {
        // Below the peak the CSF is held at its peak value: ln CT = -ln S_peak + a f (closed form).
        const T rho_p = daly_peak(v, c);
        const T log_s_peak = log_daly_csf(rho_p, v, c);
        if (-log_s_peak + a * rho_p <= log_c) return solve_above(rho_p, log_c, v, a, c);
        if (a <= T(0)) return T(0);
        return std::max(T(0), (log_c + log_s_peak) / a);
      }
      // Band-pass: ln CT is convex in f with its minimum at 2 / (a + b).
      const T rho_min = T(2) / (a + b);
      if (-log_daly_csf(rho_min, v, c) + a * rho_min > log_c) return T(0);
      return solve_above(rho_min, log_c, v, a, c);
    }
    case ThresholdModel::StelaCsf:
      if (std::isinf(e) || std::isinf(v_retinal)) return T(0);  // sensitivity 0 at every f > 0
      return stela_max_visible_frequency(std::log(contrast), e, v_retinal, p);
  }
  return kNaN<T>;
}

template <class T>
void threshold_batch(std::size_t count, const T* f, const T* e, const T* v_retinal, T* out,
                     ThresholdModel model, const ModelParams& p) {
  for (std::size_t i = 0; i < count; ++i) out[i] = threshold(f[i], e[i], v_retinal[i], model, p);
}

// ---- Names ----------------------------------------------------------------------------------------

namespace {
struct ModelName {
  const char* name;
  ThresholdModel model;
};
constexpr ModelName kModelNames[] = {{"default", ThresholdModel::Default},
                                     {"geisler-perry", ThresholdModel::GeislerPerry},
                                     {"kelly-daly", ThresholdModel::KellyDaly},
                                     {"reddy", ThresholdModel::Reddy},
                                     {"stela-csf", ThresholdModel::StelaCsf}};
}  // namespace

bool parse_threshold_model(const char* name, ThresholdModel* out) {
  for (const ModelName& m : kModelNames)
    if (name && std::strcmp(name, m.name) == 0) {
      *out = m.model;
      return true;
    }
  return false;
}

const char* to_string(ThresholdModel model) {
  for (const ModelName& m : kModelNames)
    if (m.model == model) return m.name;
  return "unknown";
}

const char* threshold_model_names() {
  static const std::string names = [] {
    std::string out;
    for (const ModelName& m : kModelNames) out += (out.empty() ? "" : ", ") + std::string(m.name);
    return out;
  }();
  return names.c_str();
}

bool parse_csf_fit(const char* name, CsfFit* out) {
  if (!name) return false;
  if (std::strcmp(name, "daly1998") == 0) {
    *out = CsfFit::Daly1998;
    return true;
  }
  if (std::strcmp(name, "laird2006") == 0) {
    *out = CsfFit::Laird2006;
    return true;
  }
  return false;
}

const char* to_string(CsfFit fit) { return fit == CsfFit::Laird2006 ? "laird2006" : "daly1998"; }

// ---- Instantiations -------------------------------------------------------------------------------

#define ACUITY_INSTANTIATE(T)                                                                     \
  template T geisler_perry_threshold<T>(T, T, const ModelParams&);                                \
  template T geisler_perry_cutoff<T>(T, T, const ModelParams&);                                   \
  template T kelly_csf<T>(T, T, const ModelParams&);                                              \
  template T kelly_peak_frequency<T>(T, const ModelParams&);                                      \
  template T daly_eye_velocity<T>(T, const ModelParams&);                                         \
  template T daly_retinal_velocity<T>(T, const ModelParams&);                                     \
  template T daly_csf<T>(T, T, const ModelParams&);                                               \
  template T daly_peak_frequency<T>(T, const ModelParams&);                                       \
  template T reddy_eccentricity<T>(T);                                                            \
  template T reddy_velocity<T>(T);                                                                \
  template T reddy_cutoff<T>(T, T);                                                               \
  template T stela_csf<T>(T, T, T, T, T, T, const StelaConstants&);                               \
  template T stela_log_area_penalty<T>(T, T, const StelaConstants&);                              \
  template T mar<T>(T, T, T);                                                                     \
  template T log_threshold<T>(T, T, T, ThresholdModel, const ModelParams&);                       \
  template T threshold<T>(T, T, T, ThresholdModel, const ModelParams&);                           \
  template T max_visible_frequency<T>(T, T, T, ThresholdModel, const ModelParams&);               \
  template void threshold_batch<T>(std::size_t, const T*, const T*, const T*, T*, ThresholdModel, \
                                   const ModelParams&);
ACUITY_INSTANTIATE(float)
ACUITY_INSTANTIATE(double)
#undef ACUITY_INSTANTIATE

}  // namespace acuity
