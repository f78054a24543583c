#pragma once
// acuity/models.hpp — contrast-sensitivity and acuity models of the human visual system.
//
// Units: spatial frequency f in cycles/degree [cpd]; velocity v in [deg/s]; eccentricity e in
// [deg]; contrast is threshold contrast CT (sensitivity S = 1/CT). Formulas, constants and sources
// are in shared/reference/vision-models.md; each function names its source.
//
// Domain rules, the same for every function here:
// - NaN in -> NaN out.
// - Inputs are magnitudes: the sign of f, e and v is ignored.
// - Finite in -> finite out. Thresholds are computed in the log domain and saturate at the largest
//   finite value of T (meaning "invisible"); they never overflow to +inf.
// - +inf in -> the mathematical limit (a threshold still saturates; a cutoff may be +inf only when
//   the contrast given is +inf).
// - Velocities are floored at ModelParams::drift (the 0.15 deg/s fixational drift), so v = 0 never
//   reaches log10(0).
// Every function is instantiated for float and double; the float path computes in float.
#include <cstddef>
#include <cstdint>
#include <limits>

namespace acuity {

// Daly's fit of Kelly's spatio-velocity CSF.
enum class CsfFit : std::uint8_t {
  Daly1998,   // Daly 1998 as corrected by Myszkowski et al. 2000: c0 = 1.14, c1 = 0.67, c2 = 1.7
  Laird2006,  // Laird et al. 2006 refit (FovVideoVDP): c0 = 0.6329, c1 = 0.8404, c2 = 0.7986, v >= 0.1
};

// Which threshold surface threshold() evaluates.
enum class ThresholdModel : std::uint8_t {
  Default,       // Daly CSF held at its peak below the peak frequency (low-pass) x Geisler-Perry
                 // eccentricity factor exp(alpha f e / e2); docs/design.md section 5
  GeislerPerry,  // Geisler & Perry 1998 alone: CT0 exp(alpha f (e + e2) / e2); ignores velocity
  KellyDaly,     // Daly's CSF, the exact band-pass surface, x the same eccentricity factor
  Reddy,         // step: CT = reddy_contrast up to reddy_cutoff(v, e), invisible above [unverified]
  StelaCsf,      // stelaCSF (Mantiuk, Ashraf, Chapiro 2022), fitted to 11 data sets: 1 / stela_csf() at
                 // ModelParams::luminance and ::area, the most sensitive meridian, temporal frequency
                 // f (v - drift); band-pass in f and in v (see log_threshold); docs/design.md section 5
};

// stelaCSF's fitted constants: gfxdisp/stelaCSF matlab/CSF_stelaCSF.m get_default_par() at commit
// 052b15e (fit "stela-csf_all_2022-04-16"), and the fixed ones of its get_sust_trans_resp() and
// csf_achrom() (Rovamo et al. 1993's A0, f0). The luminance dependences are those of CSF_base.m
// get_lum_dep() for these vector lengths. [checked: shared/reference/vision-models.md section 4.1's
// table of the authors' code run under Octave, tests/test_models.cpp]
struct StelaConstants {
  // Sustained mechanism: S_max(L) = s0 (1 + s1/L)^-s2 (1 - (1 + s3/L)^-s4), f_max(L) = m0 (1 + m1/L)^-m2 [cpd]
  double sust_s_max[5] = {68.9501, 59.5023, 0.164274, 7.54866e-07, 7.77268e+09};
  double sust_f_max[3] = {1.62144, 36.6565, 0.255823};
  double sust_bw = 0.000219263;  // log-parabola bandwidth (divides by 2^bw)
  double sust_a = 0.103686;      // below f_max the parabola is truncated at 1 - a
  // Transient mechanism: S_max(L) = t1 L^t0, f_max constant [cpd]
  double trans_s_max[2] = {0.500846, 57.3469};
  double trans_f_max = 0.0267489;
  double trans_bw = 1.75147;
  double trans_a = 0.000273289;
  // Temporal responses: R_sust = exp(-w^beta_sust / sigma_sust),
  // R_trans = exp(-|w^beta_trans - omega0^beta_trans|^2 / sigma_trans), w [Hz]
  double sigma_sust = 5.79336, beta_sust = 1.3314;
  double sigma_trans = 0.12314, beta_trans = 0.1898, omega0 = 5.0;
  // Area (Rovamo, Luntinen, Nasanen 1993): critical area A_c = a0 / (1 + (rho/f0)^2) [deg^2]
  double a0 = 270.0, f0 = 0.65;
  // Eccentricity: S x 10^(-(d + rho d_f) e); temporal/superior/inferior d, nasal d (vis_field 180)
  double ecc_drop = 0.0296662, ecc_drop_nasal = 0.0113638;
  double ecc_drop_f = 0.0190062, ecc_drop_f_nasal = 0.0193858;
};

// Every constant of every model, overridable. Defaults are the published values.
struct ModelParams {
  // Geisler & Perry 1998 [checked]
  double ct0 = 1.0 / 64.0;  // minimum threshold contrast
  double alpha = 0.106;     // spatial-frequency decay constant
  double e2 = 2.3;          // half-resolution eccentricity [deg]
  // Daly 1998 smooth-pursuit model [checked]
  double pursuit_gain = 0.82;     // g
  double pursuit_min = 0.15;      // v_min [deg/s]
  double pursuit_max = 80.0;      // v_max [deg/s]
  double drift = 0.15;            // retinal velocity floor [deg/s]
  CsfFit fit = CsfFit::Daly1998;  // the CSF used by daly_csf() and the Default/KellyDaly models
  // Reddy: the threshold contrast inside the visible region of the step model
  double reddy_contrast = 1.0 / 64.0;
  // stelaCSF (ThresholdModel::StelaCsf): the fitted constants, and the two stimulus properties the
  // model needs besides f, e and v, one value for the whole configuration:
  StelaConstants stela;
  // Adapting (display) luminance [cd/m^2], clamped to the fit's range [0.001, 10000]. 100: the SDR
  // reference white and the authors' example condition; above a typical scene's mean, so it errs
  // towards sensitivity (stelaCSF's sensitivity rises with luminance up to ~1000 cd/m^2).
  double luminance = 100.0;
  // Area of the lost detail [deg^2] (0: invisible). +inf: the detail covers at least Rovamo's
  // critical area A_c at every frequency, the most sensitive case (at 1 cpd, 9x the sensitivity of a
  // 1 deg^2 patch; at 16 cpd 1.2x), because the chain does not know the detail's extent yet. A caller
  // that knows it (e.g. the object's projected area, an upper bound) may set it.
  double area = std::numeric_limits<double>::infinity();
};

// ---- Geisler & Perry 1998 -----------------------------------------------------------------------
// Threshold contrast at frequency f [cpd] and eccentricity e [deg]: CT0 exp(alpha f (e + e2) / e2).
template <class T>
T geisler_perry_threshold(T f, T e, const ModelParams& p = {});
// Highest visible frequency [cpd] at contrast c: e2 ln(c / CT0) / (alpha (e + e2)).
// Returns 0 when nothing is visible (c <= CT0). f_c(0, 1) = 39.2347 cpd.
template <class T>
T geisler_perry_cutoff(T e, T contrast = T(1), const ModelParams& p = {});

// ---- Kelly 1979 ---------------------------------------------------------------------------------
// Spatio-velocity sensitivity G(alpha, v) = k(v) v alpha^2 exp(-2 alpha / alpha_max(v)), alpha = 2 pi f,
// k(v) = 6.1 + 7.3 |log10(v / 3)|^3, alpha_max = 45.9 / (v + 2). Kelly 1979 Eq. 8 (travelling waves).
template <class T>
T kelly_csf(T f, T v, const ModelParams& p = {});
// Frequency of Kelly's peak sensitivity [cpd]: 45.9 / (2 pi (v + 2)).
template <class T>
T kelly_peak_frequency(T v, const ModelParams& p = {});

// ---- Daly 1998 ----------------------------------------------------------------------------------
// Smooth-pursuit eye velocity for an image velocity v_image [deg/s]: min(g v_image + v_min, v_max).
template <class T>
T daly_eye_velocity(T v_image, const ModelParams& p = {});
// Retinal velocity |v_image - v_eye| [deg/s], floored at p.drift (it is exactly 0 at 0.8333 deg/s).
template <class T>
T daly_retinal_velocity(T v_image, const ModelParams& p = {});
// The retinal slip [deg/s] every decision takes for an object, all three vectors tangent at its
// direction from the eye, in world axes. world: its image's angular velocity in the world (its
// velocity relative to the eye, across the direction, over the distance) [deg/s]; turn: the head's
// angular velocity x the direction [deg/s] (what a gaze fixed in the head sweeps past it);
// gaze_velocity: the gaze direction's angular velocity in the world [deg/s] where measured, else
// null. Measured: the slip is world - gaze_velocity. Else Daly's pursuit (daly_retinal_velocity) of the
// slower of the motions in the world (the eye holds the world still: the vestibulo-ocular reflex)
// and in the head (world - turn: a head that follows the object, or head-locked content); its
// direction is that motion's. docs/design.md section 3.
void object_retinal_slip(const float world[3], const float turn[3], const float* gaze_velocity,
                         const ModelParams& p, float slip[3]);
// Daly's spatio-velocity CSF at frequency f [cpd] and retinal velocity v [deg/s], fit p.fit:
// c0 c2 v (2 pi c1 f)^2 exp(-4 pi c1 f / rho_max) k(c2 v), rho_max = 45.9 / (c2 v + 2)
// (Laird2006: prefactor c0 c1 c2). v is floored at max(p.drift, 0.1 for Laird2006).
template <class T>
T daly_csf(T f, T v, const ModelParams& p = {});
// Frequency of the peak of daly_csf [cpd]: 45.9 / (2 pi c1 (c2 v + 2)).
template <class T>
T daly_peak_frequency(T v, const ModelParams& p = {});
// The constants of one fit, the one place they are written (the scheduler's fast path uses them too).
struct DalyFitConstants {
  double c0, c1, c2;
  double prefactor;  // c0 c2 (Daly 1998) or c0 c1 c2 (Laird 2006)
  double v_floor;    // the fit's own lowest velocity [deg/s]
};
DalyFitConstants daly_fit_constants(CsfFit fit);

// ---- Reddy 1997 / 2001 --------------------------------------------------------------------------
// Eccentricity factor M(e): 1 for e <= 5.79 deg, else 7.49 / (0.3 e + 1)^2. [checked]
template <class T>
T reddy_eccentricity(T e);
// Highest visible frequency for velocity v [cpd]: 60 for v <= 0.825; 57.69 - 27.78 log10(v) up to
// 118.3 deg/s; 0.1 above. [unverified: constants from recollection of Reddy's thesis]
template <class T>
T reddy_velocity(T v);
// Highest visible frequency H(v) M(e) [cpd]. [unverified combination]
template <class T>
T reddy_cutoff(T v, T e);

// ---- stelaCSF (Mantiuk, Ashraf, Chapiro, ACM TOG 41(4):145, 2022) -------------------------------
// Sensitivity S = 1 / threshold luminance contrast of a Gabor patch: spatial frequency rho [cpd],
// temporal frequency omega [Hz], adapting luminance [cd/m^2] (clamped to [0.001, 10000]), area
// [deg^2], eccentricity e [deg] and vis_field [deg] (0 temporal, 90 superior, 180 nasal, 270
// inferior; the drop interpolates linearly between the temporal and the nasal constants by
// min(1, |vis_field - 180| / 90), as the reference code does):
//   S = R_sust(omega) S_sust + R_trans(omega) S_trans, S_x = S_max(L) S_LP(rho) sqrt(A_c A / (A_c + A)) rho,
//   then S x 10^(-(d + rho d_f) e).
// Computed in the log domain (ln S may be -inf: S = 0). rho = 0 or +inf, area 0, omega or e = +inf
// give S = 0. Signs of rho, omega, e, luminance and area are ignored. Source: gfxdisp/stelaCSF
// matlab/CSF_stelaCSF.m sensitivity() at 052b15e; vision-models.md section 4.1.
template <class T>
T stela_csf(T rho, T omega, T luminance, T area, T e = T(0), T vis_field = T(0),
            const StelaConstants& c = {});

// stelaCSF's area term (Rovamo et al. 1993; both mechanisms share it): how much ln CT at rho [cpd]
// rises for a stimulus of area [deg^2] over one of unbounded area, 0.5 ln(1 + A_c(rho) / area) >= 0
// (0 at area +inf, +inf at area 0). ln CT(area) = ln CT(inf) + this, exactly; the scheduler adds it
// per band from a profile's Detail section (the lost detail's own extent). NaN in -> NaN out.
template <class T>
T stela_log_area_penalty(T rho, T area, const StelaConstants& c = {});

// How the scheduler's stela-csf pools a level's loss over the analyzer's channels on a profile with
// a Detail section (docs/design.md section 5): orientations within a band as energy, bands by
// probability summation with this Minkowski exponent (Robson & Graham 1981 and Watson 1979 report 3
// to 4; 3.5 is their usual middle). Chosen on Gabor patches at stelaCSF's threshold
// (scripts/calibration.py, docs/spectra.md "Calibration"): 2 puts the broad patches' scores at
// 0.82-1.35, 3.5 at 0.78-1.22, the largest channel alone at 0.69-1.22.
inline constexpr float kBandPooling = 3.5f;

// ---- Minimum angle of resolution (Guenter et al. 2012, Eq. 1) ------------------------------------
// MAR [deg per cycle] = slope e + omega0. Acuity frequency is 1 / MAR [cpd].
template <class T>
T mar(T e, T slope = T(0.022), T omega0 = T(1.0 / 48.0));

// ---- Combined threshold models ------------------------------------------------------------------
// Natural log of the threshold contrast at frequency f [cpd], eccentricity e [deg] and retinal
// velocity v_retinal [deg/s] (floored at p.drift). Saturates at ln(largest finite T).
// StelaCsf: -ln stela_csf(f, f (v - drift), p.luminance, p.area, e) with v floored at p.drift, at the
// most sensitive meridian (the smaller of the temporal and nasal drops at f: nasal below 48.2 cpd;
// with two eyes open a horizontal offset is temporal for one eye and nasal for the other; the
// vertical meridians take the temporal drop, so there this errs towards sensitivity). The drift is
// subtracted because stelaCSF's static data (omega = 0) were measured with the eyes' natural drift:
// a still object (v = drift) is stelaCSF's static stimulus, and one moving at v on the retina has
// omega = f (v - drift) (set drift = 0 for omega = f v exactly). The threshold rises with e at every
// f but is band-pass in f and in v: at low f it falls as speed rises (transient mechanism, peak near
// omega = 5 Hz), so the scheduler evaluates it exactly, never from its tables.
template <class T>
T log_threshold(T f, T e, T v_retinal, ThresholdModel model = ThresholdModel::Default,
                const ModelParams& p = {});
// Threshold contrast: exp(log_threshold), saturated at the largest finite T.
template <class T>
T threshold(T f, T e, T v_retinal, ThresholdModel model = ThresholdModel::Default, const ModelParams& p = {});
// The inverse: the highest frequency [cpd] whose threshold is at most `contrast`.
// Returns 0 when no frequency above 0 is visible at that contrast, +inf when contrast is +inf.
// Closed form for GeislerPerry, Reddy and the Default model's plateau; for KellyDaly and Default
// above the plateau a monotone Newton solve in log frequency, bracketed from above (the log
// threshold is convex there). StelaCsf (not convex: two mechanisms): from an upper bracket (64 cpd,
// doubled while visible) a downward scan in quarter-octave steps to the first visible frequency, then
// Illinois false position in ln f; frequencies below 2^-10 cpd are not searched (0 when none above
// is visible), and a visible band narrower than a quarter octave above the one found could be missed
// (Inverse.StelaScanMissesNothing finds none on its grid of c, e, v against a 1/64-octave scan).
// For the continuous models threshold(max_visible_frequency(c, e, v), e, v) == c to ~1e-12 relative.
template <class T>
T max_visible_frequency(T contrast, T e, T v_retinal, ThresholdModel model = ThresholdModel::Default,
                        const ModelParams& p = {});

// Batch form of threshold(): out[i] = threshold(f[i], e[i], v[i]) for i < count.
template <class T>
void threshold_batch(std::size_t count, const T* f, const T* e, const T* v_retinal, T* out,
                     ThresholdModel model = ThresholdModel::Default, const ModelParams& p = {});

// Names used by the command line and Python: "default", "geisler-perry", "kelly-daly", "reddy",
// "stela-csf"; "daly1998", "laird2006". Return false for an unknown name (the output is left
// unchanged). threshold_model_names() lists the model names for help texts: "default, geisler-perry,
// kelly-daly, reddy, stela-csf".
bool parse_threshold_model(const char* name, ThresholdModel* out);
bool parse_csf_fit(const char* name, CsfFit* out);
const char* to_string(ThresholdModel model);
const char* threshold_model_names();
const char* to_string(CsfFit fit);

}  // namespace acuity
