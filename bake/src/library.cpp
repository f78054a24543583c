#include "acuity/bake/library.hpp"

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

#include "acuity/bake/chains.hpp"
#include "acuity/bake/scene.hpp"
#include "acuity/bake/sha256.hpp"
#include "acuity/file.hpp"
#include "acuity/lodgen/formats.hpp"
#include "acuity/lodgen/versions.hpp"
#include "acuity/profile.hpp"
#include "acuity/spectra/versions.hpp"
#include "acuity/version.hpp"

namespace acuity::bake {
namespace fs = std::filesystem;
using json = nlohmann::json;
namespace {

// 2: profiles bound the loss over each view's cell (spectra::ProfileSettings::bound_cells), so
// entries of 1 (one view's own measurement) are not reused; lodgen's meshopt chains continue from
// the welded level after a rejected one.
// 3: profiles carry the Detail section (what stelaCSF's area term reads) and write ClusterViews only
// when asked (162 directions or --view-cells): caches made before lacked the one and held the other.
// 4: profiles carry the Pooled section (what the area law reads) and bound a cell's extents by energy.
constexpr const char* kCacheFormat = "acuity-bake-cache 4";
constexpr const char* kInputToken = "{input}";  // stands for the asset's path in cached error messages

// ---- Options ------------------------------------------------------------------------------------

json to_json(const BakeOptions& o) {
  return {{"levels", o.levels},
          {"ratio", o.ratio},
          {"max_error", o.max_error},
          {"backend", o.backend},
          {"lock_border", o.lock_border},
          {"crease", o.crease},
          {"measure_seconds", o.measure_seconds},
          {"reference_height", o.reference_height},
          {"pixels", o.pixels},
          {"orientations", o.orientations},
          {"bands", o.bands},
          {"views", o.views},
          {"tolerance", o.tolerance},
          {"bound_cells", o.bound_cells},
          {"clusters", o.clusters},
          {"window_pixels", o.window_pixels},
          {"group_views", o.group_views},
          {"view_cells", o.view_cells},
          {"asset_root", o.asset_root}};
}

template <typename T>
T number(const json& v, const std::string& where, const std::string& key, double lo, double hi) {
  if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo || v.get<double>() > hi)
    throw lodgen::InputError(where + ": option '" + key + "' must be a number in [" + json(lo).dump() + ", " +
                             json(hi).dump() + "], not " + v.dump());
  if constexpr (std::is_integral_v<T>) {
    if (v.get<double>() != std::floor(v.get<double>()))
      throw lodgen::InputError(where + ": option '" + key + "' must be a whole number, not " + v.dump());
  }
  return static_cast<T>(v.get<double>());
}

BakeOptions from_json(const json& j, BakeOptions o, const std::string& where) {
  if (!j.is_object()) throw lodgen::InputError(where + ": options must be a JSON object");
  for (const auto& [key, v] : j.items()) {
    if (key == "levels")
      o.levels = number<std::uint32_t>(v, where, key, 0, 32);
    else if (key == "ratio")
      o.ratio = number<double>(v, where, key, 0.01, 0.99);
    else if (key == "max_error")
      o.max_error = number<double>(v, where, key, 0, 1e6);
    else if (key == "crease")
      o.crease = number<double>(v, where, key, 0, 180);
    else if (key == "measure_seconds")
      o.measure_seconds = number<double>(v, where, key, 0.1, 1e5);
    else if (key == "reference_height")
      o.reference_height = number<double>(v, where, key, 1, 1e6);
    else if (key == "pixels")
      o.pixels = number<std::uint32_t>(v, where, key, 16, 4096);
    else if (key == "orientations")
      o.orientations = number<std::uint32_t>(v, where, key, 1, 32);
    else if (key == "bands")
      o.bands = number<std::uint32_t>(v, where, key, 0, 32);
    else if (key == "views")
      o.views = number<std::uint32_t>(v, where, key, 0, 4096);
    else if (key == "tolerance")
      o.tolerance = number<float>(v, where, key, 0, 1e6);
    else if (key == "window_pixels")
      o.window_pixels = number<std::uint32_t>(v, where, key, 16, 4096);
    else if (key == "group_views")
      o.group_views = number<std::uint32_t>(v, where, key, 12, 162);
    else if (key == "lock_border" || key == "bound_cells" || key == "clusters" || key == "view_cells") {
      if (!v.is_boolean()) throw lodgen::InputError(where + ": option '" + key + "' must be true or false");
      (key == "lock_border"   ? o.lock_border
       : key == "bound_cells" ? o.bound_cells
       : key == "clusters"    ? o.clusters
                              : o.view_cells) = v.get<bool>();
    } else if (key == "backend" || key == "asset_root") {
      if (!v.is_string()) throw lodgen::InputError(where + ": option '" + key + "' must be a string");
      (key == "backend" ? o.backend : o.asset_root) = v.get<std::string>();
    } else {
      throw lodgen::InputError(where + ": unknown option '" + key + "'");
    }
  }
  lodgen::Backend backend;
  if (!lodgen::parse_backend(o.backend, &backend))
    throw lodgen::InputError(where + ": option 'backend' must be meshopt, openmesh, cgal or cgal-lt, not '" +
                             o.backend + "'");
  if (o.pixels & (o.pixels - 1))
    throw lodgen::InputError(where + ": option 'pixels' must be a power of two, not " +
                             std::to_string(o.pixels));
  if (o.window_pixels & (o.window_pixels - 1))
    throw lodgen::InputError(where + ": option 'window_pixels' must be a power of two, not " +
                             std::to_string(o.window_pixels));
  if (o.group_views != 12 && o.group_views != 42 && o.group_views != 162)
    throw lodgen::InputError(where + ": option 'group_views' must be 12, 42 or 162, not " +
                             std::to_string(o.group_views));
  return o;
}

// ---- Files --------------------------------------------------------------------------------------

// What a folder INPUT is walked for: the files lodgen reads.
bool bakeable(const fs::path& p) { return lodgen::input_format(p.string()) != nullptr; }

// The whole file, at most max_bytes (the load limit max_file_bytes); throws io::Error.
Blob read_bounded(const std::string& path, std::uint64_t max_bytes) {
  io::ReadLimits limits;
  limits.max_bytes = max_bytes;
  limits.max_bytes_name = "the load limit max_file_bytes";
  return io::read_file(path, limits);
}

std::string read_text(const std::string& path, std::uint64_t max_bytes) {
  const Blob b = read_bounded(path, max_bytes);
  return std::string(static_cast<const char*>(b.data()), b.size);
}

bool same_bytes(const std::string& path, const std::string& bytes) {
  try {
    const Blob b = io::read_file(path);
    return b.size == bytes.size() &&
           std::equal(bytes.begin(), bytes.end(), static_cast<const char*>(b.data()));
  } catch (const io::Error&) { return false; }
}

fs::path canonical_folder(const fs::path& p) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(fs::absolute(p, ec), ec);
  return ec ? fs::absolute(p).lexically_normal() : c;
}

// True when `inner` is `outer` or lies inside it (canonical paths).
bool within(const fs::path& inner, const fs::path& outer) {
  const fs::path rel = inner.lexically_relative(outer);
  return !rel.empty() && *rel.begin() != "..";
}

void replace_all(std::string& s, const std::string& from, const std::string& to) {
  if (from.empty()) return;
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
}

// ---- Cache entries ------------------------------------------------------------------------------

struct EntryPaths {
  std::string record, chain, profile;
};

EntryPaths entry_paths(const std::string& cache, const std::string& key) {
  const fs::path dir = fs::path(cache) / key.substr(0, 2);
  return {(dir / (key + ".json")).string(), (dir / (key + ".glb")).string(),
          (dir / (key + ".acuity")).string()};
}

void summary_to_json(const AssetResult& r, json& j) {
  j["targets"] = r.targets;
  j["triangles"] = r.triangles;
  j["errors"] = r.errors;
  j["chain_bytes"] = r.chain_bytes;
  j["profile_bytes"] = r.profile_bytes;
}

void summary_from_json(const json& j, AssetResult& r) {
  r.targets = j.at("targets").get<std::vector<std::uint64_t>>();
  r.triangles = j.at("triangles").get<std::vector<std::uint64_t>>();
  r.errors = j.at("errors").get<std::vector<double>>();
  r.chain_bytes = j.at("chain_bytes").get<std::uint64_t>();
  r.profile_bytes = j.at("profile_bytes").get<std::uint64_t>();
}

// The cached answer for r.key, when a whole, intact entry exists.
bool lookup(const std::string& cache, const AssetJob& job, AssetResult& r) {
  const EntryPaths p = entry_paths(cache, r.key);
  if (!fs::exists(p.record)) return false;
  try {
    const Blob record = io::read_file(p.record);
    const json j = json::parse(static_cast<const char*>(record.data()),
                               static_cast<const char*>(record.data()) + record.size);
    if (j.at("format").get<std::string>() != kCacheFormat || j.at("key").get<std::string>() != r.key)
      return false;
    r.seconds = j.at("seconds").get<double>();
    if (j.at("status").get<std::string>() == "error") {
      r.error = j.at("error").get<std::string>();
      replace_all(r.error, kInputToken, job.input);
      r.cached = true;
      return true;
    }
    summary_from_json(j, r);
    const Blob chain = io::read_file(p.chain), profile = io::read_file(p.profile);
    if (sha256_hex(chain.data(), chain.size) != j.at("chain_sha256").get<std::string>() ||
        sha256_hex(profile.data(), profile.size) != j.at("profile_sha256").get<std::string>())
      return false;  // damaged: rebake
  } catch (const json::exception&) { return false; } catch (const io::Error&) {
    return false;
  }  // a missing or unreadable part: rebake
  r.ok = r.cached = true;
  return true;
}

void store(const std::string& cache, const AssetJob& job, const AssetResult& r, const std::string& chain,
           const std::string& profile) {
  const EntryPaths p = entry_paths(cache, r.key);
  fs::create_directories(fs::path(p.record).parent_path());
  json j = {{"format", kCacheFormat}, {"key", r.key}, {"seconds", r.seconds}};
  if (r.ok) {
    io::write_file_atomically(p.chain, chain);
    io::write_file_atomically(p.profile, profile);
    j["status"] = "ok";
    j["chain_sha256"] = sha256_hex(chain.data(), chain.size());
    j["profile_sha256"] = sha256_hex(profile.data(), profile.size());
    summary_to_json(r, j);
  } else {
    std::string error = r.error;
    replace_all(error, job.input, kInputToken);
    j["status"] = "error";
    j["error"] = error;
  }
  io::write_file_atomically(p.record, j.dump(1) + "\n");  // last: the entry exists once this is in place
}

// The cache key: format, versions, options, the input's bytes and every file its uris read.
std::string cache_key(const AssetJob& job, const std::string& input_sha256,
                      const std::vector<std::string>& files_read) {
  Sha256 h;
  h.update(std::string(kCacheFormat) + "\n" + tool_version() + "\n" + options_json(job.options) + "\ninput " +
           input_sha256 + "\n");
  const fs::path base = canonical_folder(
      fs::path(job.input).parent_path().empty() ? fs::path(".") : fs::path(job.input).parent_path());
  for (const std::string& f : files_read) {
    std::string digest = "unreadable";
    try {
      const Blob b = io::read_file(f);
      digest = sha256_hex(b.data(), b.size);
    } catch (const io::Error&) {}
    h.update("file " + fs::path(f).lexically_relative(base).generic_string() + " " + digest + "\n");
  }
  return h.hex();
}

// The chain's bytes, its profile's bytes and the summary of the profiled object.
void bake_content(const AssetJob& job, lodgen::Scene scene, unsigned profile_jobs, AssetResult& r,
                  std::string* chain, std::string* profile) {
  const BakeOptions& o = job.options;
  const SceneChains sc =
      chains_of_scene(std::move(scene), job.input, chain_options(o), {}, o.measure_seconds, o.clusters);
  lodgen::GltfWriteOptions wo;
  wo.reference_height = o.reference_height;
  *chain = lodgen::encode_lod_gltf(sc.objects, sc.scene.materials, wo);
  if (o.clusters) {  // the profile `acuity profile` makes of the cluster file: its first hierarchy
    const auto top = std::find_if(sc.objects.begin(), sc.objects.end(),
                                  [](const lodgen::LodObject& obj) { return !obj.clusters.empty(); });
    if (top == sc.objects.end())
      throw lodgen::InputError(job.input + ": no mesh to build a cluster hierarchy of");
    const spectra::ProfileData data = profile_clusters(
        cluster_mesh(top->chain.levels[0].mesh, top->clusters), spectra_material(sc.scene, top->material),
        profile_settings(o, profile_jobs), cluster_loss_settings(o, profile_jobs));
    const Blob blob = spectra::encode_profile(data);
    profile->assign(static_cast<const char*>(blob.data()), blob.size);
    r.targets.push_back(top->chain.levels[0].target_triangles);
    r.triangles.push_back(top->chain.levels[0].mesh.triangle_count());
    r.errors.push_back(0);
    r.chain_bytes = chain->size();
    r.profile_bytes = profile->size();
    return;
  }
  // The profile `acuity profile` makes of the chain file: its first object with MSFT_lod levels.
  const auto top = std::find_if(sc.objects.begin(), sc.objects.end(),
                                [](const lodgen::LodObject& obj) { return obj.chain.levels.size() > 1; });
  if (top == sc.objects.end())
    throw lodgen::InputError(job.input +
                             ": no object has more than one level (too few triangles to decimate)");
  const spectra::ProfileData data =
      spectra::build_profile(spectra_levels(top->chain), spectra_material(sc.scene, top->material),
                             profile_settings(o, profile_jobs));
  const Blob blob = spectra::encode_profile(data);
  profile->assign(static_cast<const char*>(blob.data()), blob.size);
  for (const lodgen::Level& l : top->chain.levels) {
    r.targets.push_back(l.target_triangles);
    r.triangles.push_back(l.mesh.triangle_count());
    r.errors.push_back(l.hausdorff);
  }
  r.chain_bytes = chain->size();
  r.profile_bytes = profile->size();
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

std::string tool_version() {
  return std::string("acuity ") + ACUITY_VERSION_STRING + "; profile format " +
         std::to_string(kProfileVersion) + "; " + lodgen::library_versions() + "; " +
         spectra::library_versions();
}

std::string options_json(const BakeOptions& options) { return to_json(options).dump(); }

lodgen::ChainOptions chain_options(const BakeOptions& o) {
  lodgen::ChainOptions co;
  co.levels = o.levels;
  co.ratio = o.ratio;
  co.max_error = o.max_error;
  co.decimate.lock_border = o.lock_border;
  co.decimate.crease_degrees = o.crease;
  if (!lodgen::parse_backend(o.backend, &co.decimate.backend))
    throw lodgen::InputError("backend: meshopt, openmesh, cgal or cgal-lt, not '" + o.backend + "'");
  return co;
}

ChainRequest chain_request(const std::string& input, const BakeOptions& o) {
  ChainRequest request;
  request.input = input;
  request.asset_root = o.asset_root;
  request.chain = chain_options(o);
  request.measure_seconds = o.measure_seconds;
  return request;
}

spectra::ProfileSettings profile_settings(const BakeOptions& o, unsigned jobs) {
  spectra::ProfileSettings s;
  s.render.pixels = o.pixels;
  s.analysis.orientations = o.orientations;
  s.analysis.bands = o.bands;
  s.views = o.views;
  s.view_tolerance = o.tolerance;
  s.bound_cells = o.bound_cells;
  s.jobs = jobs;
  return s;
}

spectra::ClusterLossSettings cluster_loss_settings(const BakeOptions& o, unsigned jobs) {
  spectra::ClusterLossSettings s;
  s.render.pixels = o.window_pixels;
  s.analysis.orientations = o.orientations;
  s.views = o.group_views;
  s.view_cells = o.view_cells;
  s.jobs = jobs;
  return s;
}

BakeOptions parse_options(const std::string& text, const BakeOptions& defaults, const std::string& where) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw lodgen::InputError(where + ": options are not JSON: " + e.what());
  }
  return from_json(j, defaults, where);
}

// ---- Plan ---------------------------------------------------------------------------------------

BakePlan plan_bake(const std::string& input, const std::string& out, const std::string& cache,
                   const BakeOptions& defaults, std::size_t max_assets) {
  BakePlan plan;
  plan.out = out;
  plan.cache = cache.empty() ? (fs::path(out) / ".cache").string() : cache;
  plan.defaults = defaults;
  std::error_code ec;
  const fs::file_status st = fs::status(input, ec);
  if (ec || !fs::exists(st)) throw lodgen::InputError(input + ": no such file or folder");
  std::set<fs::path> folders;      // every folder holding an input: OUT and the cache may not be one
  std::optional<fs::path> walked;  // a folder INPUT: OUT and the cache may not lie inside it
  auto add = [&](const fs::path& file, std::string name, const BakeOptions& options) {
    if (plan.jobs.size() >= max_assets)
      throw lodgen::InputError(input + ": more than " + std::to_string(max_assets) + " assets");
    plan.jobs.push_back({std::move(name), file.string(), options});
    folders.insert(canonical_folder(file.parent_path().empty() ? fs::path(".") : file.parent_path()));
  };
  auto default_name = [](const fs::path& rel) { return (rel.parent_path() / rel.stem()).generic_string(); };
  if (fs::is_directory(st)) {
    walked = canonical_folder(input);
    std::vector<fs::path> files;
    for (fs::recursive_directory_iterator it(input, fs::directory_options::none, ec), end; !ec && it != end;
         it.increment(ec)) {
      if (it->is_regular_file() && !it->is_symlink() && bakeable(it->path())) files.push_back(it->path());
    }
    if (ec) throw lodgen::InputError(input + ": cannot walk the folder: " + ec.message());
    std::sort(files.begin(), files.end());
    std::map<std::string, int> stems;
    for (const fs::path& f : files) ++stems[default_name(f.lexically_relative(input))];
    for (const fs::path& f : files) {
      const fs::path rel = f.lexically_relative(input);
      std::string name = default_name(rel);
      if (stems[name] > 1) name += "_" + rel.extension().string().substr(1);
      add(f, name, defaults);
    }
  } else if (fs::path(input).extension() == ".json") {
    const fs::path dir = fs::path(input).parent_path();
    json m;
    try {
      m = json::parse(read_text(input, 64ull << 20));
    } catch (const json::exception& e) {
      throw lodgen::InputError(input + ": the manifest is not JSON: " + e.what());
    }
    if (!m.is_object() || !m.contains("assets") || !m["assets"].is_array())
      throw lodgen::InputError(input +
                               ": a manifest is {\"options\": {...}, \"assets\": [{\"input\": ..., \"name\": "
                               "..., \"options\": {...}}]}");
    if (m.contains("options")) plan.defaults = from_json(m["options"], defaults, input + ": options");
    for (std::size_t i = 0; i < m["assets"].size(); ++i) {
      const json& a = m["assets"][i];
      const std::string where = input + ": assets[" + std::to_string(i) + "]";
      if (!a.is_object() || !a.contains("input") || !a["input"].is_string())
        throw lodgen::InputError(where + ": needs \"input\": \"path\"");
      const fs::path file = dir / a["input"].get<std::string>();
      std::string name = default_name(fs::path(a["input"].get<std::string>()).lexically_normal());
      if (a.contains("name")) {
        if (!a["name"].is_string() || a["name"].get<std::string>().empty())
          throw lodgen::InputError(where + ": \"name\" must be a non-empty string");
        name = a["name"].get<std::string>();
      }
      add(file, name,
          a.contains("options") ? from_json(a["options"], plan.defaults, where + ": options")
                                : plan.defaults);
    }
  } else {
    add(fs::path(input), fs::path(input).stem().string(), defaults);
  }
  const fs::path out_path = canonical_folder(out);
  const fs::path cache_path = canonical_folder(plan.cache);
  if (walked && within(out_path, *walked))
    throw lodgen::InputError(out + ": the output folder is or lies inside the input folder " +
                             walked->string());
  if (walked && within(cache_path, *walked))
    throw lodgen::InputError(plan.cache + ": the cache folder is or lies inside the input folder " +
                             walked->string());
  for (const fs::path& f : folders) {  // an output could replace an input
    if (out_path == f)
      throw lodgen::InputError(out + ": the output folder is the input folder " + f.string());
    if (cache_path == f)
      throw lodgen::InputError(plan.cache + ": the cache folder is the input folder " + f.string());
  }
  if (fs::exists(out) && !fs::is_directory(out))
    throw lodgen::InputError(out + ": exists and is not a folder");
  std::sort(plan.jobs.begin(), plan.jobs.end(),
            [](const AssetJob& a, const AssetJob& b) { return a.name < b.name; });
  std::map<std::string, std::string> files;  // file_safe name -> asset
  for (const AssetJob& j : plan.jobs) {
    const auto [it, fresh] = files.try_emplace(file_safe(j.name), j.name);
    if (!fresh)
      throw lodgen::InputError(input + ": assets '" + it->second + "' and '" + j.name +
                               "' would both be written as " + it->first);
  }
  return plan;
}

// ---- One asset ----------------------------------------------------------------------------------

AssetResult bake_asset(const AssetJob& job, const std::string& cache, unsigned profile_jobs) {
  AssetResult r;
  r.name = job.name;
  const lodgen::LoadLimits limits;
  try {
    const Blob bytes = read_bounded(job.input, limits.max_file_bytes);
    r.input_sha256 = sha256_hex(bytes.data(), bytes.size);
  } catch (const io::Error& e) {
    r.error = e.what();
    return r;
  }
  const auto start = std::chrono::steady_clock::now();
  lodgen::Scene scene;
  std::vector<std::string> files_read;
  try {  // load errors may depend on files the load did not reach: not cached
    lodgen::LoadOptions lo;
    lo.asset_root = job.options.asset_root;
    lo.files_read = &files_read;
    scene = lodgen::load_scene(job.input, lo);
  } catch (const std::exception& e) {
    r.error = e.what();
    return r;
  }
  r.key = cache_key(job, r.input_sha256, files_read);
  if (lookup(cache, job, r)) return r;
  std::string chain, profile;
  bool content_fault = false;
  try {
    bake_content(job, std::move(scene), profile_jobs, r, &chain, &profile);
    r.ok = true;
  } catch (const lodgen::InputError& e) {
    r.error = e.what(), content_fault = true;
  } catch (const std::invalid_argument& e) {
    r.error = job.input + ": " + e.what(), content_fault = true;
  } catch (const std::exception& e) { r.error = job.input + ": " + e.what(); }
  r.seconds = seconds_since(start);
  if (r.ok || content_fault) {
    try {
      store(cache, job, r, chain, profile);
    } catch (const std::exception& e) {
      r.ok = false;
      r.error = "cache: " + std::string(e.what());
    }
  }
  return r;
}

// ---- Transport ----------------------------------------------------------------------------------

std::string job_json(const AssetJob& job) {
  return json{{"name", job.name}, {"input", job.input}, {"options", to_json(job.options)}}.dump();
}

AssetJob parse_job(const std::string& text) {
  try {
    const json j = json::parse(text);
    return {j.at("name").get<std::string>(), j.at("input").get<std::string>(),
            from_json(j.at("options"), BakeOptions{}, "job")};
  } catch (const json::exception& e) { throw lodgen::InputError(std::string("not a bake job: ") + e.what()); }
}

std::string result_json(const AssetResult& r) {
  json j = {{"name", r.name},
            {"ok", r.ok},
            {"error", r.error},
            {"key", r.key},
            {"input_sha256", r.input_sha256},
            {"seconds", r.seconds},
            {"cached", r.cached}};
  summary_to_json(r, j);
  return j.dump();
}

AssetResult parse_result(const std::string& text) {
  AssetResult r;
  try {
    const json j = json::parse(text);
    r.name = j.at("name").get<std::string>();
    r.ok = j.at("ok").get<bool>();
    r.error = j.at("error").get<std::string>();
    r.key = j.at("key").get<std::string>();
    r.input_sha256 = j.at("input_sha256").get<std::string>();
    r.seconds = j.at("seconds").get<double>();
    r.cached = j.at("cached").get<bool>();
    summary_from_json(j, r);
  } catch (const json::exception& e) {
    throw lodgen::InputError(std::string("not a bake result: ") + e.what());
  }
  return r;
}

// ---- Many assets --------------------------------------------------------------------------------

std::vector<AssetResult> bake_all(const BakePlan& plan, unsigned jobs, const BakeProgress& progress) {
  const unsigned threads = jobs ? jobs : std::max(1u, std::thread::hardware_concurrency());
  std::vector<AssetResult> results(plan.jobs.size());
  std::mutex m;
  std::size_t done = 0;
  const auto start = std::chrono::steady_clock::now();
  oneapi::tbb::task_arena arena{static_cast<int>(threads)};
  arena.execute([&] {
    oneapi::tbb::parallel_for(
        std::size_t(0), plan.jobs.size(),
        [&](std::size_t i) {
          results[i] = bake_asset(plan.jobs[i], plan.cache, threads);
          const std::lock_guard<std::mutex> lock(m);
          ++done;
          if (progress) progress(done, plan.jobs.size(), plan.jobs[i].name, seconds_since(start));
        },
        oneapi::tbb::simple_partitioner());
  });
  return results;
}

std::string index_json(const BakePlan& plan, const std::vector<AssetResult>& results) {
  json assets = json::object();
  std::size_t failed = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const AssetResult& r = results[i];
    const AssetJob& job = plan.jobs[i];
    json a = {{"status", r.ok ? "ok" : "error"},
              {"input", job.input},
              {"input_sha256", r.input_sha256},
              {"seconds", r.seconds}};
    if (r.ok) {
      const std::string file = file_safe(job.name);
      a["chain"] = file + ".glb";
      a["profile"] = file + ".acuity";
      a["levels"] = r.targets;
      a["triangles"] = r.triangles;
      a["errors"] = r.errors;
      a["profile_bytes"] = r.profile_bytes;
    } else {
      a["error"] = r.error;
      ++failed;
    }
    if (options_json(job.options) != options_json(plan.defaults)) a["options"] = to_json(job.options);
    assets[job.name] = a;
  }
  const json index = {{"tool", tool_version()},
                      {"options", to_json(plan.defaults)},
                      {"assets", assets},
                      {"ok", results.size() - failed},
                      {"failed", failed}};
  return index.dump(2) + "\n";
}

namespace {

template <typename... Args>
std::string format(const char* pattern, Args... args) {
  char line[512];
  std::snprintf(line, sizeof line, pattern, args...);
  return line;
}

}  // namespace

std::string progress_text(std::size_t done, std::size_t total, const std::string& current, double seconds) {
  const int width = 24, filled = total ? int(width * std::min(done, total) / total) : width;
  const double eta = done ? seconds / double(done) * double(total - std::min(done, total)) : 0;
  return format("[%.*s%*s] %zu/%zu  %-24.24s ETA %4.0f s", filled, "########################", width - filled,
                "", done, total, current.c_str(), eta);
}

std::string summary_table(const BakePlan& plan, const std::vector<AssetResult>& results, double seconds) {
  std::string out = format("%-28s %-6s %6s %20s %10s %8s\n", "asset", "status", "levels", "triangles",
                           "profile", "seconds");
  std::size_t hits = 0;
  for (std::size_t i = 0; i < results.size() && i < plan.jobs.size(); ++i) {
    const AssetResult& r = results[i];
    hits += r.cached;
    if (!r.ok) {
      out += format("%-28.28s %-6s ", plan.jobs[i].name.c_str(), "error") + r.error + "\n";
      continue;
    }
    const std::string tris = r.triangles.empty() ? std::string("-")
                                                 : std::to_string(r.triangles.front()) + " -> " +
                                                       std::to_string(r.triangles.back());
    out += format("%-28.28s %-6s %6zu %20s %10llu %8.2f %s\n", plan.jobs[i].name.c_str(), "ok",
                  r.triangles.size(), tris.c_str(), static_cast<unsigned long long>(r.profile_bytes),
                  r.seconds, r.cached ? "cached" : "");
  }
  return out + format("%zu assets in %.2f s (%zu from the cache, %.1f assets/min); index %s/index.json\n",
                      results.size(), seconds, hits,
                      seconds > 0 ? 60.0 * double(results.size()) / seconds : 0.0, plan.out.c_str());
}

std::string cache_format() { return kCacheFormat; }

std::size_t finish_bake(const BakePlan& plan, const std::vector<AssetResult>& results) {
  if (results.size() != plan.jobs.size())
    throw std::invalid_argument("finish_bake: one result per job expected");
  fs::create_directories(plan.out);
  std::size_t failed = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const AssetResult& r = results[i];
    const fs::path base = fs::path(plan.out) / file_safe(plan.jobs[i].name);
    const std::string chain = base.string() + ".glb", profile = base.string() + ".acuity";
    if (!r.ok) {  // no output of an earlier run stays beside an error
      ++failed;
      std::error_code ec;
      fs::remove(chain, ec);
      fs::remove(profile, ec);
      continue;
    }
    const EntryPaths p = entry_paths(plan.cache, r.key);
    for (const auto& [from, to] : {std::pair{p.chain, chain}, std::pair{p.profile, profile}}) {
      const std::string bytes = read_text(from, std::uint64_t(1) << 40);
      if (!same_bytes(to, bytes)) io::write_file_atomically(to, bytes);
    }
  }
  io::write_file_atomically((fs::path(plan.out) / "index.json").string(), index_json(plan, results));
  return failed;
}

}  // namespace acuity::bake
