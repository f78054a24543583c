// `acuity lodgen INPUT -o OUTPUT`: a measured chain of levels, written as glTF with MSFT_lod; with
// --clusters, level 0 and its cluster hierarchy (ACUITY_cluster_hierarchy) instead.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "acuity/bake/chains.hpp"
#include "acuity/bake/library.hpp"
#include "acuity/file.hpp"
#include "acuity/lodgen/formats.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

struct LodgenOptions {
  std::string input, output;
  bake::BakeOptions chain;  // the chain options acuity bake takes too (its profile options unused)
  int refine = 0;
  bool clusters = false;
  bool quiet = false;
};

void progress(const char* stage, std::size_t done, std::size_t total) {
  std::fprintf(stderr, "\r%-10s %zu/%zu", stage, done, total);
  if (done == total) std::fputc('\n', stderr);
}

void run(const LodgenOptions& o) {
  io::check_output(o.output + ".json", {o.input});  // before any work
  bake::ChainRequest request;
  try {
    request = bake::chain_request(o.input, o.chain);
  } catch (const lodgen::InputError& e) { throw std::runtime_error(std::string("--") + e.what()); }
  request.refine = o.refine;
  request.clusters = o.clusters;
  const bake::WrittenChains w = bake::write_scene_chains(
      request, o.output, o.chain.reference_height, o.refine > 0 ? "opensubdiv" : o.chain.backend,
      o.quiet ? lodgen::ChainProgress{} : lodgen::ChainProgress(progress));
  for (const auto& c : w.chains.chains)
    for (const std::string& warning : c.warnings) std::fprintf(stderr, "warning: %s\n", warning.c_str());
  std::fputs(bake::chains_table(w.chains).c_str(), stdout);
  io::write_file_atomically(o.output + ".json", w.json);
  std::printf("wrote %s (%zu objects) and %s.json in %.2f s\n", o.output.c_str(), w.chains.objects.size(),
              o.output.c_str(), w.seconds);
}

}  // namespace

void add_lodgen_command(CLI::App& app) {
  auto o = std::make_shared<LodgenOptions>();
  CLI::App* cmd = app.add_subcommand(
      "lodgen", "Build a measured chain of levels of detail, written as glTF with MSFT_lod");
  cmd->add_option("input", o->input, lodgen::input_format_names())->required();
  cmd->add_option("-o,--output", o->output, "Output .glb (or .gltf)")->required();
  add_chain_options(cmd, o->chain);
  add_number(cmd, "--refine", o->refine, "OpenSubdiv refinements of a coarse cage (finer levels)", 0, 6);
  cmd->add_flag(
         "--clusters", o->clusters,
         "Instead of a chain: the finest level and its cluster hierarchy (clusters of <= 128 triangles, "
         "simplified groups up to a root; ACUITY_cluster_hierarchy, docs/lodgen.md)")
      ->excludes("--refine");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress");
  cmd->callback([o] { run(*o); });
}

}  // namespace acuity::tools
