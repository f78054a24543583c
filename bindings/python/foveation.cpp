// acuity.foveation: the foveation planner (acuity/foveation_plan.hpp) — per-tile shading-rate and
// mip-bias maps as numpy arrays, and the Guenter layers from the same model.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <variant>

#include "acuity/foveation_plan.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {
namespace {

struct Plan {
  py::array_t<std::uint8_t> shading_rate;  // rows x cols x 2
  py::array_t<float> mip_bias;             // rows x cols
  std::string status;
  std::uint32_t tile_px = 0;
  float origin_x = 0, origin_y = 0, retinal_speed = 0;
  double shaded = 0, pixels = 0;
  py::dict layers;
};

struct Planner {
  std::unique_ptr<FoveationPlanner> planner = std::make_unique<FoveationPlanner>();
  explicit Planner(const FoveationConfig& c) {
    if (init_foveation_planner(c, planner.get()) != FoveationStatus::Ok)
      throw py::value_error(
          "invalid foveation config: quality > 0, radii finite and >= 0, max_rate 1, 2 or 4");
  }
  Plan plan(const Eye& eye, const Gaze& gaze, std::uint32_t tile_px, int n_layers) const {
    std::uint32_t cols = 0, rows = 0;
    if (!foveation_map_size(eye, tile_px, &cols, &rows))
      throw py::value_error(
          "tile_px must be 8, 16 or 32 and the viewport non-empty (at most 2048 tiles per axis)");
    Plan p;
    p.shading_rate = py::array_t<std::uint8_t>({py::ssize_t(rows), py::ssize_t(cols), py::ssize_t(2)});
    p.mip_bias = py::array_t<float>({py::ssize_t(rows), py::ssize_t(cols)});
    FoveationMaps maps;
    maps.tile_px = tile_px;
    maps.capacity = cols * rows;
    maps.shading_rate = p.shading_rate.mutable_data();
    maps.mip_bias = p.mip_bias.mutable_data();
    p.status = to_string(plan_foveation(*planner, eye, gaze, &maps));
    p.tile_px = tile_px;
    p.origin_x = maps.origin_px[0];
    p.origin_y = maps.origin_px[1];
    p.retinal_speed = maps.retinal_speed;
    p.shaded = maps.shaded;
    p.pixels = maps.pixels;
    if (n_layers > 0) {
      const FoveationLayers l = foveation_layers(*planner, eye, n_layers);
      py::list radius, sampling, pixels;
      for (int i = 0; i < l.layers.n_layers; ++i) {
        radius.append(l.layers.radius[i]);
        sampling.append(l.layers.sampling[i]);
        pixels.append(l.layers.pixels[i]);
      }
      p.layers = py::dict("n_layers"_a = l.layers.n_layers, "radius_deg"_a = radius, "sampling"_a = sampling,
                          "pixels"_a = pixels, "speedup"_a = l.layers.speedup, "omega0"_a = l.omega0,
                          "slope"_a = l.slope);
    }
    return p;
  }
};

FoveationConfig config_of(const py::object& config) {
  if (config.is_none()) return FoveationConfig{};
  if (py::isinstance<FoveationConfig>(config)) return config.cast<FoveationConfig>();
  if (py::isinstance<SchedulerConfig>(config)) return foveation_config(config.cast<SchedulerConfig>());
  throw py::type_error("config must be None, acuity.foveation.FoveationConfig or acuity.SchedulerConfig");
}

}  // namespace

void bind_foveation(py::module_ m) {
  py::class_<FoveationConfig>(m, "FoveationConfig",
                              "Foveation planner settings (see acuity/foveation_plan.hpp).")
      .def(py::init<>())
      .def_property(
          "model", [](const FoveationConfig& c) { return std::string(to_string(c.model)); },
          [](FoveationConfig& c, const std::string& name) {
            if (!parse_threshold_model(name.c_str(), &c.model))
              throw py::value_error("unknown model '" + name + "'");
          },
          threshold_model_doc())
      .def_readwrite("params", &FoveationConfig::params)
      .def_readwrite("quality", &FoveationConfig::quality,
                     "q: a lost component is invisible at contrast <= q CT")
      .def_readwrite("min_gaze_confidence", &FoveationConfig::min_gaze_confidence)
      .def_readwrite("gaze_uncertainty_deg", &FoveationConfig::gaze_uncertainty_deg)
      .def_readwrite("no_gaze_radius_deg", &FoveationConfig::no_gaze_radius_deg)
      .def_readwrite("foveal_radius_deg", &FoveationConfig::foveal_radius_deg)
      .def_readwrite("max_rate", &FoveationConfig::max_rate, "coarsest pixels per shade: 1, 2 or 4")
      .def_readwrite("head_rotation", &FoveationConfig::head_rotation);
  m.def(
      "config_from", [](const SchedulerConfig& c) { return foveation_config(c); }, "scheduler_config"_a,
      "The scheduler's model, q and gaze handling as a FoveationConfig.");

  py::class_<Plan>(m, "Plan", "One eye's maps for one frame.")
      .def_readonly("shading_rate", &Plan::shading_rate,
                    "rows x cols x 2 uint8: pixels per shade in x, y (1, 2, 4); row 0 at the top")
      .def_readonly("mip_bias", &Plan::mip_bias, "rows x cols float32: texture LOD bias >= 0 [octaves]")
      .def_readonly("status", &Plan::status, "ok, no-gaze, invalid-eye or invalid-argument")
      .def_readonly("tile_px", &Plan::tile_px)
      .def_property_readonly(
          "origin_px", [](const Plan& p) { return py::make_tuple(p.origin_x, p.origin_y); },
          "the gaze (or view centre) in pixels, x right, y down")
      .def_readonly("retinal_speed", &Plan::retinal_speed, "the speed the cutoff was taken at [deg/s]")
      .def_readonly("shaded", &Plan::shaded, "shading work: pixels over their rates, summed")
      .def_readonly("pixels", &Plan::pixels, "full-rate work: width x height")
      .def_property_readonly(
          "saved", [](const Plan& p) { return 1.0 - p.shaded / p.pixels; },
          "fraction of the shading work saved against full rate")
      .def_readonly("layers", &Plan::layers,
                    "Guenter layers: n_layers, radius_deg, sampling, pixels, speedup, omega0, slope");

  py::class_<Planner>(m, "Planner",
                      "Tables for one configuration (built once, ~ms); plan() per eye and frame.")
      .def(py::init([](const py::object& config) { return std::make_unique<Planner>(config_of(config)); }),
           "config"_a = py::none())
      .def("plan", &Planner::plan, "eye"_a, "gaze"_a, "tile_px"_a = 16, "layers"_a = 3);

  m.def(
      "plan",
      [](const Eye& eye, const Gaze& gaze, std::uint32_t tile_px, const py::object& config, int layers) {
        return Planner(config_of(config)).plan(eye, gaze, tile_px, layers);
      },
      "eye"_a, "gaze"_a, "tile_px"_a = 16, "config"_a = py::none(), "layers"_a = 3,
      "Shading-rate and mip-bias maps for one eye and its gaze, plus n Guenter layers (0: none).\n"
      "config: None, a FoveationConfig or a SchedulerConfig (its model, q and gaze handling).");
}

}  // namespace acuity::python
