// acuity.sim: the simulation from Python, through the same calls as `acuity simulate` and `acuity
// explain` (acuity::bake::load_scene_assets, acuity::sim::simulate, summary_text, explain_frame).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>

#include "acuity/bake/scene.hpp"
#include "acuity/file.hpp"
#include "acuity/sim/run.hpp"
#include "acuity/sim/tracks.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {
namespace {

// The options simulate and explain share, checked as the command line checks them.
struct SceneRun {
  std::unique_ptr<bake::SceneAssets> scene;
  sim::SimulationOptions options;
};

SceneRun load(const std::string& scene, const py::kwargs& kw) {
  SceneRun r;
  bake::AssetOptions assets;
  assets.quiet = true;
  sim::SimulationOptions& o = r.options;
  for (const auto& [key, value] : kw) {
    const std::string k = py::str(key);
    if (k == "asset_root")
      assets.asset_root = value.cast<std::string>();
    else if (k == "profiles")
      assets.profiles = value.cast<std::string>();
    else if (k == "res")
      assets.profile_pixels = value.cast<std::uint32_t>();
    else if (k == "head")
      o.head_file = value.cast<std::string>();
    else if (k == "gaze")
      o.gaze_file = value.cast<std::string>();
    else if (k == "seconds")
      o.seconds = value.cast<double>();
    else if (k == "fps")
      o.fps = value.cast<double>();
    else if (k == "seed")
      o.seed = value.cast<unsigned>();
    else if (k == "movers")
      o.movers = value.cast<std::uint32_t>();
    else if (k == "viewport")
      o.viewport = value.cast<std::uint32_t>();
    else if (k == "fov")
      o.fov_deg = value.cast<float>();
    else if (k == "saccade_speed")
      o.saccade_speed = value.cast<float>();
    else if (k == "validate")
      o.validate = value.cast<std::uint32_t>();
    else if (k == "images")
      o.images = value.cast<std::uint32_t>();
    else if (k == "output")
      o.output = value.cast<std::string>();
    else if (k == "evaluation") {
      if (!parse_evaluation(value.cast<std::string>().c_str(), &o.evaluation))
        throw py::value_error("evaluation: 'tabulated' or 'exact'");
    } else if (k == "model") {
      if (!parse_threshold_model(value.cast<std::string>().c_str(), &o.model))
        throw py::value_error(std::string("model: ") + threshold_model_names());
    } else
      throw py::type_error("unknown option '" + k + "'");
  }
  sim::check_options(o);
  py::gil_scoped_release release;
  io::check_output_folder(o.output);  // before any work
  io::check_output_folder(assets.profiles);
  r.scene = bake::load_scene_assets(scene, assets);
  return r;
}

}  // namespace

void bind_sim(py::module_ m) {
  m.def(
      "simulate",
      [](const std::string& scene, const py::kwargs& kw) {
        SceneRun r = load(scene, kw);
        sim::Run run;
        std::string summary;
        {
          py::gil_scoped_release release;
          run = sim::simulate(*r.scene, r.options);
          summary = sim::summary_text(*run.simulation, run.results);
        }
        const sim::Simulation& s = *run.simulation;
        const sim::Results& res = run.results;
        py::list rules;
        for (std::size_t i = 0; i < s.rules().size(); ++i) {
          const sim::RuleRun& rule = s.rules()[i];
          py::dict d("name"_a = rule.name, "parameter"_a = rule.parameter, "sweep"_a = rule.sweep,
                     "triangles_per_frame"_a = res.frames ? rule.triangles / double(res.frames) : 0.0,
                     "switches"_a = rule.switches,
                     "switches_outside_saccades"_a = rule.switches_outside_saccades);
          if (res.judged) d["visible_losses"] = res.visible_losses[i];
          rules.append(d);
        }
        return py::dict("summary"_a = summary, "frames"_a = res.frames, "objects"_a = res.objects,
                        "judged"_a = res.judged, "all_finest"_a = res.all_finest, "rules"_a = rules,
                        "written"_a = run.written, "simulate_seconds"_a = run.simulate_seconds,
                        "judge_seconds"_a = run.judge_seconds);
      },
      "scene"_a,
      "Run a glTF scene along a head path and gaze trace through the four LOD rules and their sweeps,\n"
      "as `acuity simulate` does (the same code). Options (keywords, the command's defaults): seconds,\n"
      "fps, seed, movers, viewport, fov, saccade_speed, evaluation ('tabulated'/'exact'), model (the\n"
      "perceptual rule's: 'default', 'stela-csf', ...), validate (decisions judged by\n"
      "render-and-analyze), images, output (folder for CSV/JSON/PNG), head and gaze (track files),\n"
      "profiles (folder of .acuity), res (snapshot px), asset_root.\n"
      "Returns a dict: summary (the text acuity simulate prints), frames, objects, judged, all_finest\n"
      "(triangles per frame at level 0), rules (name, parameter, sweep, triangles_per_frame, switches,\n"
      "switches_outside_saccades, visible_losses when judged), written (paths), simulate_seconds,\n"
      "judge_seconds. Raises acuity.lodgen.InputError or RuntimeError naming the file at fault.");
  m.def(
      "explain",
      [](const std::string& scene, std::size_t frame, const std::string& object, const py::kwargs& kw) {
        SceneRun r = load(scene, kw);
        py::gil_scoped_release release;
        return sim::explain_frame(*r.scene, r.options, frame, object);
      },
      "scene"_a, "frame"_a, "object"_a,
      "Why `object` (node name or instance index) got its level in `frame`: the text `acuity explain`\n"
      "prints. Options as simulate().");
  m.def(
      "read_table",
      [](const std::string& path) {
        const sim::Table t = sim::read_table(path);
        return py::dict("source"_a = t.source, "columns"_a = t.columns, "rows"_a = t.rows);
      },
      "path"_a,
      "A head path or gaze trace (CSV with a header line, or JSON: an array of flat objects) as\n"
      "{source, columns, rows}. Raises RuntimeError naming the file and the line or row at fault.");
}

}  // namespace acuity::python
