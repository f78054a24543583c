// acuity::bake: SHA-256 against FIPS 180-2's examples; a library bake of a folder with good and
// broken assets (statuses, count, nothing partial), the cache (re-run answered and identical, a
// changed input rebaked alone, a damaged entry rebaked), bad input refused, nothing written
// outside OUT.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <unistd.h>

#include "acuity/bake/chains.hpp"
#include "acuity/bake/library.hpp"
#include "acuity/bake/sha256.hpp"
#include "acuity/clusters.hpp"
#include "acuity/file.hpp"
#include "acuity/lodgen/mesh.hpp"
#include "acuity/profile.hpp"
#include "mesh_fixture.hpp"

namespace fs = std::filesystem;
using namespace acuity;
using json = nlohmann::json;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("acuity_test_bake_" + std::to_string(::getpid())) / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

// An ellipsoid (icosphere scaled by sx, sy, sz) as OFF text.
void write_off(const fs::path& path, int subdivisions, float sx, float sy, float sz) {
  const acuity::testing::TestMesh m = acuity::testing::icosphere(subdivisions);
  std::ofstream f(path);
  f << "OFF\n" << m.positions.size() / 3 << " " << m.indices.size() / 3 << " 0\n";
  for (std::size_t v = 0; v < m.positions.size(); v += 3)
    f << m.positions[v] * sx << " " << m.positions[v + 1] * sy << " " << m.positions[v + 2] * sz << "\n";
  for (std::size_t t = 0; t < m.indices.size(); t += 3)
    f << "3 " << m.indices[t] << " " << m.indices[t + 1] << " " << m.indices[t + 2] << "\n";
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// Every file under `dir` with its bytes.
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[e.path().lexically_relative(dir).string()] = slurp(e.path());
  return out;
}

// The same ellipsoid as a .gltf whose buffer is a separate `<bin>` file beside it.
void write_gltf_with_bin(const fs::path& gltf, const std::string& bin, float sy) {
  const acuity::testing::TestMesh m = acuity::testing::icosphere(2);
  std::vector<float> p = m.positions;
  for (std::size_t v = 1; v < p.size(); v += 3) p[v] *= sy;
  const std::size_t pos_bytes = p.size() * 4, idx_bytes = m.indices.size() * 4;
  std::ofstream b(gltf.parent_path() / bin, std::ios::binary);
  b.write(reinterpret_cast<const char*>(p.data()), std::streamsize(pos_bytes));
  b.write(reinterpret_cast<const char*>(m.indices.data()), std::streamsize(idx_bytes));
  json doc = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"byteLength", pos_bytes + idx_bytes}, {"uri", bin}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteLength", pos_bytes}},
        {{"buffer", 0}, {"byteOffset", pos_bytes}, {"byteLength", idx_bytes}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", 5126}, {"count", p.size() / 3}, {"type", "VEC3"}},
        {{"bufferView", 1}, {"componentType", 5125}, {"count", m.indices.size()}, {"type", "SCALAR"}}}},
      {"meshes", {{{"name", "egg"}, {"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"nodes", {{{"mesh", 0}, {"name", "egg"}}}},
      {"scenes", {{{"nodes", {0}}}}}};
  std::ofstream(gltf) << doc.dump();
}

bake::BakeOptions small() {
  bake::BakeOptions o;
  o.pixels = 32;
  o.views = 6;
  return o;
}

// A folder: two ellipsoids and a broken OFF (a NaN coordinate), plus a file that is not an asset.
fs::path library(const std::string& name) {
  const fs::path root = scratch(name), in = root / "in";
  fs::create_directories(in / "props");
  write_off(in / "ball.off", 2, 1, 1, 1);
  write_off(in / "props" / "egg.off", 2, 1, 1.6f, 1);
  std::ofstream(in / "broken.off") << "OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n";
  std::ofstream(in / "notes.txt") << "not an asset\n";
  return root;
}

struct BakeRun {
  bake::BakePlan plan;
  std::vector<bake::AssetResult> results;
  std::size_t failed = 0;
};

BakeRun bake_folder(const fs::path& root, unsigned jobs = 2) {
  BakeRun r;
  r.plan = bake::plan_bake((root / "in").string(), (root / "out").string(), "", small());
  r.results = bake::bake_all(r.plan, jobs);
  r.failed = bake::finish_bake(r.plan, r.results);
  return r;
}

}  // namespace

TEST(Sha256, FipsExamples) {
  EXPECT_EQ(bake::sha256_hex("", 0), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(bake::sha256_hex("abc", 3), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const std::string two =
      "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";  // 448 bits: padding spills a block
  EXPECT_EQ(bake::sha256_hex(two.data(), two.size()),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  const std::string million(1000000, 'a');
  bake::Sha256 h;  // fed in uneven pieces: the same digest
  for (std::size_t at = 0, step = 1; at < million.size(); at += step, step = step * 3 % 1000 + 1)
    h.update(million.data() + at, std::min(step, million.size() - at));
  EXPECT_EQ(h.hex(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Bake, OneBrokenAssetFailsAloneAndLeavesNothing) {
  const fs::path root = library("folder");
  const BakeRun run = bake_folder(root);
  ASSERT_EQ(run.plan.jobs.size(), 3u);  // notes.txt is not an asset
  EXPECT_EQ(run.failed, 1u);
  const json index = json::parse(slurp(root / "out" / "index.json"));
  EXPECT_EQ(index["failed"], 1);
  EXPECT_EQ(index["ok"], 2);
  EXPECT_EQ(index["tool"], bake::tool_version());
  EXPECT_EQ(index["assets"]["broken"]["status"], "error");
  EXPECT_NE(index["assets"]["broken"]["error"].get<std::string>().find("broken.off"), std::string::npos);
  for (const char* name : {"ball", "props/egg"}) {
    const json& a = index["assets"][name];
    ASSERT_EQ(a["status"], "ok") << a.dump();
    const std::string profile_bytes = slurp(root / "out" / a["profile"].get<std::string>());
    EXPECT_EQ(a["profile_bytes"].get<std::size_t>(), profile_bytes.size());
    const std::string input = slurp(root / "in" / (std::string(name) + ".off"));
    EXPECT_EQ(a["input_sha256"], bake::sha256_hex(input.data(), input.size()));
    // The profile the runtime reads describes the chain the index lists.
    const Blob blob = io::read_file((root / "out" / a["profile"].get<std::string>()).string());
    Profile p{};
    ASSERT_EQ(open_profile(blob.data(), blob.size, &p), ProfileStatus::Ok);
    ASSERT_EQ(p.meta.level_count, a["triangles"].size());
    ASSERT_GE(p.meta.level_count, 2u);
    for (std::size_t k = 0; k < p.meta.level_count; ++k) {
      EXPECT_EQ(p.levels[k].triangles, a["triangles"][k].get<std::uint32_t>());
      EXPECT_FLOAT_EQ(p.levels[k].geometric_error, a["errors"][k].get<float>());
    }
    EXPECT_EQ(a["triangles"][0], 320);  // an icosphere of 2 subdivisions, untouched at level 0
    const lodgen::Scene chain = lodgen::load_scene((root / "out" / a["chain"].get<std::string>()).string());
    EXPECT_EQ(chain.meshes.size(), a["triangles"].size());
  }
  // OUT holds the index, the good assets' files and the cache; nothing of the broken one, no temporaries.
  std::vector<std::string> top;
  for (const auto& e : fs::directory_iterator(root / "out")) top.push_back(e.path().filename().string());
  std::sort(top.begin(), top.end());
  EXPECT_EQ(top, (std::vector<std::string>{".cache", "ball.acuity", "ball.glb", "index.json",
                                           "props_egg.acuity", "props_egg.glb"}));
  for (const auto& [file, bytes] : tree(root / "out"))
    EXPECT_EQ(file.find(".tmp"), std::string::npos) << file;
}

TEST(Bake, RerunIsAnsweredByTheCacheWithTheSameBytes) {
  const fs::path root = library("rerun");
  const BakeRun first = bake_folder(root);
  const auto before = tree(root / "out");
  const BakeRun second = bake_folder(root, 1);
  for (const bake::AssetResult& r : second.results)
    EXPECT_EQ(r.cached, r.name != "broken") << r.name;  // load errors are not cached
  EXPECT_EQ(tree(root / "out"), before);                // index, chains, profiles and cache: the same bytes
  // The summary acuity bake prints: a row per asset in plan order, the error's text, the cache hits.
  const std::string table = bake::summary_table(second.plan, second.results, 3.0);
  std::vector<std::string> lines;
  for (std::istringstream in(table); std::getline(in, lines.emplace_back());) {}
  lines.pop_back();
  ASSERT_EQ(lines.size(), second.results.size() + 2) << table;
  EXPECT_EQ(lines[0].rfind("asset", 0), 0u);
  for (std::size_t i = 0; i < second.results.size(); ++i) {
    const bake::AssetResult& r = second.results[i];
    EXPECT_EQ(lines[i + 1].rfind(second.plan.jobs[i].name, 0), 0u) << lines[i + 1];
    if (r.ok)
      EXPECT_NE(lines[i + 1].find(std::to_string(r.triangles.front()) + " -> " +
                                  std::to_string(r.triangles.back())),
                std::string::npos)
          << lines[i + 1];
    else
      EXPECT_NE(lines[i + 1].find(r.error), std::string::npos) << lines[i + 1];
  }
  EXPECT_EQ(lines.back(), "3 assets in 3.00 s (2 from the cache, 60.0 assets/min); index " + second.plan.out +
                              "/index.json");
}

TEST(Bake, ProgressLineShowsTheShareDoneAndTheRemainingTime) {
  // 24 characters of bar: a quarter done is 6 marks; 10 s for 1 of 4 leaves 30 s.
  EXPECT_EQ(bake::progress_text(1, 4, "ball", 10.0),
            "[######                  ] 1/4  ball                     ETA   30 s");
  EXPECT_EQ(bake::progress_text(0, 4, "", 0.0).substr(0, 26), "[                        ]");
  EXPECT_EQ(bake::progress_text(4, 4, "egg", 8.0).substr(0, 26), "[########################]");
  // More done than the total (a caller's slip) and no total at all stay well formed.
  EXPECT_EQ(bake::progress_text(5, 4, "x", 1.0).substr(0, 26), "[########################]");
  EXPECT_EQ(bake::progress_text(0, 0, "", 0.0).substr(0, 26), "[########################]");
  // A long asset name is cut to its column.
  EXPECT_EQ(bake::progress_text(1, 2, std::string(100, 'n'), 1.0).size(),
            bake::progress_text(1, 2, "n", 1.0).size());
}

TEST(Bake, ChangedInputIsRebakedAlone) {
  const fs::path root = library("changed");
  bake_folder(root);
  write_off(root / "in" / "props" / "egg.off", 2, 1, 2.0f, 1);
  const BakeRun second = bake_folder(root);
  std::map<std::string, bool> cached;
  for (const bake::AssetResult& r : second.results) cached[r.name] = r.cached;
  EXPECT_TRUE(cached["ball"]);
  EXPECT_FALSE(cached["props/egg"]);
  const json index = json::parse(slurp(root / "out" / "index.json"));
  const std::string egg = slurp(root / "in" / "props" / "egg.off");
  EXPECT_EQ(index["assets"]["props/egg"]["input_sha256"], bake::sha256_hex(egg.data(), egg.size()));
}

// The key covers the files a glTF's uris read: a changed buffer rebakes the asset though the .gltf
// itself is unchanged.
TEST(Bake, ChangedBufferFileIsRebaked) {
  const fs::path root = scratch("buffer");
  fs::create_directories(root / "in");
  write_gltf_with_bin(root / "in" / "egg.gltf", "egg.bin", 1.2f);
  const bake::BakePlan plan = bake::plan_bake((root / "in").string(), (root / "out").string(), "", small());
  ASSERT_EQ(plan.jobs.size(), 1u);
  const bake::AssetResult first = bake::bake_asset(plan.jobs[0], plan.cache);
  ASSERT_TRUE(first.ok) << first.error;
  const std::string gltf = slurp(root / "in" / "egg.gltf");
  write_gltf_with_bin(root / "in" / "egg.gltf", "egg.bin", 1.5f);
  ASSERT_EQ(slurp(root / "in" / "egg.gltf"), gltf);  // the .gltf is the same bytes; only egg.bin changed
  const bake::AssetResult second = bake::bake_asset(plan.jobs[0], plan.cache);
  ASSERT_TRUE(second.ok) << second.error;
  EXPECT_EQ(second.input_sha256, first.input_sha256);
  EXPECT_NE(second.key, first.key);
  EXPECT_FALSE(second.cached);
  EXPECT_TRUE(bake::bake_asset(plan.jobs[0], plan.cache).cached);
}

TEST(Bake, DamagedCacheEntryIsRebakedNotServed) {
  const fs::path root = library("damaged");
  const BakeRun first = bake_folder(root);
  const bake::AssetResult& ball = first.results[0];
  ASSERT_EQ(ball.name, "ball");
  const fs::path entry = fs::path(first.plan.cache) / ball.key.substr(0, 2) / (ball.key + ".acuity");
  const std::string good = slurp(entry);
  std::ofstream(entry, std::ios::binary | std::ios::trunc) << good.substr(0, good.size() / 2);  // a torn copy
  const bake::AssetResult again = bake::bake_asset(first.plan.jobs[0], first.plan.cache);
  EXPECT_TRUE(again.ok);
  EXPECT_FALSE(again.cached);
  EXPECT_EQ(slurp(entry), good);  // repaired with the same bytes
}

TEST(Bake, ManifestGivesPerAssetOptions) {
  const fs::path root = library("manifest");
  std::ofstream(root / "in" / "bake.json") << R"({"options": {"pixels": 32, "views": 6},
    "assets": [{"input": "ball.off", "name": "ball2", "options": {"levels": 2}}, {"input": "ball.off"}]})";
  const bake::BakePlan plan =
      bake::plan_bake((root / "in" / "bake.json").string(), (root / "out").string(), "", {});
  ASSERT_EQ(plan.jobs.size(), 2u);
  EXPECT_EQ(plan.jobs[1].name, "ball2");
  EXPECT_EQ(plan.jobs[1].options.levels, 2u);
  EXPECT_EQ(plan.jobs[0].options.pixels, 32u);
  EXPECT_EQ(bake::finish_bake(plan, bake::bake_all(plan, 2)), 0u);
  const json index = json::parse(slurp(root / "out" / "index.json"));
  EXPECT_EQ(index["assets"]["ball2"]["triangles"].size(), 2u);
  EXPECT_EQ(index["assets"]["ball2"]["options"]["levels"], 2);
  EXPECT_FALSE(index["assets"]["ball"].contains("options"));  // as the defaults
  EXPECT_EQ(index["options"]["pixels"], 32);
}

// bound_cells reaches the profile builder's settings (the one translation acuity profile, acuity bake
// and the manifests share), enters the cache key, and round-trips through the options' JSON.
TEST(Bake, BoundCellsOptionReachesTheProfileSettings) {
  const bake::BakeOptions defaults;
  EXPECT_TRUE(defaults.bound_cells);
  EXPECT_TRUE(bake::profile_settings(defaults, 1).bound_cells);
  EXPECT_EQ(bake::profile_settings(defaults, 1).bound_cells, spectra::ProfileSettings{}.bound_cells);
  const bake::BakeOptions off = bake::parse_options(R"({"bound_cells": false})", defaults, "m");
  EXPECT_FALSE(off.bound_cells);
  EXPECT_FALSE(bake::profile_settings(off, 1).bound_cells);
  EXPECT_NE(bake::options_json(off), bake::options_json(defaults));
  EXPECT_FALSE(bake::parse_options(bake::options_json(off), defaults, "m").bound_cells);
  EXPECT_TRUE(bake::parse_options(R"({"bound_cells": true})", off, "m").bound_cells);
}

TEST(Bake, BadInputIsRefusedClearly) {
  const fs::path root = library("bad");
  const std::string in = (root / "in").string();
  auto error_of = [](auto f) {
    try {
      f();
    } catch (const lodgen::InputError& e) { return std::string(e.what()); }
    return std::string("no error");
  };
  EXPECT_NE(error_of([&] {
              bake::plan_bake((root / "nope").string(), (root / "out").string(), "", {});
            }).find("no such file"),
            std::string::npos);
  EXPECT_NE(error_of([&] { bake::plan_bake(in, in, "", {}); }).find("inside the input folder"),
            std::string::npos);
  EXPECT_NE(error_of([&] { bake::plan_bake(in, in + "/baked", "", {}); }).find("inside the input folder"),
            std::string::npos);
  EXPECT_NE(
      error_of([&] { bake::plan_bake(in, (root / "out").string(), in + "/cache", {}); }).find("cache folder"),
      std::string::npos);
  EXPECT_NE(error_of([&] { bake::plan_bake(in + "/ball.off", in, "", {}); }).find("is the input folder"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { bake::plan_bake(in + "/ball.off", in + "/x", "", {}); }),
            "no error");  // one file: beside it is fine
  EXPECT_NE(error_of([&] { bake::parse_options(R"({"pixels": 48})", {}, "m"); }).find("power of two"),
            std::string::npos);
  EXPECT_NE(error_of([&] { bake::parse_options(R"({"ratio": 2})", {}, "m"); }).find("'ratio'"),
            std::string::npos);
  EXPECT_NE(
      error_of([&] { bake::parse_options(R"({"colour": 1})", {}, "m"); }).find("unknown option 'colour'"),
      std::string::npos);
  EXPECT_NE(error_of([&] {
              bake::parse_options(R"({"bound_cells": 0})", {}, "m");
            }).find("option 'bound_cells' must be true or false"),
            std::string::npos);
  std::ofstream(root / "in" / "list.json")
      << R"({"assets": [{"input": "ball.off", "name": "a b"}, {"input": "ball.off", "name": "a_b"}]})";
  EXPECT_NE(error_of([&] {
              bake::plan_bake((root / "in" / "list.json").string(), (root / "o2").string(), "", {});
            }).find("both be written as a_b"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(root / "out"));
  EXPECT_FALSE(fs::exists(root / "o2"));
}

// A glTF naming a buffer outside its folder fails alone; the reader never reaches the file, and
// nothing is written outside OUT.
TEST(Bake, HostileAssetFailsAloneAndNothingOutsideOutIsWritten) {
  const fs::path root = library("hostile");
  std::ofstream(root / "secret.bin") << std::string(36, '\1');
  std::ofstream(root / "in" / "thief.gltf")
      << R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36, "uri": "../secret.bin"}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]})";
  const auto before = tree(root);
  const BakeRun run = bake_folder(root);
  EXPECT_EQ(run.failed, 2u);  // broken.off and thief.gltf
  const json index = json::parse(slurp(root / "out" / "index.json"));
  EXPECT_EQ(index["assets"]["thief"]["status"], "error");
  EXPECT_NE(index["assets"]["thief"]["error"].get<std::string>().find("../secret.bin"), std::string::npos);
  EXPECT_EQ(index["assets"]["ball"]["status"], "ok");
  auto after = tree(root);
  for (auto it = after.begin(); it != after.end();)
    it = it->first.rfind("out/", 0) == 0 ? after.erase(it) : std::next(it);
  EXPECT_EQ(after, before);
}

TEST(Bake, CacheFolderIsClearedOfWhatAnotherVersionOrSettingMade) {
  const fs::path dir = scratch("refresh");
  fs::create_directories(dir / "profiles");
  const auto put = [](const fs::path& p) { std::ofstream(p) << "x"; };
  for (const fs::path& p : {dir / "ball.glb", dir / "profiles" / "ball.acuity", dir / "mine.glb",
                            dir / "profiles" / "mine.acuity", dir / "notes.txt"})
    put(p);
  // No stamp: the named assets' chain and profile go, nothing else; the stamp is written.
  EXPECT_FALSE(bake::refresh_cache(dir.string(), {"ball"}, "profile pixels 256"));
  EXPECT_FALSE(fs::exists(dir / "ball.glb"));
  EXPECT_FALSE(fs::exists(dir / "profiles" / "ball.acuity"));
  for (const fs::path& p : {dir / "mine.glb", dir / "profiles" / "mine.acuity", dir / "notes.txt"})
    EXPECT_TRUE(fs::exists(p)) << p;
  const std::string stamp = slurp(dir / "cache-stamp");
  EXPECT_NE(stamp.find(bake::cache_format()), std::string::npos);
  EXPECT_NE(stamp.find(bake::tool_version()), std::string::npos);
  EXPECT_NE(stamp.find("profile pixels 256"), std::string::npos);
  // Same stamp: kept.
  put(dir / "ball.glb");
  EXPECT_TRUE(bake::refresh_cache(dir.string(), {"ball"}, "profile pixels 256"));
  EXPECT_TRUE(fs::exists(dir / "ball.glb"));
  // Other settings: removed again; a damaged stamp too.
  EXPECT_FALSE(bake::refresh_cache(dir.string(), {"ball"}, "profile pixels 64"));
  EXPECT_FALSE(fs::exists(dir / "ball.glb"));
  put(dir / "cache-stamp");
  EXPECT_FALSE(bake::refresh_cache(dir.string(), {"ball"}, "profile pixels 64"));
  EXPECT_TRUE(bake::refresh_cache(dir.string(), {"ball"}, "profile pixels 64"));
  // A new folder is made.
  EXPECT_FALSE(bake::refresh_cache((dir / "new" / "deeper").string(), {"ball"}, ""));
  EXPECT_TRUE(fs::exists(dir / "new" / "deeper" / "cache-stamp"));
}

// cached_chain builds with the options it is given and reads the cached file back: with creases at
// 0 degrees every level is flat-shaded (each corner's normal its triangle's), with the default 45
// degrees a ball stays smooth (corners share vertices and normals differ across a triangle).
TEST(Bake, CachedChainBuildsWithItsOptionsAndReadsTheCacheBack) {
  const fs::path dir = scratch("cached_chain");
  write_off(dir / "ball.off", 3, 1, 1, 1);
  auto flat_corners = [](const lodgen::Mesh& m) {  // corners whose normal is their triangle's
    std::size_t n = 0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      const float* p[3];
      const float* nn[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = &m.positions[3 * std::size_t(m.indices[t + k])];
        nn[k] = &m.normals[3 * std::size_t(m.indices[t + k])];
      }
      const double e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
      const double e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
      double f[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0]};
      const double len = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      for (int k = 0; k < 3; ++k) {
        const double dot = (f[0] * nn[k][0] + f[1] * nn[k][1] + f[2] * nn[k][2]) / len;
        n += dot > 0.9999;
      }
    }
    return n;
  };
  lodgen::ChainOptions flat;
  flat.levels = 3;
  flat.decimate.crease_degrees = 0;
  bool cached = true;
  const lodgen::LodObject built =
      bake::cached_chain((dir / "ball.off").string(), (dir / "flat.glb").string(), flat, &cached);
  EXPECT_FALSE(cached);
  ASSERT_EQ(built.chain.levels.size(), 3u);
  for (const lodgen::Level& l : built.chain.levels) {
    ASSERT_EQ(l.mesh.normals.size(), l.mesh.positions.size());
    EXPECT_EQ(flat_corners(l.mesh), l.mesh.indices.size());
  }
  const lodgen::LodObject again =
      bake::cached_chain((dir / "ball.off").string(), (dir / "flat.glb").string(), flat, &cached);
  EXPECT_TRUE(cached);
  ASSERT_EQ(again.chain.levels.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_EQ(again.chain.levels[k].mesh.triangle_count(), built.chain.levels[k].mesh.triangle_count());
  lodgen::ChainOptions smooth;
  smooth.levels = 3;
  const lodgen::LodObject round =
      bake::cached_chain((dir / "ball.off").string(), (dir / "smooth.glb").string(), smooth, &cached);
  EXPECT_FALSE(cached);
  const lodgen::Mesh& top = round.chain.levels[0].mesh;
  EXPECT_LT(top.vertex_count(), top.indices.size() / 2);  // shared corners
  EXPECT_LT(flat_corners(top), top.indices.size() / 10);
}

// `acuity bake --clusters` (issue 48): the asset's glb holds a cluster hierarchy and its profile the
// Clusters section measured for that hierarchy as the glb stores it (measured_group_loss reads it:
// the hash of the records read back matches the one measured in memory); the option is in the
// cache key and round-trips through the options' JSON.
TEST(Bake, ClustersBakeAHierarchyWithItsMeasuredLoss) {
  const fs::path root = scratch("clusters");
  fs::create_directories(root / "in");
  write_off(root / "in" / "egg.off", 4, 1.0f, 1.4f, 0.8f);
  bake::BakeOptions o;
  o.clusters = true;
  o.pixels = 32;
  o.views = 6;
  o.window_pixels = 32;
  EXPECT_NE(bake::options_json(o), bake::options_json(bake::BakeOptions{}));
  EXPECT_TRUE(bake::parse_options(bake::options_json(o), {}, "m").clusters);
  EXPECT_THROW(bake::parse_options(R"({"group_views": 13})", {}, "m"), lodgen::InputError);
  EXPECT_THROW(bake::parse_options(R"({"window_pixels": 48})", {}, "m"), lodgen::InputError);
  const bake::BakePlan plan = bake::plan_bake((root / "in").string(), (root / "out").string(), "", o);
  ASSERT_EQ(bake::finish_bake(plan, bake::bake_all(plan, 2)), 0u);
  const bake::ClusterFile file = bake::read_cluster_file((root / "out" / "egg.glb").string());
  ASSERT_TRUE(file.found());
  const lodgen::ClusterHierarchy& h = file.scene.clusters[file.mesh];
  ASSERT_GT(h.groups.size(), 1u);
  const Blob blob = io::read_file((root / "out" / "egg.acuity").string());
  Profile p;
  ProfileError e;
  ASSERT_EQ(open_profile(blob.data(), blob.size, &p, &e), ProfileStatus::Ok) << e.message;
  EXPECT_EQ(p.meta.level_count, 1u);
  ClusterLoss loss;
  ASSERT_EQ(measured_group_loss(p, h.clusters, h.groups, &loss), GroupLossStatus::Measured);
  EXPECT_EQ(loss.lost.size(), h.groups.size() * loss.bands_cpod.size());
  EXPECT_EQ(p.clusters.window_pixels, 32u);
  EXPECT_EQ(p.clusters.view_count, 12u);
}
