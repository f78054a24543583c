// Vision models: see acuity/models.hpp for the contract and vision-models.md for the sources.
#include "acuity/models.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

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
                                     {"reddy", ThresholdModel::Reddy}};
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
