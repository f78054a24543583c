// `acuity profile LEVEL0 LEVEL1 ... -o OUT.acuity`: snapshots, lost-contrast spectra, profile.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "acuity/bake/chains.hpp"
#include "acuity/bake/library.hpp"
#include "acuity/bake/scene.hpp"
#include "acuity/file.hpp"
#include "acuity/lodgen/formats.hpp"
#include "acuity/lodgen/mesh.hpp"
#include "acuity/spectra/profile_builder.hpp"
#include "acuity/spectra/snapshots.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

struct ProfileOptions {
  std::vector<std::string> levels;
  std::string snapshots;
  std::string output, asset_root;
  std::string views = "auto";
  bake::BakeOptions profile;  // the profile options acuity bake takes too (views from `views`)
  unsigned jobs = 0;
};

void progress_bar(const char* stage, std::size_t done, std::size_t total) {
  const int width = 30, filled = total ? int(width * done / total) : width;
  std::fprintf(stderr, "\r%-6s [%.*s%*s] %zu/%zu", stage, filled, "##############################",
               width - filled, "", done, total);
  if (done == total) std::fputc('\n', stderr);
}

void run_snapshots(const ProfileOptions& o) {
  io::check_output(o.output, {o.snapshots});
  spectra::AnalysisSettings a;
  a.orientations = o.profile.orientations;
  a.bands = o.profile.bands;
  const spectra::ProfileData data = spectra::profile_from_snapshots(o.snapshots, a);
  spectra::write_profile(o.output, data);
  std::printf("profile   %s from %zu views x %zu levels of user snapshots (%u px)\n", o.output.c_str(),
              data.views.size(), data.levels.size(), data.snapshot_pixels);
}

// The views option as ProfileSettings::views (0: adaptive).
std::uint32_t views_option(const std::string& views) {
  if (views == "auto") return 0;
  std::uint32_t n = 0;
  try {
    n = static_cast<std::uint32_t>(std::stoul(views));
  } catch (...) { n = 0; }
  if (n == 0) throw std::runtime_error("--views: 'auto' or a positive count, not '" + views + "'");
  return n;
}

// A cluster file: its finest mesh as a one-level profile and what each group loses.
void run_clusters(const ProfileOptions& o, const bake::ClusterFile& file, double load_seconds) {
  bake::BakeOptions b = o.profile;
  b.views = views_option(o.views);
  const spectra::ProfileSettings s = bake::profile_settings(b, o.jobs);
  spectra::ProfileReport report;
  spectra::ClusterLossReport clusters;
  const spectra::ProfileData data =
      bake::profile_clusters(file.view(), file.material, s, bake::cluster_loss_settings(b, o.jobs),
                             progress_bar, &report, &clusters);
  spectra::write_profile(o.output, data);
  const Blob blob = spectra::encode_profile(data);
  const spectra::ProfileClusterData& c = data.clusters;
  const std::size_t section = sizeof(ProfileClusterMeta) + sizeof(float) * (c.bands.size() + c.lost.size());
  const std::size_t cells =
      c.view_lost.empty()
          ? 0
          : sizeof(ProfileClusterViewsMeta) + sizeof(float) * (c.view_directions.size() + c.view_lost.size());
  std::printf("profile   %s\n", o.output.c_str());
  std::printf("level 0   %u triangles, %u views kept\n", data.levels[0].triangles, report.views_kept);
  std::printf(
      "groups    %u x %u views (%u windows hidden), %u px windows, %zu bands (%.3g .. %.3g cycles per "
      "diameter)\n",
      clusters.groups, clusters.views, clusters.hidden, b.window_pixels, data.clusters.bands.size(),
      data.clusters.bands.front(), data.clusters.bands.back());
  std::printf(
      "size      %zu bytes (Clusters section %zu: %.1f bytes per group; ClusterViews %zu, %zu cells: %.1f "
      "bytes "
      "per group)\n",
      blob.size, section, double(section) / clusters.groups, cells, c.view_directions.size() / 3,
      double(cells) / clusters.groups);
  std::printf("time      load %.2f s, level 0 %.2f s, groups %.2f s\n", load_seconds, report.seconds,
              clusters.seconds);
}

void run(const ProfileOptions& o) {
  if (!o.snapshots.empty()) return run_snapshots(o);
  if (o.levels.empty())
    throw std::runtime_error("profile: give the levels (mesh files or a glTF), or --snapshots MANIFEST");
  if (o.levels.size() > kMaxLevels)
    throw std::runtime_error("profile: " + std::to_string(o.levels.size()) + " level files, more than " +
                             std::to_string(kMaxLevels));
  io::check_output(o.output, o.levels);  // before any work
  const auto start = std::chrono::steady_clock::now();
  bake::ChainFile file;  // lodgen's output: the first node with MSFT_lod holds the chain
  if (o.levels.size() == 1 && lodgen::is_gltf(o.levels[0])) {
    bake::ClusterFile clusters = bake::read_cluster_file(o.levels[0], o.asset_root);
    if (clusters.found())
      return run_clusters(o, clusters,
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    file = bake::chain_file(std::move(clusters.scene), o.levels[0]);
  } else {  // mesh files, finest first, without errors
    for (const std::string& path : o.levels) {
      lodgen::Mesh mesh = lodgen::load_mesh_isolated(path);  // untrusted files
      const std::size_t triangles = mesh.triangle_count();
      file.chain.levels.push_back({std::move(mesh), triangles, 0.0, 0.0});
    }
  }
  const std::vector<spectra::LevelInput> levels = bake::spectra_levels(file.chain);
  bake::BakeOptions b = o.profile;
  b.views = views_option(o.views);
  const spectra::ProfileSettings s = bake::profile_settings(b, o.jobs);
  const double load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  spectra::ProfileReport report;
  const spectra::ProfileData data = spectra::build_profile(levels, file.material, s, progress_bar, &report);
  spectra::write_profile(o.output, data);
  const Blob blob = spectra::encode_profile(data);
  std::printf("profile   %s\n", o.output.c_str());
  std::printf("levels    %zu (triangles", levels.size());
  for (const auto& l : data.levels) std::printf(" %u", l.triangles);
  std::printf(")\nviews     %u kept of %u measured (%s); worst switching-distance error %.1f%%\n",
              report.views_kept, report.views_measured, s.views ? "fixed" : "adaptive",
              100.0 * report.prediction_error);
  std::printf("spectra   %zu orientations x %zu bands (%.3g .. %.3g cycles per diameter), %u px snapshots\n",
              data.orientations.size(), data.bands.size(), data.bands.front(), data.bands.back(), b.pixels);
  std::printf("size      %zu bytes\n", blob.size);
  std::printf("time      load %.2f s, profile %.2f s\n", load_seconds, report.seconds);
}

}  // namespace

void add_profile_command(CLI::App& app) {
  auto o = std::make_shared<ProfileOptions>();
  CLI::App* cmd =
      app.add_subcommand("profile", "Measure what each level loses and write a profile (.acuity)");
  cmd->add_option(
         "levels", o->levels,
         "A glTF/GLB from acuity lodgen (MSFT_lod; with --clusters, its hierarchy's groups are measured "
         "too), or mesh files finest first (" +
             lodgen::input_format_names() + ")")
      ->check(CLI::ExistingFile);
  cmd->add_option("--snapshots", o->snapshots,
                  "A JSON manifest of your own snapshots (PNG per view and level) instead of meshes")
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", o->output, "Output profile")->required();
  cmd->add_option("--asset-root", o->asset_root,
                  "Folder a glTF's uris may read from (default: the glTF's own folder)");
  cmd->add_option("--views", o->views, "'auto' (adaptive) or a number of views")->capture_default_str();
  add_profile_options(cmd, o->profile);
  cmd->add_option("--jobs", o->jobs, "Worker threads (0: all cores)")->capture_default_str();
  cmd->callback([o] { run(*o); });
}

}  // namespace acuity::tools
