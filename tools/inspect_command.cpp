// `acuity inspect PROFILE [--json]`: what a profile holds.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "acuity/file.hpp"
#include "acuity/profile.hpp"
#include "acuity/scheduler.hpp"
#include "commands.hpp"

namespace acuity::tools {
namespace {

void run(const std::string& path, bool json) {
  const Blob blob = io::read_file(path);
  Profile p;
  ProfileError pe;
  if (open_profile(blob.data(), blob.size, &p, &pe) != ProfileStatus::Ok)
    throw std::runtime_error(path + ": " + to_string(pe.status) + ": " + pe.message);
  const ProfileMeta& m = p.meta;
  nlohmann::json j;
  j["file"] = path;
  j["bytes"] = blob.size;
  j["format_version"] = kProfileVersion;
  j["sphere"] = {m.sphere[0], m.sphere[1], m.sphere[2], m.sphere[3]};
  j["snapshot_pixels"] = m.snapshot_pixels;
  j["runtime_table_bytes"] =
      Scheduler::table_bytes(p, SchedulerConfig{});  // the tabulated path, default config
  j["runtime_view_table_bytes"] = Scheduler::table_bytes(p, SchedulerConfig{}, 0);  // one view's
  j["orientations_deg"] = std::vector<float>(p.orientations, p.orientations + m.orientation_count);
  j["bands_cpod"] = std::vector<float>(p.bands, p.bands + m.band_count);
  for (std::uint32_t v = 0; v < m.view_count; ++v)
    j["views"].push_back({p.views[v].direction[0], p.views[v].direction[1], p.views[v].direction[2]});
  for (std::uint32_t k = 0; k < m.level_count; ++k) {
    nlohmann::json level = {{"triangles", p.levels[k].triangles},
                            {"geometric_error", p.levels[k].geometric_error}};
    if (k > 0) {
      std::vector<float> peak(m.band_count, 0.0f);  // per band, the largest loss over views and orientations
      for (std::uint32_t v = 0; v < m.view_count; ++v)
        for (std::uint32_t t = 0; t < m.orientation_count; ++t)
          for (std::uint32_t b = 0; b < m.band_count; ++b)
            peak[b] = std::max(peak[b], p.lost_contrast(k, v, t, b));
      level["max_lost_contrast_per_band"] = peak;
    }
    j["levels"].push_back(level);
  }
  if (p.cluster_lost) {  // the optional Clusters section: per band, the largest and median over groups
    const ProfileClusterMeta& c = p.clusters;
    std::vector<float> peak(c.band_count, 0.0f), median(c.band_count, 0.0f), column(c.group_count);
    for (std::uint32_t b = 0; b < c.band_count; ++b) {
      for (std::uint32_t g = 0; g < c.group_count; ++g)
        column[g] = p.cluster_lost[std::size_t(g) * c.band_count + b];
      std::sort(column.begin(), column.end());
      peak[b] = column.back();
      median[b] = column[column.size() / 2];
    }
    j["clusters"] = {{"groups", c.group_count},
                     {"window_pixels", c.window_pixels},
                     {"views", c.view_count},
                     {"bands_cpod", std::vector<float>(p.cluster_bands, p.cluster_bands + c.band_count)},
                     {"max_lost_contrast_per_band", peak},
                     {"median_lost_contrast_per_band", median}};
    if (p.cluster_view_lost) {  // the optional ClusterViews section: per band, the median over groups and cells
      const std::size_t Vc = p.cluster_views.view_count, n = std::size_t(c.group_count) * Vc;
      std::vector<float> cell(n), cell_median(c.band_count);
      for (std::uint32_t b = 0; b < c.band_count; ++b) {
        for (std::size_t i = 0; i < n; ++i) cell[i] = p.cluster_view_lost[i * c.band_count + b];
        std::sort(cell.begin(), cell.end());
        cell_median[b] = cell[n / 2];
      }
      j["clusters"]["view_cells"] = Vc;
      j["clusters"]["view_samples"] = p.cluster_views.sample_count;
      j["clusters"]["median_lost_contrast_per_band_and_cell"] = cell_median;
    }
  }
  if (json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("%s: acuity profile v%u, %zu bytes\n", path.c_str(), kProfileVersion, blob.size);
  std::printf("sphere    centre (%g, %g, %g), radius %g; snapshots %u px across\n", m.sphere[0], m.sphere[1],
              m.sphere[2], m.sphere[3], m.snapshot_pixels);
  std::printf("views     %u (lookup %u x %u per cube face)\n", m.view_count, m.lookup_resolution,
              m.lookup_resolution);
  const std::size_t tables = Scheduler::table_bytes(p, SchedulerConfig{});
  std::printf(
      "runtime   %zu bytes of tables (tabulated path, default config); %zu with the profile;\n"
      "          as much again per tabulated bias, and all of it twice with a hysteresis margin;\n"
      "          %zu bytes per view, where only the views seen are made (add_profile_deferred)\n",
      tables, tables + blob.size, Scheduler::table_bytes(p, SchedulerConfig{}, 0));
  std::printf("spectra   %u orientations x %u bands:", m.orientation_count, m.band_count);
  for (std::uint32_t b = 0; b < m.band_count; ++b) std::printf(" %g", p.bands[b]);
  std::printf(" cycles per diameter\n\nlevel  triangles  geom.error  largest loss per band\n");
  for (std::uint32_t k = 0; k < m.level_count; ++k) {
    std::printf("%5u  %9u  %10.5f ", k, p.levels[k].triangles, p.levels[k].geometric_error);
    if (k > 0)
      for (float x : j["levels"][k]["max_lost_contrast_per_band"].get<std::vector<float>>())
        std::printf(" %6.3f", x);
    std::printf("\n");
  }
  if (!j.contains("clusters")) return;
  const nlohmann::json& c = j["clusters"];
  std::printf("\nclusters  %u groups, each measured from %u directions in %u px windows\n",
              c["groups"].get<unsigned>(), c["views"].get<unsigned>(), c["window_pixels"].get<unsigned>());
  if (c.contains("view_cells"))
    std::printf("          and per view: %u cells, each bounding the directions measured in or near it\n",
                c["view_cells"].get<unsigned>());
  for (const char* row : {"bands_cpod", "max_lost_contrast_per_band", "median_lost_contrast_per_band",
                          "median_lost_contrast_per_band_and_cell"}) {
    if (!c.contains(row)) continue;
    std::printf("%-38s", row);
    for (float x : c[row].get<std::vector<float>>()) std::printf(" %6.3g", x);
    std::printf("\n");
  }
}

}  // namespace

void add_inspect_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand("inspect", "Print what a profile holds");
  cmd->add_option("profile", *path, "A .acuity file")->required();
  cmd->add_flag("--json", *json, "Machine-readable output");
  cmd->callback([path, json] { run(*path, *json); });
}

}  // namespace acuity::tools
