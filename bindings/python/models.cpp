// acuity.models: every function of acuity/models.hpp and acuity/foveation.hpp, vectorised over
// numpy arrays (arguments broadcast; scalars in -> scalar out). Computed in float64.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "acuity/foveation.hpp"
#include "acuity/models.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {
namespace {

using Array = py::array_t<double, py::array::forcecast>;
using Params = std::optional<ModelParams>;

CsfFit fit_from(const std::string& name) {
  CsfFit f{};
  if (!parse_csf_fit(name.c_str(), &f))
    throw py::value_error("unknown fit '" + name + "': expected daly1998 or laird2006");
  return f;
}

// Vectorises a function of N doubles that also needs the parameters (captured, not broadcast).
template <class Fn>
auto vec(Fn fn) {
  return py::vectorize(fn);
}

}  // namespace

const char* threshold_model_doc() {
  static const std::string doc = std::string("threshold model name: ") + threshold_model_names();
  return doc.c_str();
}

ThresholdModel model_from(const std::string& name) {
  ThresholdModel m{};
  if (!parse_threshold_model(name.c_str(), &m))
    throw py::value_error("unknown model '" + name + "': expected one of " + threshold_model_names());
  return m;
}

void bind_models(py::module_ m) {
  py::enum_<CsfFit>(m, "CsfFit").value("daly1998", CsfFit::Daly1998).value("laird2006", CsfFit::Laird2006);

  py::class_<ModelParams>(m, "ModelParams", "Every constant of every model (defaults: the published values).")
      .def(py::init<>())
      .def_readwrite("ct0", &ModelParams::ct0, "Geisler-Perry minimum threshold contrast (1/64)")
      .def_readwrite("alpha", &ModelParams::alpha, "Geisler-Perry frequency decay (0.106)")
      .def_readwrite("e2", &ModelParams::e2, "Geisler-Perry half-resolution eccentricity [deg] (2.3)")
      .def_readwrite("pursuit_gain", &ModelParams::pursuit_gain, "Daly pursuit gain g (0.82)")
      .def_readwrite("pursuit_min", &ModelParams::pursuit_min, "Daly v_min [deg/s] (0.15)")
      .def_readwrite("pursuit_max", &ModelParams::pursuit_max, "Daly v_max [deg/s] (80)")
      .def_readwrite("drift", &ModelParams::drift, "retinal velocity floor [deg/s] (0.15)")
      .def_readwrite("fit", &ModelParams::fit, "CSF fit used by daly_csf and the Daly-based models")
      .def_readwrite("reddy_contrast", &ModelParams::reddy_contrast,
                     "threshold contrast inside the Reddy step model (1/64)")
      .def_readwrite("luminance", &ModelParams::luminance,
                     "stela-csf: adapting (display) luminance [cd/m^2] (100), clamped to 0.001..10000")
      .def_readwrite("area", &ModelParams::area,
                     "stela-csf: area of the lost detail [deg^2] (inf: the critical-area limit, the most "
                     "sensitive)");

  m.def(
      "geisler_perry_threshold",
      [](Array f, Array e, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        return vec([q](double f, double e) { return geisler_perry_threshold(f, e, q); })(f, e);
      },
      "f"_a, "e"_a, "params"_a = py::none(),
      "Geisler & Perry 1998 threshold contrast CT0 exp(alpha f (e + e2) / e2). f [cpd], e [deg].");

  m.def(
      "geisler_perry_cutoff",
      [](Array e, Array contrast, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        return vec([q](double e, double c) { return geisler_perry_cutoff(e, c, q); })(e, contrast);
      },
      "e"_a, "contrast"_a = 1.0, "params"_a = py::none(),
      "Highest visible frequency [cpd] at contrast c and eccentricity e [deg]: e2 ln(c/CT0) / (alpha (e + "
      "e2)).\n"
      "0 when nothing is visible (c <= CT0). f_c(0) = 39.2347 cpd.");

  m.def(
      "kelly_csf",
      [](Array f, Array v, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        return vec([q](double f, double v) { return kelly_csf(f, v, q); })(f, v);
      },
      "f"_a, "v"_a, "params"_a = py::none(),
      "Kelly 1979 spatio-velocity sensitivity, alpha = 2 pi f. f [cpd], v [deg/s] (floored at drift).");

  m.def(
      "kelly_peak_frequency",
      [](Array v, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        return vec([q](double v) { return kelly_peak_frequency(v, q); })(v);
      },
      "v"_a, "params"_a = py::none(), "Peak of Kelly's CSF [cpd]: 45.9 / (2 pi (v + 2)).");

  m.def(
      "daly_eye_velocity",
      [](Array v, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        return vec([q](double v) { return daly_eye_velocity(v, q); })(v);
      },
      "v_image"_a, "params"_a = py::none(), "Daly 1998 pursuit velocity min(g v + v_min, v_max) [deg/s].");

  m.def(
      "daly_retinal_velocity",
      [](Array v, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        return vec([q](double v) { return daly_retinal_velocity(v, q); })(v);
      },
      "v_image"_a, "params"_a = py::none(),
      "Retinal velocity |v_image - v_eye| [deg/s] (Daly 1998), floored at the 0.15 deg/s drift.");

  m.def(
      "daly_csf",
      [](Array f, Array v, const std::string& fit, Params p) {
        ModelParams q = p.value_or(ModelParams{});
        q.fit = fit_from(fit);
        return vec([q](double f, double v) { return daly_csf(f, v, q); })(f, v);
      },
      "f"_a, "v_retinal"_a, "fit"_a = "daly1998", "params"_a = py::none(),
      "Daly's spatio-velocity CSF (fit 'daly1998' or 'laird2006'). f [cpd], v_retinal [deg/s].");

  m.def(
      "daly_peak_frequency",
      [](Array v, const std::string& fit, Params p) {
        ModelParams q = p.value_or(ModelParams{});
        q.fit = fit_from(fit);
        return vec([q](double v) { return daly_peak_frequency(v, q); })(v);
      },
      "v_retinal"_a, "fit"_a = "daly1998", "params"_a = py::none(),
      "Peak of Daly's CSF [cpd]: 45.9 / (2 pi c1 (c2 v + 2)).");

  m.def(
      "reddy_eccentricity", [](Array e) { return vec([](double e) { return reddy_eccentricity(e); })(e); },
      "e"_a, "Reddy's eccentricity factor M(e): 1 up to 5.79 deg, then 7.49 / (0.3 e + 1)^2.");
  m.def(
      "reddy_velocity", [](Array v) { return vec([](double v) { return reddy_velocity(v); })(v); }, "v"_a,
      "Reddy's highest visible frequency H(v) [cpd]. [unverified constants]");
  m.def(
      "reddy_cutoff",
      [](Array v, Array e) { return vec([](double v, double e) { return reddy_cutoff(v, e); })(v, e); },
      "v"_a, "e"_a, "Reddy's highest visible frequency H(v) M(e) [cpd]. [unverified]");

  m.def(
      "mar",
      [](Array e, double slope, double omega0) {
        return vec([slope, omega0](double e) { return mar(e, slope, omega0); })(e);
      },
      "e"_a, "slope"_a = 0.022, "omega0"_a = 1.0 / 48.0,
      "Minimum angle of resolution [deg per cycle] = slope e + omega0 (Guenter et al. 2012, Eq. 1).");

  m.def(
      "stela_csf",
      [](Array rho, Array omega, Array luminance, Array area, Array e, Array vis_field) {
        return vec([](double rho, double omega, double luminance, double area, double e, double vis_field) {
          return stela_csf(rho, omega, luminance, area, e, vis_field);
        })(rho, omega, luminance, area, e, vis_field);
      },
      "rho"_a, "omega"_a, "luminance"_a, "area"_a, "e"_a = 0.0, "vis_field"_a = 0.0,
      "stelaCSF sensitivity (1 / threshold contrast; Mantiuk, Ashraf, Chapiro 2022) at spatial frequency\n"
      "rho [cpd], temporal frequency omega [Hz], luminance [cd/m^2] (clamped to 0.001..10000), area\n"
      "[deg^2], eccentricity e [deg] and vis_field [deg] (0 temporal, 90 superior, 180 nasal, 270 "
      "inferior).");

  m.def(
      "log_threshold",
      [](Array f, Array e, Array v, const std::string& model, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        const ThresholdModel mdl = model_from(model);
        return vec([q, mdl](double f, double e, double v) { return log_threshold(f, e, v, mdl, q); })(f, e,
                                                                                                      v);
      },
      "f"_a, "e"_a, "v_retinal"_a, "model"_a = "default", "params"_a = py::none(),
      "Natural log of threshold(); finite for finite input.");

  m.def(
      "threshold",
      [](Array f, Array e, Array v, const std::string& model, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        const ThresholdModel mdl = model_from(model);
        return vec([q, mdl](double f, double e, double v) { return threshold(f, e, v, mdl, q); })(f, e, v);
      },
      "f"_a, "e"_a, "v_retinal"_a, "model"_a = "default", "params"_a = py::none(),
      "Threshold contrast at f [cpd], eccentricity e [deg], retinal velocity [deg/s].\n"
      "model: 'default' (Daly CSF held at its peak below the peak frequency x exp(alpha f e / e2)),\n"
      "'geisler-perry', 'kelly-daly' (exact band-pass), 'reddy' (step, unverified) or 'stela-csf'\n"
      "(stelaCSF, Mantiuk et al. 2022, at params.luminance and params.area; band-pass in f and v).\n"
      "Saturates at the largest float64 instead of overflowing; NaN in -> NaN out.");

  m.def(
      "max_visible_frequency",
      [](Array c, Array e, Array v, const std::string& model, Params p) {
        const ModelParams q = p.value_or(ModelParams{});
        const ThresholdModel mdl = model_from(model);
        return vec([q, mdl](double c, double e, double v) { return max_visible_frequency(c, e, v, mdl, q); })(
            c, e, v);
      },
      "contrast"_a, "e"_a, "v_retinal"_a, "model"_a = "default", "params"_a = py::none(),
      "Highest frequency [cpd] whose threshold is at most `contrast`; 0 when none is visible.");

  m.def(
      "guenter_layers",
      [](double width, double distance, double pixels, double aspect, double slope, int n_layers,
         double omega0, int grid) {
        const GuenterLayers g =
            guenter_layers(width, distance, pixels, aspect, slope, n_layers, omega0, grid);
        if (g.n_layers == 0) throw py::value_error("guenter_layers: invalid display or layer count");
        py::list radius, sampling, diameter, pixels_per_layer;
        for (int i = 0; i < g.n_layers; ++i) {
          radius.append(g.radius[i]);
          sampling.append(g.sampling[i]);
          diameter.append(g.diameter_px[i]);
          pixels_per_layer.append(g.pixels[i]);
        }
        return py::dict("e_star"_a = g.e_star, "omega_star"_a = g.omega_star, "radius"_a = radius,
                        "sampling"_a = sampling, "diameter_px"_a = diameter, "pixels"_a = pixels_per_layer,
                        "work"_a = g.work, "display_work"_a = g.display_work, "speedup"_a = g.speedup);
      },
      "width_cm"_a, "distance_cm"_a, "pixels"_a, "aspect"_a, "slope"_a = 0.022, "n_layers"_a = 3,
      "omega0"_a = 1.0 / 48.0, "grid"_a = 2000,
      "Guenter et al. 2012 eccentricity layers (Sec. 4.3): radii [deg], sampling factors, pixels per\n"
      "layer and predicted speedup P*/P, minimised exactly over a grid of radii.");
}

}  // namespace acuity::python
