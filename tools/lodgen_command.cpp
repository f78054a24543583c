// `acuity lodgen INPUT -o OUTPUT`: a measured chain of levels, written as glTF with MSFT_lod.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "acuity/bake/chains.hpp"
#include "acuity/bake/library.hpp"
#include "acuity/file.hpp"
#include "acuity/lodgen/output.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

struct LodgenOptions {
  std::string input, output;
  bake::BakeOptions chain;  // the chain options acuity bake takes too (its profile options unused)
  int refine = 0;
  bool quiet = false;
};

void progress(const char* stage, std::size_t done, std::size_t total) {
  std::fprintf(stderr, "\r%-10s %zu/%zu", stage, done, total);
  if (done == total) std::fputc('\n', stderr);
}

void run(const LodgenOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  lodgen::check_output(o.output, {o.input}, {".glb", ".gltf"});  // before any work
  lodgen::check_output(o.output + ".json", {o.input});
  const lodgen::ChainProgress report = o.quiet ? lodgen::ChainProgress{} : lodgen::ChainProgress(progress);

  bake::ChainRequest request;
  request.input = o.input;
  request.asset_root = o.chain.asset_root;
  try {
    request.chain = bake::chain_options(o.chain);
  } catch (const lodgen::InputError& e) { throw std::runtime_error(std::string("--") + e.what()); }
  request.refine = o.refine;
  request.measure_seconds = o.chain.measure_seconds;
  const bake::SceneChains sc = bake::build_scene_chains(request, report);
  const lodgen::Scene& scene = sc.scene;
  const std::vector<lodgen::Chain>& chains = sc.chains;
  for (const auto& c : chains)
    for (const std::string& w : c.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

  lodgen::GltfWriteOptions wo;
  wo.reference_height = o.chain.reference_height;
  wo.binary = !bake::is_gltf_text_path(o.output);
  lodgen::write_lod_gltf(o.output, sc.objects, scene.materials, wo);

  // Summary table, and the same as JSON beside the output.
  nlohmann::json summary;
  summary["input"] = o.input;
  summary["output"] = o.output;
  summary["backend"] = o.refine > 0 ? "opensubdiv" : o.chain.backend;
  std::printf("%-24s %5s %10s %10s %12s %9s %8s\n", "mesh", "level", "target", "triangles", "hausdorff",
              "normal99", "seconds");
  for (std::size_t m = 0; m < chains.size(); ++m) {
    nlohmann::json jm;
    jm["name"] = scene.mesh_names[m];
    jm["diameter"] = chains[m].diameter;
    for (std::size_t k = 0; k < chains[m].levels.size(); ++k) {
      const lodgen::Level& l = chains[m].levels[k];
      std::printf("%-24.24s %5zu %10zu %10zu %12.6f %9.2f %8.3f\n", scene.mesh_names[m].c_str(), k,
                  l.target_triangles, l.mesh.triangle_count(), l.hausdorff, l.normal_deviation, l.seconds);
      jm["levels"].push_back({{"target", l.target_triangles},
                              {"triangles", l.mesh.triangle_count()},
                              {"hausdorff_diameters", l.hausdorff},
                              {"normal_deviation_degrees", l.normal_deviation},
                              {"normal_deviation_max_degrees", l.normal_deviation_max},
                              {"measured_fully", l.measured_fully},
                              {"seconds", l.seconds}});
    }
    summary["meshes"].push_back(jm);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary["seconds"] = seconds;
  const std::string text = summary.dump(2) + "\n";
  std::string error;
  if (!write_file_atomically(o.output + ".json", text.data(), text.size(), &error))
    throw std::runtime_error(error);
  std::printf("wrote %s (%zu objects) and %s.json in %.2f s\n", o.output.c_str(), sc.objects.size(),
              o.output.c_str(), seconds);
}

}  // namespace

void add_lodgen_command(CLI::App& app) {
  auto o = std::make_shared<LodgenOptions>();
  CLI::App* cmd = app.add_subcommand(
      "lodgen", "Build a measured chain of levels of detail, written as glTF with MSFT_lod");
  cmd->add_option("input", o->input, "OFF, OBJ, PLY, STL, glTF or GLB")->required();
  cmd->add_option("-o,--output", o->output, "Output .glb (or .gltf)")->required();
  add_chain_options(cmd, o->chain);
  add_number(cmd, "--refine", o->refine, "OpenSubdiv refinements of a coarse cage (finer levels)", 0, 6);
  cmd->add_flag("-q,--quiet", o->quiet, "No progress");
  cmd->callback([o] { run(*o); });
}

}  // namespace acuity::tools
