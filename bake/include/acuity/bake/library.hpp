#pragma once
// acuity/bake/library.hpp — baking an asset library: for each asset its MSFT_lod chain (.glb,
// the bytes `acuity lodgen` writes) and its profile (.acuity, the bytes `acuity profile` writes of
// that chain's first object), through a content-addressed cache, and OUT/index.json.
//
// The flow, the same for `acuity bake`, Python's acuity.bake.bake and each Dask task:
//   plan_bake (walk a folder or read a manifest)  ->  bake_asset per job (anywhere: a thread, a
//   Dask worker; it only reads the input and writes the cache)  ->  finish_bake (copies from the
//   cache into OUT and writes OUT/index.json).
// The cache is a folder, shareable between machines: entries are written with temp file + rename,
// the entry's record last, so a reader sees a whole entry or none, and concurrent bakers of one
// key write the same bytes. An entry is addressed by the SHA-256 of: a cache format tag, the tool,
// profile-format and library versions, the asset's options, the input's bytes and every file its
// uris read. Recorded "seconds" are those of the bake that made the entry, so the index is the same
// bytes whenever the same cache answers (run to run, local or Dask).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "acuity/bake/chains.hpp"
#include "acuity/spectra/profile_builder.hpp"

namespace acuity::bake {

// One asset's options; every field enters the cache key. Units and ranges as in `acuity lodgen`
// and `acuity profile`.
struct BakeOptions {
  std::uint32_t levels = 0;         // 0: halve down to ~1%; at most 32
  double ratio = 0.5;               // triangles of each level over the previous, in [0.01, 0.99]
  double max_error = 0;             // >= 0 [bounding-sphere diameters]
  std::string backend = "meshopt";  // meshopt | openmesh | cgal | cgal-lt
  bool lock_border = false;
  double crease = 45;                        // edges sharper than this are drawn sharp [degrees], in [0, 180]
  double measure_seconds = kMeasureSeconds;  // error-measurement budget for the asset [s], in [0.1, 1e5]
  double reference_height = 1080;            // pixels, for MSFT_screencoverage, in [1, 1e6]
  std::uint32_t pixels = 256;                // profile snapshot pixels (power of two, 16 .. 4096)
  std::uint32_t orientations = 8;            // 1 .. 32
  std::uint32_t bands = 0;                   // 0: all up to pixels / 4
  std::uint32_t views = 0;                   // 0: adaptive
  float tolerance = 0.25f;                   // adaptive views' switching-distance error, >= 0
  bool bound_cells = true;                   // each view bounds the loss over its cell (docs/spectra.md)
  bool clusters = false;                     // a cluster hierarchy instead of a chain (lodgen --clusters),
                                             // profiled with what each group loses (issue 48)
  std::uint32_t window_pixels =
      128;                         // clusters: pixels across each group's window (power of two, 16 .. 4096)
  std::uint32_t group_views = 12;  // clusters: directions measured per group: 12, 42 or 162 (cells read: 162)
  bool view_cells = false;         // clusters: keep the loss per view cell (ClusterViews) from fewer than 162
  std::string asset_root;          // folder a glTF's uris may read ("": the glTF's own folder)
};

// lodgen's chain options for these options (levels, ratio, max_error, backend, lock_border,
// crease). Throws lodgen::InputError for an unknown backend.
lodgen::ChainOptions chain_options(const BakeOptions& options);
// The chain request of `input` under these options (chain_options, asset_root, measure_seconds): what
// `acuity lodgen` and acuity.lodgen.build hand to write_scene_chains. Throws as chain_options.
ChainRequest chain_request(const std::string& input, const BakeOptions& options);
// The profile builder's settings for these options (pixels, orientations, bands, views, tolerance,
// bound_cells) with `jobs` threads (0: all cores).
spectra::ProfileSettings profile_settings(const BakeOptions& options, unsigned jobs);
// The per-group measurement's settings for these options (window_pixels, group_views, orientations;
// the renderer's and analyser's other defaults as the profile's) with `jobs` threads.
spectra::ClusterLossSettings cluster_loss_settings(const BakeOptions& options, unsigned jobs);

// The options as canonical JSON text (sorted keys), and back: `json` holds any subset of the
// fields over `defaults`. Throws lodgen::InputError naming `where` and the field for an unknown
// field, a wrong type or a value out of range.
std::string options_json(const BakeOptions& options);
BakeOptions parse_options(const std::string& json, const BakeOptions& defaults, const std::string& where);

struct AssetJob {
  std::string name;   // key in index.json, unique; its file_safe() form names OUT/<name>.glb/.acuity
  std::string input;  // the asset's file
  BakeOptions options;
};

struct BakePlan {
  std::string out;             // OUT
  std::string cache;           // the cache folder (default OUT/.cache)
  BakeOptions defaults;        // as given on the command line / to Python, recorded in the index
  std::vector<AssetJob> jobs;  // sorted by name
};

// A folder INPUT is walked (sorted, symbolic links not followed) for the files lodgen reads
// (lodgen::input_formats(), any case); the name is the path relative to INPUT without its extension (with the extension's
// letters appended on a clash). A file INPUT ending in .json is a manifest:
//   {"options": {...defaults...}, "assets": [{"input": "path", "name": "n", "options": {...}}, ...]}
// (paths relative to the manifest's folder; name defaults as for a folder). Any other file is one
// asset. Throws lodgen::InputError for a missing INPUT; OUT or the cache inside a folder INPUT (or
// equal to it), or equal to the folder of any input (an output could replace it); a malformed
// manifest; clashing names; more than max_assets assets; io::Error for a manifest that cannot be
// read (not a regular file, or over 64 MiB).
BakePlan plan_bake(const std::string& input, const std::string& out, const std::string& cache,
                   const BakeOptions& defaults, std::size_t max_assets = 1000000);

struct AssetResult {
  std::string name;
  bool ok = false;
  std::string error;                     // when !ok: what and where
  std::string key;                       // the cache key ("" when the input could not be read)
  std::string input_sha256;              // of the input file's bytes ("" when unreadable)
  std::vector<std::uint64_t> targets;    // per level: triangles asked of the decimator
  std::vector<std::uint64_t> triangles;  // per level: triangles obtained
  std::vector<double> errors;            // per level: Hausdorff error to level 0 [diameters]
  std::uint64_t chain_bytes = 0, profile_bytes = 0;
  double seconds = 0;   // of the bake that made the cache entry
  bool cached = false;  // answered by the cache in this run
};

// Bakes one asset into the cache, or finds it there (verified by the recorded SHA-256 of both
// files; a damaged entry is rebaked). Never throws for a bad asset: its error is in the result.
// Errors of the asset's content (lodgen::InputError, invalid profile input) are cached too, so
// they are reproduced without rebaking; others (I/O) are not. `profile_jobs`: threads for the
// profile (0: all cores); the bytes do not depend on it.
AssetResult bake_asset(const AssetJob& job, const std::string& cache, unsigned profile_jobs = 0);

// Jobs and results as JSON text, for Dask tasks (the Python bindings).
std::string job_json(const AssetJob& job);
AssetJob parse_job(const std::string& json);
std::string result_json(const AssetResult& result);
AssetResult parse_result(const std::string& json);

// done, total, the asset just finished, seconds since the start.
using BakeProgress =
    std::function<void(std::size_t done, std::size_t total, const std::string& current, double seconds)>;

// bake_asset for every job on up to `jobs` threads (0: all cores; oneTBB), results in plan order.
// `progress` is called after each asset, one call at a time.
std::vector<AssetResult> bake_all(const BakePlan& plan, unsigned jobs = 0, const BakeProgress& progress = {});

// Copies each good asset's chain and profile from the cache into OUT (atomically; unchanged files
// are not rewritten), removes the outputs of a failed asset left by an earlier run, and writes
// OUT/index.json. Returns the number of failed assets. Throws io::Error when OUT cannot be
// written.
std::size_t finish_bake(const BakePlan& plan, const std::vector<AssetResult>& results);

// The text of OUT/index.json for these results (what finish_bake writes).
std::string index_json(const BakePlan& plan, const std::vector<AssetResult>& results);

// What `acuity bake` prints: the progress line "[#####     ] 3/10  elephant  ETA 12 s" (no newline;
// the caller rewrites it in place), and the summary table of the results (one row per asset, then a
// totals line naming OUT/index.json).
std::string progress_text(std::size_t done, std::size_t total, const std::string& current, double seconds);
std::string summary_table(const BakePlan& plan, const std::vector<AssetResult>& results, double seconds);

// The bake cache's format ("acuity-bake-cache N"): every cache key and refresh_cache's stamp holds
// it; raised whenever the chains or profiles the same options produce change.
std::string cache_format();

// The version string every key and index records: "acuity 0.1.0; profile format 1; <libraries>".
std::string tool_version();

}  // namespace acuity::bake
