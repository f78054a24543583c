// Hostile assets and callers (issue 12): every glTF read is confined to the asset's folder and
// bounded before heavy work, offsets are overflow-checked, walks are iterative, outputs are
// regular files, and the C ABI is all or nothing. Each test builds its hostile file here.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "acuity.h"
#include "acuity/file.hpp"
#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "acuity/sim/tracks.hpp"
#include "profile_fixture.hpp"

#include "scratch_dir.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace acuity;

namespace {

using acuity::testing::scratch;

void write(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) { return e.what(); }
  return "no error";
}

// One triangle: 3 float positions (36 bytes) then 3 uint16 indices (6 bytes) and 2 bytes padding.
std::string triangle_bytes() {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t i[4] = {0, 1, 2, 0};
  std::string b(44, '\0');
  std::memcpy(b.data(), p, 36);
  std::memcpy(b.data() + 36, i, 8);
  return b;
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    std::uint32_t v = std::uint32_t(static_cast<unsigned char>(in[i])) << 16;
    if (i + 1 < in.size()) v |= std::uint32_t(static_cast<unsigned char>(in[i + 1])) << 8;
    if (i + 2 < in.size()) v |= std::uint32_t(static_cast<unsigned char>(in[i + 2]));
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? k[v & 63] : '=';
  }
  return out;
}

// A valid one-triangle glTF whose buffer is `uri` (default: embedded as a data: URI).
json triangle_gltf(const std::string& uri = "") {
  const std::string bytes = triangle_bytes();
  return json{
      {"asset", {{"version", "2.0"}}},
      {"buffers",
       json::array({{{"byteLength", 44},
                     {"uri", uri.empty() ? "data:application/octet-stream;base64," + base64(bytes) : uri}}})},
      {"bufferViews", json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
                                   {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}})},
      {"accessors",
       json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
                    {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}})},
      {"meshes",
       json::array({{{"name", "tri"},
                     {"primitives", json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}})}}})},
      {"nodes", json::array({{{"name", "tri"}, {"mesh", 0}}})},
      {"scenes", json::array({{{"nodes", json::array({0})}}})},
  };
}

fs::path save(const json& doc, const std::string& name) {
  const fs::path p = scratch(name);
  write(p, doc.dump());
  return p;
}

std::string load_error(const fs::path& p, const lodgen::LoadOptions& o = {}) {
  return error_of([&] { lodgen::load_scene(p.string(), o); });
}

// --- 1: reads outside the asset folder ------------------------------------------------------

// A secret beside the asset folder, and the asset folder itself.
struct Assets {
  fs::path dir = scratch("uri/assets"), secret = scratch("uri/secret/x.bin");
  Assets() {
    write(secret, triangle_bytes());  // a well-formed buffer: only the confinement can refuse it
    fs::create_directories(dir);
  }
};

TEST(Confinement, ParentPathIsRefused) {
  Assets a;
  const fs::path p = a.dir / "up.gltf";
  write(p, triangle_gltf("../secret/x.bin").dump());
  EXPECT_NE(load_error(p).find("leaves the asset folder"), std::string::npos) << load_error(p);
}

TEST(Confinement, PercentEscapesAreRefused) {
  Assets a;
  const fs::path p = a.dir / "escaped.gltf";
  write(p, triangle_gltf("%2e%2e/secret/x.bin").dump());
  EXPECT_NE(load_error(p).find("%-escapes"), std::string::npos) << load_error(p);
}

TEST(Confinement, AbsolutePathsAndFileUrlsAreRefused) {
  Assets a;
  const fs::path abs = a.dir / "abs.gltf", url = a.dir / "url.gltf";
  write(abs, triangle_gltf(fs::absolute(a.secret).string()).dump());
  write(url, triangle_gltf("file://" + fs::absolute(a.secret).string()).dump());
  EXPECT_NE(load_error(abs).find("absolute path"), std::string::npos) << load_error(abs);
  EXPECT_NE(load_error(url).find("scheme"), std::string::npos) << load_error(url);
  // Given as a bare file name (relative to the current folder), still refused.
  const fs::path cwd = fs::current_path();
  fs::current_path(a.dir);
  const std::string bare = load_error("abs.gltf");
  fs::current_path(cwd);
  EXPECT_NE(bare.find("absolute path"), std::string::npos) << bare;
}

TEST(Confinement, TheCurrentFolderIsNotSearched) {
  Assets a;
  // only_here.bin exists in the current folder, not beside the glTF.
  const fs::path here = scratch("uri/cwd");
  write(here / "only_here.bin", triangle_bytes());
  const fs::path p = a.dir / "cwd.gltf";
  write(p, triangle_gltf("only_here.bin").dump());
  const fs::path cwd = fs::current_path();
  fs::current_path(here);
  const std::string e = load_error(fs::absolute(p));
  fs::current_path(cwd);
  EXPECT_NE(e.find("only_here.bin"), std::string::npos) << e;
  EXPECT_EQ(e.find("no error"), std::string::npos) << e;
}

TEST(Confinement, SymbolicLinksOutOfTheFolderAreRefused) {
  Assets a;
  fs::create_symlink(fs::absolute(a.secret), a.dir / "link.bin");
  const fs::path p = a.dir / "link.gltf";
  write(p, triangle_gltf("link.bin").dump());
  EXPECT_NE(load_error(p).find("outside the asset folder"), std::string::npos) << load_error(p);
  fs::remove(a.dir / "link.bin");
}

TEST(Confinement, AssetRootWidensTheFolderAndInsideFilesWork) {
  Assets a;
  write(a.dir / "in.bin", triangle_bytes());
  const fs::path inside = a.dir / "inside.gltf", sibling = a.dir / "sibling.gltf";
  write(inside, triangle_gltf("in.bin").dump());
  write(sibling, triangle_gltf("../secret/x.bin").dump());
  EXPECT_EQ(lodgen::load_scene(inside.string()).meshes.at(0).triangle_count(), 1u);
  lodgen::LoadOptions o;
  o.asset_root = a.dir.parent_path().string();  // holds assets/ and secret/
  EXPECT_EQ(lodgen::load_scene(sibling.string(), o).meshes.at(0).triangle_count(), 1u);
  o.asset_root = a.dir.string();
  EXPECT_NE(load_error(sibling, o).find("leaves the asset folder"), std::string::npos);
}

// --- 2: accessor offsets near 2^64 -------------------------------------------------------------

TEST(Overflow, AccessorByteOffsetNear2To64IsRefused) {
  for (const std::uint64_t count : {std::uint64_t(3), std::uint64_t(1) << 40}) {
    json doc = triangle_gltf();
    // byteOffset + (count - 1) * 12 + 12 wraps to a small number in 64 bits.
    doc["accessors"][0]["byteOffset"] = std::numeric_limits<std::uint64_t>::max() - 35;
    doc["accessors"][0]["count"] = count;
    const std::string e = load_error(save(doc, "offset.gltf"));
    EXPECT_NE(e.find("overflows"), std::string::npos) << e;
  }
  json doc = triangle_gltf();
  doc["accessors"][1]["byteOffset"] = std::numeric_limits<std::uint64_t>::max() - 1;
  const std::string e = load_error(save(doc, "index_offset.gltf"));
  EXPECT_NE(e.find("overflows"), std::string::npos) << e;
  EXPECT_EQ(e.find("is out of range"), std::string::npos) << e;  // no heap word in the message
}

// --- 3, 4: node graphs --------------------------------------------------------------------------

json with_nodes(json nodes, json roots) {
  json doc = triangle_gltf();
  doc["nodes"] = std::move(nodes);
  doc["scenes"] = json::array({{{"nodes", std::move(roots)}}});
  return doc;
}

TEST(Nodes, DeepChainIsRefusedByDepthNotByTheStack) {
  json nodes = json::array();
  const int n = 100000;
  for (int i = 0; i < n; ++i)
    nodes.push_back(i + 1 < n ? json{{"children", json::array({i + 1})}} : json{{"mesh", 0}});
  const std::string e = load_error(save(with_nodes(nodes, json::array({0})), "deep.gltf"));
  EXPECT_NE(e.find("max_node_depth"), std::string::npos) << e;
}

TEST(Nodes, CyclesAreRefused) {
  const std::string two = load_error(
      save(with_nodes(json::array({{{"children", {1}}}, {{"children", {0}}, {"mesh", 0}}}), json::array({0})),
           "ab.gltf"));
  const std::string self = load_error(
      save(with_nodes(json::array({{{"children", {0}}, {"mesh", 0}}}), json::array({0})), "aa.gltf"));
  EXPECT_NE(two.find("cycle"), std::string::npos) << two;
  EXPECT_NE(self.find("its own child"), std::string::npos) << self;
  // A cycle no scene names: still found.
  const std::string hidden = load_error(save(
      with_nodes(json::array({{{"mesh", 0}}, {{"children", {2}}}, {{"children", {1}}}}), json::array({0})),
      "hidden.gltf"));
  EXPECT_NE(hidden.find("cycle"), std::string::npos) << hidden;
}

TEST(Nodes, FanOutAndSharedChildrenAreRefused) {
  json repeated = json::array({{{"children", json::array()}}, {{"mesh", 0}}});
  for (int i = 0; i < 64; ++i) repeated[0]["children"].push_back(1);
  const std::string fan = load_error(save(with_nodes(repeated, json::array({0})), "fan.gltf"));
  EXPECT_NE(fan.find("twice"), std::string::npos) << fan;
  // A DAG of 24 levels, two edges each: node k has children k+1 (twice through two parents).
  json dag = json::array();
  for (int k = 0; k < 24; ++k) {
    dag.push_back({{"children", json::array({2 * k + 1, 2 * k + 2})}});
    dag.push_back({{"children", json::array({2 * k + 2})}});
  }
  dag.push_back({{"mesh", 0}});
  const std::string shared = load_error(save(with_nodes(dag, json::array({0})), "dag.gltf"));
  EXPECT_NE(shared.find("two parents"), std::string::npos) << shared;
}

TEST(Nodes, TooManyChildrenAndNodesAreRefused) {
  json nodes = json::array({{{"children", json::array()}}});
  for (int i = 1; i <= 10001; ++i) {
    nodes[0]["children"].push_back(i);
    nodes.push_back({{"mesh", 0}});
  }
  EXPECT_NE(load_error(save(with_nodes(nodes, json::array({0})), "wide.gltf")).find("max_children"),
            std::string::npos);
  lodgen::LoadOptions o;
  o.limits.max_nodes = 100;
  EXPECT_NE(load_error(save(with_nodes(nodes, json::array({0})), "many.gltf"), o).find("max_nodes"),
            std::string::npos);
}

// The walk itself, on a scene built in memory: iterative (a 100 000-deep chain is fine), world
// matrices composed parent * child, and a cycle or shared node refused.
TEST(WorldMatrices, IterativeComposedAndCycleSafe) {
  lodgen::Scene s;
  const int n = 100000;
  s.nodes.resize(n);
  for (int i = 0; i < n; ++i) {
    s.nodes[std::size_t(i)].matrix[12] = 1.0;  // translate x by 1
    if (i + 1 < n) s.nodes[std::size_t(i)].children = {i + 1};
  }
  s.roots = {0};
  const std::vector<lodgen::PlacedNode> placed = lodgen::world_matrices(s);
  ASSERT_EQ(placed.size(), std::size_t(n));
  EXPECT_EQ(placed.back().node, n - 1);
  EXPECT_DOUBLE_EQ(placed.back().world[12], double(n));  // n translations of 1 along x
  // Rotation then translation: parent rotates 90 deg about z, child translates (1, 0, 0): the
  // child's origin lands at (0, 1, 0).
  lodgen::Scene r;
  r.nodes.resize(2);
  r.nodes[0].matrix = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  r.nodes[1].matrix[12] = 1.0;
  r.nodes[0].children = {1};
  r.roots = {0};
  const auto rp = lodgen::world_matrices(r);
  EXPECT_NEAR(rp[1].world[12], 0.0, 1e-12);
  EXPECT_NEAR(rp[1].world[13], 1.0, 1e-12);
  // Skipped subtrees are left out.
  EXPECT_EQ(lodgen::world_matrices(r, [](int id) { return id == 1; }).size(), 1u);
  s.nodes.back().children = {0};  // a cycle
  EXPECT_NE(error_of([&] { lodgen::world_matrices(s); }).find("reached twice"), std::string::npos);
  lodgen::Scene shared;
  shared.nodes.resize(3);
  shared.nodes[0].children = {2};
  shared.nodes[1].children = {2};
  shared.roots = {0, 1};
  EXPECT_NE(error_of([&] { lodgen::world_matrices(shared); }).find("reached twice"), std::string::npos);
}

// --- 5: image bombs ---------------------------------------------------------------------------

std::uint32_t crc32(const std::string& data) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : data) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}

std::string be32(std::uint32_t v) { return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

// A PNG signature and IHDR claiming width x height, 8-bit RGBA: what stbi_info reads. No pixels.
std::string png_header(std::uint32_t width, std::uint32_t height) {
  const std::string body = "IHDR" + be32(width) + be32(height) + std::string("\x08\x06\x00\x00\x00", 5);
  return std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + body + be32(crc32(body));
}

json textured(const std::vector<std::string>& images, int used) {
  json doc = triangle_gltf();
  doc["images"] = json::array();
  for (const std::string& png : images)
    doc["images"].push_back({{"uri", "data:image/png;base64," + base64(png)}});
  if (used >= 0) {
    doc["textures"] = json::array({{{"source", used}}});
    doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    doc["meshes"][0]["primitives"][0]["material"] = 0;
  }
  return doc;
}

TEST(Images, HugeDimensionsAreRefusedFromTheHeader) {
  const std::string e = load_error(save(textured({png_header(12000, 12000)}, 0), "bomb.gltf"));
  EXPECT_NE(e.find("max_image_pixels"), std::string::npos) << e;
  EXPECT_NE(e.find("12000 x 12000"), std::string::npos) << e;
}

TEST(Images, UnusedImagesAreNotDecoded) {
  // Six images no material uses, none decodable: never touched, so the scene loads.
  std::vector<std::string> bombs(6, png_header(12000, 12000));
  const lodgen::Scene s = lodgen::load_scene(save(textured(bombs, -1), "unused.gltf").string());
  EXPECT_EQ(s.meshes.at(0).triangle_count(), 1u);
}

TEST(Images, TotalBytesAreBounded) {
  lodgen::LoadOptions o;
  o.limits.max_total_bytes = 100;  // less than the glTF itself
  EXPECT_NE(load_error(save(triangle_gltf(), "budget.gltf"), o).find("max_total_bytes"), std::string::npos);
}

// --- 6, 7: MSFT_lod levels and JSON depth --------------------------------------------------------

TEST(Limits, MsftLodWithTooManyIdsIsRefusedBeforeAnyWork) {
  json doc = triangle_gltf();
  doc["nodes"].push_back({{"mesh", 0}});
  json ids = json::array();
  for (int i = 0; i < 100000; ++i) ids.push_back(1);
  doc["nodes"][0]["extensions"]["MSFT_lod"]["ids"] = ids;
  const std::string e = load_error(save(doc, "lods.gltf"));
  EXPECT_NE(e.find("max_levels"), std::string::npos) << e;
  EXPECT_NE(e.find("100001 levels"), std::string::npos) << e;
}

TEST(Limits, ChainsNeverHoldMoreLevelsThanAProfile) {
  // A long, narrow strip of 400 triangles: few Hausdorff samples per level, so this stays quick.
  lodgen::Mesh m;
  for (int i = 0; i <= 200; ++i)
    for (int j = 0; j < 2; ++j) {
      const float x = float(i) / 200.0f;
      m.positions.insert(m.positions.end(), {x, 0.01f * float(j), 0.002f * std::sin(40.0f * x)});
    }
  for (std::uint32_t i = 0; i < 200; ++i) {
    const std::uint32_t a = 2 * i, b = a + 1, c = a + 2, d = a + 3;
    m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
  }
  lodgen::ChainOptions o;
  o.ratio = 0.9;  // 0.9^k x 400 stays above 4 triangles for 43 levels
  o.min_triangles = 1;
  EXPECT_EQ(lodgen::build_chain(m, "strip", o).levels.size(), std::size_t(kMaxLevels));
}

TEST(Limits, DeepJsonIsRefusedBeforeParsing) {
  std::string doc = triangle_gltf().dump();
  doc.pop_back();  // the closing brace
  doc += ",\"extras\":" + std::string(100000, '[') + std::string(100000, ']') + "}";
  const fs::path p = scratch("deep_json.gltf");
  write(p, doc);
  const std::string e = load_error(p);
  EXPECT_NE(e.find("max_json_depth"), std::string::npos) << e;
  // Brackets inside strings do not count.
  json ok = triangle_gltf();
  ok["extras"] = {{"text", std::string(1000, '[')}};
  EXPECT_EQ(lodgen::load_scene(save(ok, "brackets.gltf").string()).meshes.size(), 1u);
}

// --- the broader hostile set -------------------------------------------------------------------

TEST(Broader, MalformedAccessorsViewsAndBuffersFailCleanly) {
  struct Case {
    const char* name;
    std::function<void(json&)> edit;
  };
  const std::vector<Case> cases = {
      {"negative count", [](json& d) { d["accessors"][0]["count"] = -1; }},
      {"huge count", [](json& d) { d["accessors"][0]["count"] = 1e19; }},
      {"count past the view", [](json& d) { d["accessors"][0]["count"] = 1000000; }},
      {"sparse",
       [](json& d) {
         d["accessors"][0]["sparse"] = {{"count", 1},
                                        {"indices", {{"bufferView", 1}, {"componentType", 5123}}},
                                        {"values", {{"bufferView", 0}}}};
       }},
      {"bad base64",
       [](json& d) { d["buffers"][0]["uri"] = "data:application/octet-stream;base64,!!!not base64!!!"; }},
      {"byteLength larger than the data", [](json& d) { d["buffers"][0]["byteLength"] = 4000; }},
      {"stride below the element size", [](json& d) { d["bufferViews"][0]["byteStride"] = 4; }},
      {"view past its buffer", [](json& d) { d["bufferViews"][0]["byteOffset"] = 40; }},
      {"view offset near 2^64",
       [](json& d) { d["bufferViews"][0]["byteOffset"] = std::numeric_limits<std::uint64_t>::max() - 8; }},
      {"buffer index out of range", [](json& d) { d["bufferViews"][0]["buffer"] = 7; }},
      {"child index out of range", [](json& d) { d["nodes"][0]["children"] = {5}; }},
      {"negative child", [](json& d) { d["nodes"][0]["children"] = {-1}; }},
      {"nodes not an array",
       [](json& d) {
         d["nodes"] = {{"a", 1}};
       }},
      {"uri not a string", [](json& d) { d["buffers"][0]["uri"] = 5; }},
      {"missing external buffer", [](json& d) { d["buffers"][0]["uri"] = "nope.bin"; }},
  };
  for (const Case& c : cases) {
    json doc = triangle_gltf();
    c.edit(doc);
    const std::string e = load_error(save(doc, "broader.gltf"));
    EXPECT_EQ(e.find("no error"), std::string::npos) << c.name;
    EXPECT_NE(e.find("broader.gltf"), std::string::npos) << c.name << ": " << e;  // names the file
  }
}

TEST(Broader, GlbFramingIsChecked) {
  // A GLB header whose JSON chunk claims to run past the file.
  std::string glb = "glTF" + std::string("\x02\x00\x00\x00", 4) + std::string("\x40\x00\x00\x00", 4) +
                    std::string("\xff\xff\xff\x00", 4) + "JSON" + std::string(44, ' ');
  const fs::path p = scratch("framing.glb");
  write(p, glb);
  EXPECT_NE(load_error(p).find("GLB"), std::string::npos) << load_error(p);
}

// --- 8, 9, 16, 18: files ---------------------------------------------------------------------

TEST(Files, NonRegularFilesAreNotReadNorReplaced) {
  const fs::path fifo = scratch("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // read_file returns at once: opened non-blocking.
  EXPECT_NE(error_of([&] { io::read_file(fifo.string()); }).find("FIFO"), std::string::npos);
  EXPECT_NE(error_of([&] { io::read_file(scratch("").string()); }).find("directory"), std::string::npos);
  EXPECT_NE(error_of([&] { io::write_file_atomically(fifo.string(), "x"); }).find("refusing to replace"),
            std::string::npos);
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));  // still the FIFO
  EXPECT_NE(error_of([&] { io::check_output("/dev/null", {}); }).find("not a regular file"),
            std::string::npos);
  // A glTF uri naming a FIFO: refused without waiting.
  write(scratch("fifo.gltf"), triangle_gltf("fifo").dump());
  EXPECT_NE(load_error(scratch("fifo.gltf")).find("FIFO"), std::string::npos)
      << load_error(scratch("fifo.gltf"));
}

// SIGTERM while the temporary exists: it is delivered only after the temporary was renamed, so
// nothing is left behind. The parent waits until the temporary is there, then signals.
TEST(Files, SignalDuringAWriteLeavesNoTemporary) {
  const fs::path dir = scratch("signal");
  fs::create_directories(dir);
  const fs::path target = dir / "big.bin";
  auto temporaries = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir))
      n += e.path().filename().string().find(".tmp.") != std::string::npos;
    return n;
  };
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string bytes(std::size_t(64) << 20, 'x');
    io::write_file_atomically(target.string(), bytes);
    ::_exit(0);
  }
  bool seen = false;
  for (int i = 0; i < 200000 && !seen; ++i) {
    seen = temporaries() > 0;
    if (!seen) ::usleep(50);
  }
  ::kill(child, SIGTERM);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(seen) << "the temporary never appeared";
  EXPECT_EQ(temporaries(), 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);  // delivered, after the write
  EXPECT_EQ(fs::file_size(target), std::uintmax_t(64) << 20);
}

TEST(Files, OutputMustNotBeAnInput) {
  const fs::path in = scratch("in.glb"), link = scratch("hard.glb");
  write(in, "x");
  fs::remove(link);
  fs::create_hard_link(in, link);
  EXPECT_NE(error_of([&] { io::check_output(in.string(), {in.string()}); }).find("is the input"),
            std::string::npos);
  EXPECT_NE(error_of([&] { io::check_output(link.string(), {in.string()}); }).find("is the input"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              io::check_output(scratch("x.off").string(), {}, {".glb", ".gltf"});
            }).find("must end in"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              io::check_output((scratch("") / "no/such/dir/x.glb").string(), {});
            }).find("does not exist"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { io::check_output(scratch("fresh.GLB").string(), {in.string()}, {".glb"}); }),
            "no error");
}

TEST(Files, NanReferenceHeightIsRefusedNotWrittenAsNull) {
  lodgen::LodObject o;
  o.name = "tri";
  const lodgen::Mesh tri = lodgen::load_scene(save(triangle_gltf(), "tri.gltf").string()).meshes[0];
  o.chain.levels = {{tri, 1, 0.0, 0.0}, {tri, 1, 0.1, 0.0}};
  lodgen::GltfWriteOptions w;
  w.reference_height = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(error_of([&] {
              lodgen::write_lod_gltf(scratch("nan.glb").string(), {o}, {}, w);
            }).find("reference height"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(scratch("nan.glb")));
}

// --- 17: a byte order mark in a CSV track ------------------------------------------------------

TEST(Tracks, Utf8ByteOrderMarkIsAccepted) {
  const sim::Table t = sim::parse_table("\xEF\xBB\xBFt,x,y,z\n0,0,0,-1\n1,0,0,-1\n", "gaze.csv", false);
  EXPECT_EQ(t.column("t", true), 0);
  EXPECT_EQ(t.rows.size(), 2u);
}

// --- 10, 14, 15 and all-or-nothing: the C ABI -------------------------------------------------

struct CScheduler {
  acuity_scheduler* s = nullptr;
  std::vector<std::uint64_t> bytes;
  std::size_t size = 0;
  explicit CScheduler(std::uint32_t max_objects) {
    acuity_config c;
    acuity_config_default(&c);
    c.max_objects = max_objects;
    EXPECT_EQ(acuity_create(&c, &s), ACUITY_OK);
    const Blob blob = spectra::encode_profile(acuity::testing::small_profile());
    bytes = blob.storage;
    size = blob.size;
  }
  ~CScheduler() { acuity_destroy(s); }
};

TEST(CAbi, ProfileSizesThatCannotBeAProfileFailCleanly) {
  CScheduler c(4);
  std::int32_t index = -7;
  EXPECT_EQ(acuity_load_profile(c.s, c.bytes.data(), SIZE_MAX, &index), ACUITY_BAD_PROFILE);
  EXPECT_NE(std::string(acuity_last_error()).find("size"), std::string::npos);
  EXPECT_EQ(acuity_load_profile(c.s, c.bytes.data(), 0, &index), ACUITY_BAD_PROFILE);
  EXPECT_EQ(acuity_load_profile(c.s, c.bytes.data(), 7, &index), ACUITY_BAD_PROFILE);
  EXPECT_EQ(index, -7);
  EXPECT_EQ(acuity_load_profile(c.s, c.bytes.data(), c.size, &index), ACUITY_OK) << acuity_last_error();
  EXPECT_EQ(index, 0);
}

TEST(CAbi, AddObjectsIsAllOrNothing) {
  CScheduler c(3);
  std::int32_t p = -1;
  ASSERT_EQ(acuity_load_profile(c.s, c.bytes.data(), c.size, &p), ACUITY_OK) << acuity_last_error();
  const double pos[9] = {0, 0, -5, 1, 0, -5, 2, 0, -5};
  const float rot[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::uint32_t ids[3] = {99, 99, 99};
  const std::int32_t bad[2] = {0, 5};
  EXPECT_EQ(acuity_add_objects(c.s, 2, bad, pos, 0, rot, 0, nullptr, ids), ACUITY_INVALID_ARGUMENT);
  EXPECT_NE(std::string(acuity_last_error()).find("profiles[1]"), std::string::npos) << acuity_last_error();
  const std::int32_t negative[1] = {-1};
  EXPECT_EQ(acuity_add_objects(c.s, 1, negative, pos, 0, rot, 0, nullptr, ids), ACUITY_INVALID_ARGUMENT);
  // Nothing was added: all three slots are still free.
  const std::int32_t good[3] = {0, 0, 0};
  ASSERT_EQ(acuity_add_objects(c.s, 3, good, pos, 0, rot, 0, nullptr, ids), ACUITY_OK) << acuity_last_error();
  std::uint32_t more = 99;
  EXPECT_EQ(acuity_add_objects(c.s, 1, good, pos, 0, rot, 0, nullptr, &more), ACUITY_FULL);
  EXPECT_EQ(more, 99u);
  // Remove with one stale id removes nothing; then stale ids are INVALID_ARGUMENT everywhere.
  const std::uint32_t mixed[2] = {ids[0], 12345};
  EXPECT_EQ(acuity_remove_objects(c.s, 2, mixed), ACUITY_INVALID_ARGUMENT);
  std::uint8_t levels[3];
  EXPECT_EQ(acuity_get_levels(c.s, 3, ids, levels, nullptr), ACUITY_OK);
  ASSERT_EQ(acuity_remove_objects(c.s, 1, ids), ACUITY_OK);
  EXPECT_EQ(acuity_remove_objects(c.s, 1, ids), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_set_transforms(c.s, 1, ids, pos, 0, rot, 0, nullptr), ACUITY_INVALID_ARGUMENT);
  const float v[3] = {0, 0, 0};
  EXPECT_EQ(acuity_set_velocities(c.s, 1, ids, v, 0), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_get_levels(c.s, 1, ids, levels, nullptr), ACUITY_INVALID_ARGUMENT);
  const std::uint32_t twice[2] = {ids[1], ids[1]};
  EXPECT_EQ(acuity_remove_objects(c.s, 2, twice), ACUITY_INVALID_ARGUMENT);
  // One slot is free again: exactly one more object fits.
  EXPECT_EQ(acuity_add_objects(c.s, 1, good, pos, 0, rot, 0, nullptr, &more), ACUITY_OK);
  EXPECT_EQ(acuity_add_objects(c.s, 1, good, pos, 0, rot, 0, nullptr, &more), ACUITY_FULL);
}

TEST(CAbi, UpdateRangeBeforeBeginFrameIsAnError) {
  CScheduler c(2);
  std::int32_t p = -1;
  ASSERT_EQ(acuity_load_profile(c.s, c.bytes.data(), c.size, &p), ACUITY_OK);
  const double pos[3] = {0, 0, -5};
  const float rot[4] = {0, 0, 0, 1};
  std::uint32_t id = 0;
  ASSERT_EQ(acuity_add_objects(c.s, 1, &p, pos, 0, rot, 0, nullptr, &id), ACUITY_OK);
  EXPECT_EQ(acuity_update_range(c.s, 0, 1), ACUITY_INVALID_ARGUMENT);
  EXPECT_NE(std::string(acuity_last_error()).find("acuity_begin_frame"), std::string::npos)
      << acuity_last_error();
  EXPECT_EQ(acuity_end_frame(c.s), ACUITY_INVALID_ARGUMENT);
  acuity_eye eye;
  acuity_eye_default(&eye);
  ASSERT_EQ(acuity_begin_frame(c.s, &eye, 1, 1.0f / 90), ACUITY_OK);
  EXPECT_EQ(acuity_update_range(c.s, 0, 1), ACUITY_OK);
  EXPECT_EQ(acuity_end_frame(c.s), ACUITY_OK);
}

}  // namespace
