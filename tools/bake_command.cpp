// `acuity bake INPUT -o OUT`: every asset of a folder or manifest to its LOD chain (.glb) and
// profile (.acuity), through a content-addressed cache, on all cores; OUT/index.json lists them.
// `--dask ADDRESS` hands the same job to `python3 -m acuity.bake` (acuity/bake.py), which runs each
// asset as a task on a dask.distributed cluster.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "acuity/bake/library.hpp"
#include "acuity/lodgen/formats.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

struct BakeCommandOptions {
  std::string input, output, cache, dask;
  bake::BakeOptions bake;
  unsigned jobs = 0;
  bool quiet = false;
};

void progress_line(std::size_t done, std::size_t total, const std::string& current, double seconds) {
  std::fprintf(stderr, "\r%s", bake::progress_text(done, total, current, seconds).c_str());
  if (done == total) std::fputc('\n', stderr);
}

// Replaces this process with `python3 -m acuity.bake ... --dask ADDRESS` (no shell).
[[noreturn]] void run_dask(const BakeCommandOptions& o) {
  const std::string path = std::string(ACUITY_PYTHON_DIR) +
                           (std::getenv("PYTHONPATH") ? std::string(":") + std::getenv("PYTHONPATH") : "");
  ::setenv("PYTHONPATH", path.c_str(), 1);
  std::vector<std::string> args = {
      "python3", "-m",     "acuity.bake", o.input,     "-o",
      o.output,  "--dask", o.dask,        "--options", bake::options_json(o.bake)};
  if (!o.cache.empty()) args.insert(args.end(), {"--cache", o.cache});
  if (o.quiet) args.push_back("--quiet");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  ::execv(ACUITY_PYTHON3, argv.data());
  throw std::runtime_error(std::string("--dask: cannot run ") + ACUITY_PYTHON3 + " -m acuity.bake");
}

void run(const BakeCommandOptions& o) {
  if (!o.dask.empty()) run_dask(o);
  const auto start = std::chrono::steady_clock::now();
  const bake::BakePlan plan = bake::plan_bake(o.input, o.output, o.cache, o.bake);
  if (!o.quiet)
    std::fprintf(stderr, "baking %zu assets into %s (cache %s)\n", plan.jobs.size(), plan.out.c_str(),
                 plan.cache.c_str());
  const std::vector<bake::AssetResult> results =
      bake::bake_all(plan, o.jobs, o.quiet ? bake::BakeProgress{} : progress_line);
  const std::size_t failed = bake::finish_bake(plan, results);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fputs(bake::summary_table(plan, results, seconds).c_str(), stdout);
  if (failed)
    throw std::runtime_error(std::to_string(failed) + " of " + std::to_string(results.size()) +
                             " assets failed (see " + plan.out + "/index.json)");
}

}  // namespace

void add_bake_command(CLI::App& app) {
  auto o = std::make_shared<BakeCommandOptions>();
  bake::BakeOptions& b = o->bake;
  CLI::App* cmd = app.add_subcommand(
      "bake", "Bake a folder or manifest of assets: LOD chains, profiles and an index, cached");
  cmd->add_option(
         "input", o->input,
         "A folder (walked for " + lodgen::input_format_names() + "), a manifest (.json) or one asset")
      ->required();
  cmd->add_option("-o,--output", o->output, "Output folder (index.json, <asset>.glb, <asset>.acuity)")
      ->required();
  cmd->add_option("--cache", o->cache, "Cache folder, shareable between machines (default OUTPUT/.cache)");
  cmd->add_option("-j,--jobs", o->jobs, "Threads (0: all cores)")->capture_default_str();
  cmd->add_option("--dask", o->dask,
                  "Run each asset as a task on this dask.distributed scheduler (tcp://host:8786) through "
                  "python3 -m acuity.bake");
  add_chain_options(cmd, b);
  add_profile_options(cmd, b);
  add_number(cmd, "--views", b.views, "Views (0: adaptive)", 0, 4096);
  cmd->add_flag("--clusters", b.clusters,
                "Cluster hierarchies instead of chains (acuity lodgen --clusters), profiled with what each "
                "group loses");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress bar");
  cmd->callback([o] {
    o->bake = bake::parse_options(bake::options_json(o->bake), bake::BakeOptions{},
                                  "options");  // the library's checks
    run(*o);
  });
}

}  // namespace acuity::tools
