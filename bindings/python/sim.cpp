// acuity.sim: the simulation from Python, through the same calls as `acuity simulate` and `acuity
// explain` (acuity::bake::load_scene_assets, acuity::sim::simulate, summary_text, explain_frame,
// run_large_object, large_object_text).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>

#include "acuity/bake/scene.hpp"
#include "acuity/file.hpp"
#include "acuity/sim/large_object.hpp"
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
  bake::AssetOptions assets;
  sim::SimulationOptions options;
};

SceneRun load(const std::string& scene, const py::dict& kw) {
  SceneRun r;
  bake::AssetOptions& assets = r.assets;
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

// run_large_object's result as a dict, with the block `acuity simulate --large-object` prints.
py::dict large_object_dict(const sim::LargeObjectRun& run, const sim::LargeObjectOptions& o) {
  py::list spans;
  for (const sim::LargeObjectRun::Span& span : run.spans) {
    py::list judged;
    for (const sim::LargeObjectRun::Judged& j : span.judged)
      judged.append(py::dict("frame"_a = j.frame, "object_triangles"_a = j.object_triangles,
                             "cut_triangles"_a = j.cut_triangles, "object_score"_a = j.object_score,
                             "cut_score"_a = j.cut_score));
    spans.append(py::dict("deg"_a = span.deg, "object_rule"_a = span.object_rule, "cut"_a = span.cut,
                          "judged"_a = judged));
  }
  return py::dict("asset"_a = run.asset, "finest"_a = run.finest, "clusters"_a = run.clusters,
                  "groups"_a = run.groups, "bands"_a = run.bands, "frames"_a = run.frames, "spans"_a = spans,
                  "text"_a = sim::large_object_text(run, o));
}

}  // namespace

void bind_sim(py::module_ m) {
  m.def(
      "simulate",
      [](const std::string& scene, const py::kwargs& kw) {
        // large_object is simulate's own (as --large-object is the command's); the rest as explain's.
        py::dict rest(kw);
        sim::LargeObjectOptions large;
        large.asset.clear();  // none unless asked (the options' default is the demo's)
        if (rest.contains("large_object")) large.asset = rest.attr("pop")("large_object").cast<std::string>();
        if (!large.asset.empty() &&
            (!rest.contains("profiles") || rest["profiles"].cast<std::string>().empty()))
          throw py::value_error("large_object needs profiles (the folder where its profile is cached)");
        SceneRun r = load(scene, rest);
        if (!large.asset.empty()) {
          large.profiles = r.assets.profiles;
          large.pixels = r.assets.profile_pixels;
          sim::large_object_asset(*r.scene, large.asset, "large_object");  // before the run
        }
        sim::Run run;
        std::string summary;
        sim::LargeObjectRun large_run;
        {
          py::gil_scoped_release release;
          run = sim::simulate(*r.scene, r.options);
          summary = sim::summary_text(*run.simulation, run.results);
          if (!large.asset.empty()) large_run = sim::run_large_object(*run.simulation, large);
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
        py::dict out("summary"_a = summary, "frames"_a = res.frames, "objects"_a = res.objects,
                     "judged"_a = res.judged, "all_finest"_a = res.all_finest, "rules"_a = rules,
                     "written"_a = run.written, "simulate_seconds"_a = run.simulate_seconds,
                     "judge_seconds"_a = run.judge_seconds);
        if (!large.asset.empty()) out["large_object"] = large_object_dict(large_run, large);
        return out;
      },
      "scene"_a,
      "Run a glTF scene along a head path and gaze trace through the four LOD rules and their sweeps,\n"
      "as `acuity simulate` does (the same code). Options (keywords, the command's defaults): seconds,\n"
      "fps, seed, movers, viewport, fov, saccade_speed, evaluation ('tabulated'/'exact'), model (the\n"
      "perceptual rule's: 'default', 'stela-csf', ...), validate (decisions judged by\n"
      "render-and-analyze), images, output (folder for CSV/JSON/PNG), head and gaze (track files),\n"
      "profiles (folder of .acuity), res (snapshot px), asset_root; large_object (a mesh name of the\n"
      "scene, needs profiles): that asset also drawn large under the run's gaze as a cluster hierarchy,\n"
      "the object rule against the cluster cut, as --large-object does.\n"
      "Returns a dict: summary (the text acuity simulate prints), frames, objects, judged, all_finest\n"
      "(triangles per frame at level 0), rules (name, parameter, sweep, triangles_per_frame, switches,\n"
      "switches_outside_saccades, visible_losses when judged), written (paths), simulate_seconds,\n"
      "judge_seconds; with large_object, large_object: asset, finest, clusters, groups, bands, frames,\n"
      "spans (deg, object_rule and cut in triangles per frame, judged: frame, object_triangles,\n"
      "cut_triangles, object_score, cut_score) and text (the block the command prints). Raises\n"
      "acuity.lodgen.InputError or RuntimeError naming the file at fault, RuntimeError for a\n"
      "large_object the scene lacks.");
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
