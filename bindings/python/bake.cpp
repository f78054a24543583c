// acuity._acuity._bake: the bake library's three steps for acuity.bake (bake.py), which runs them
// locally or as Dask tasks. Jobs, plans and results cross as JSON text (picklable, the same bytes
// on every worker).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>

#include "acuity/bake/library.hpp"
#include "acuity/bake/sha256.hpp"
#include "acuity/lodgen/mesh.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {
namespace {

std::string plan_json(const bake::BakePlan& plan) {
  nlohmann::json jobs = nlohmann::json::array();
  for (const bake::AssetJob& j : plan.jobs) jobs.push_back(bake::job_json(j));
  return nlohmann::json{{"out", plan.out},
                        {"cache", plan.cache},
                        {"defaults", bake::options_json(plan.defaults)},
                        {"jobs", jobs}}
      .dump();
}

bake::BakePlan parse_plan(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text);
  bake::BakePlan plan;
  plan.out = j.at("out").get<std::string>();
  plan.cache = j.at("cache").get<std::string>();
  plan.defaults = bake::parse_options(j.at("defaults").get<std::string>(), bake::BakeOptions{}, "plan");
  for (const auto& job : j.at("jobs")) plan.jobs.push_back(bake::parse_job(job.get<std::string>()));
  return plan;
}

std::vector<bake::AssetResult> parse_results(const std::vector<std::string>& results) {
  std::vector<bake::AssetResult> out;
  for (const std::string& r : results) out.push_back(bake::parse_result(r));
  return out;
}

}  // namespace

void bind_bake(py::module_ m) {
  m.def(
      "plan",
      [](const std::string& input, const std::string& out, const std::string& cache,
         const std::string& options) {
        return plan_json(
            bake::plan_bake(input, out, cache, bake::parse_options(options, bake::BakeOptions{}, "options")));
      },
      "input"_a, "out"_a, "cache"_a = "", "options"_a = "{}",
      "acuity::bake::plan_bake: the jobs of a folder, manifest or file, as JSON text {out, cache, defaults, "
      "jobs}.\n"
      "Raises acuity.lodgen.InputError for a missing input, OUT inside an input folder, a bad manifest or "
      "option.");
  m.def(
      "bake_asset",
      [](const std::string& job, const std::string& cache, unsigned profile_jobs) {
        const bake::AssetJob j = bake::parse_job(job);
        py::gil_scoped_release release;
        return bake::result_json(bake::bake_asset(j, cache, profile_jobs));
      },
      "job"_a, "cache"_a, "profile_jobs"_a = 1,
      "acuity::bake::bake_asset: one job (JSON text from plan()) into the cache; returns the result as JSON "
      "text.\n"
      "Never raises for a bad asset: the error is in the result. What a Dask worker runs.");
  m.def(
      "bake_all",
      [](const std::string& plan, unsigned jobs) {
        const bake::BakePlan p = parse_plan(plan);
        std::vector<std::string> out;
        {
          py::gil_scoped_release release;
          for (const bake::AssetResult& r : bake::bake_all(p, jobs)) out.push_back(bake::result_json(r));
        }
        return out;
      },
      "plan"_a, "jobs"_a = 0,
      "bake_asset for every job on `jobs` threads (0: all cores); results in plan order.");
  m.def(
      "finish",
      [](const std::string& plan, const std::vector<std::string>& results) {
        const bake::BakePlan p = parse_plan(plan);
        const std::vector<bake::AssetResult> r = parse_results(results);
        py::gil_scoped_release release;
        return bake::finish_bake(p, r);
      },
      "plan"_a, "results"_a,
      "acuity::bake::finish_bake: outputs from the cache into OUT and OUT/index.json; returns the number of "
      "failed assets.");
  m.def("progress_text", &bake::progress_text, "done"_a, "total"_a, "current"_a, "seconds"_a,
        "The progress line acuity bake rewrites in place: bar, done/total, current asset, ETA.");
  m.def(
      "summary_table",
      [](const std::string& plan, const std::vector<std::string>& results, double seconds) {
        return bake::summary_table(parse_plan(plan), parse_results(results), seconds);
      },
      "plan"_a, "results"_a, "seconds"_a,
      "The summary table acuity bake prints (one row per asset, totals).");
  m.def(
      "sha256",
      [](py::bytes data) {
        const std::string s = data;
        return bake::sha256_hex(s.data(), s.size());
      },
      "data"_a, "SHA-256 of the bytes, 64 hex digits (the cache's hash).");
  m.attr("TOOL_VERSION") = bake::tool_version();
}

}  // namespace acuity::python
