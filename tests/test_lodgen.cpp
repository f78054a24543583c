// lodgen: validation and repair on crafted meshes, chains on real meshes (Debian's libcgal-demo),
// the glTF round trip, OpenSubdiv refinement and bad input of every format.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "acuity/file.hpp"
#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/formats.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "acuity/lodgen/refine.hpp"
#include "acuity/lodgen/repair.hpp"

using namespace acuity::lodgen;
namespace fs = std::filesystem;

namespace {
const fs::path kMeshes = ACUITY_MESH_DIR;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "acuity_lodgen_test";
  fs::create_directories(dir);
  return dir / name;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// Two triangles sharing an edge, plus whatever the test adds.
Mesh quad() {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

// The sanitizer run sets ACUITY_QUICK_TESTS: the robustness tests run there, the long real-mesh
// chains only in the plain build.
#define SKIP_IF_QUICK() \
  if (std::getenv("ACUITY_QUICK_TESTS")) GTEST_SKIP() << "long test: run in the plain build"

Mesh real(const char* name) {
  if (!fs::exists(kMeshes / name))
    ADD_FAILURE() << "missing " << (kMeshes / name) << ": install libcgal-demo";
  return load_mesh((kMeshes / name).string());
}
}  // namespace

TEST(Validate, CountsEveryProblem) {
  EXPECT_TRUE(validate(quad()).clean());
  EXPECT_EQ(validate(quad()).border_edges, 4u);
  Mesh m = quad();
  m.positions.insert(m.positions.end(), {0, 0, 0, NAN, 0, 0, 0.5f, 0.5f, 1});  // 4: duplicate of 0; 5: NaN; 6
  m.indices.insert(m.indices.end(), {0, 1, 1,                                  // degenerate (repeated vertex)
                                     0, 2, 9,                                  // index out of range
                                     1, 2, 5,    // uses the NaN vertex: dropped, not counted twice
                                     0, 1, 6,    // 0-1 now used twice the same way: misoriented
                                     1, 0, 6});  // and 0-1 a third time: non-manifold edge
  const MeshReport r = validate(m);
  EXPECT_EQ(r.nonfinite_vertices, 1u);
  EXPECT_EQ(r.duplicate_vertices, 1u);
  EXPECT_EQ(r.degenerate_triangles, 1u);
  EXPECT_EQ(r.bad_indices, 1u);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_GE(r.misoriented_edges, 1u);
  EXPECT_FALSE(r.clean());
  EXPECT_NE(r.summary().find("degenerate"), std::string::npos);
  // Two fans touching at one vertex: a non-manifold vertex.
  Mesh bowtie;
  bowtie.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
  bowtie.indices = {0, 1, 2, 0, 3, 4};
  EXPECT_EQ(validate(bowtie).non_manifold_vertices, 1u);
  EXPECT_FALSE(validate(Mesh{}).clean());
}

TEST(Repair, MakesACleanMeshOrSaysWhy) {
  Mesh m = quad();
  m.positions.insert(m.positions.end(), {NAN, 0, 0, 1, 0, 0});  // 4: NaN, 5: duplicate of 1
  m.indices = {0, 1, 2, 0, 3, 2, /*flipped*/ 0, 2, 4 /*NaN*/, 0, 0, 3 /*degenerate*/, 5, 2, 0};
  MeshReport before;
  const Mesh r = repair(m, "test mesh", &before);
  EXPECT_FALSE(before.clean());
  const MeshReport after = validate(r);
  EXPECT_EQ(
      after.nonfinite_vertices + after.degenerate_triangles + after.bad_indices + after.misoriented_edges, 0u)
      << after.summary();
  EXPECT_GE(r.triangle_count(), 2u);
  EXPECT_EQ(r.normals.size(), r.positions.size());
  Mesh hopeless;
  hopeless.positions = {NAN, 0, 0, 1, 0, 0, 0, 1, 0};
  hopeless.indices = {0, 1, 2};
  try {
    repair(hopeless, "hopeless.off");
    FAIL() << "expected InputError";
  } catch (const InputError& e) { EXPECT_NE(std::string(e.what()).find("hopeless.off"), std::string::npos); }
}

TEST(Chain, RealMeshesBothBackends) {
  SKIP_IF_QUICK();
  for (const char* name : {"elephant.off", "fandisk.off"})
    for (Backend b :
         {Backend::Meshopt, Backend::OpenMesh, Backend::CgalGarlandHeckbert, Backend::CgalLindstromTurk}) {
      ChainOptions o;
      o.levels = 5;
      o.decimate.backend = b;
      const Chain c = build_chain(real(name), name, o);
      ASSERT_EQ(c.levels.size(), 5u) << name;
      EXPECT_GT(c.diameter, 0);
      for (std::size_t k = 0; k < c.levels.size(); ++k) {
        const Level& l = c.levels[k];
        const double target = double(l.target_triangles);
        EXPECT_LE(std::abs(double(l.mesh.triangle_count()) - target), 0.02 * target)
            << name << " " << to_string(b) << " level " << k;
        if (k) {
          EXPECT_GE(l.hausdorff, c.levels[k - 1].hausdorff);
          EXPECT_GT(l.hausdorff, 0);
        }
        EXPECT_EQ(l.mesh.normals.size(), l.mesh.positions.size());
        EXPECT_TRUE(validate(l.mesh).nonfinite_vertices == 0);
      }
      EXPECT_LT(c.levels.back().hausdorff, 0.2);  // 1/16 of the triangles stays recognisable
    }
}

TEST(Chain, ErrorBudgetAndLockedBorder) {
  SKIP_IF_QUICK();
  ChainOptions o;
  o.max_error = 0.01;
  const Chain c = build_chain(real("elephant.off"), "elephant", o);
  ASSERT_GE(c.levels.size(), 2u);
  EXPECT_LE(c.levels.back().hausdorff, 0.01);
  // A mesh with a border: locked border vertices do not move.
  const Mesh open = real("elephant-with-holes.off");
  ChainOptions lo;
  lo.levels = 3;
  lo.decimate.lock_border = true;
  for (Backend b : {Backend::Meshopt, Backend::OpenMesh, Backend::CgalGarlandHeckbert}) {
    lo.decimate.backend = b;
    const Chain lc = build_chain(open, "elephant-with-holes", lo);
    using P = std::array<float, 3>;
    std::set<P> before, after;
    const Mesh& m0 = lc.levels[0].mesh;  // split at creases: edges are told apart by position
    auto at = [&](std::uint32_t v) {
      return P{m0.positions[3 * v], m0.positions[3 * v + 1], m0.positions[3 * v + 2]};
    };
    std::map<std::pair<P, P>, int> edges;
    for (std::size_t t = 0; t < m0.indices.size(); t += 3)
      for (int e = 0; e < 3; ++e) {
        const P a = at(m0.indices[t + e]), bb = at(m0.indices[t + (e + 1) % 3]);
        ++edges[{std::min(a, bb), std::max(a, bb)}];
      }
    for (const auto& [e, n] : edges)
      if (n == 1) before.insert({e.first, e.second});
    const Mesh& last = lc.levels.back().mesh;
    for (std::size_t v = 0; v < last.vertex_count(); ++v)
      after.insert({last.positions[3 * v], last.positions[3 * v + 1], last.positions[3 * v + 2]});
    ASSERT_GT(before.size(), 10u);
    for (const auto& p : before) EXPECT_TRUE(after.count(p)) << to_string(b);
  }
}

TEST(Gltf, RoundTripKeepsLevelsCountsAndAttributes) {
  ChainOptions o;
  o.levels = 4;
  const Chain c = build_chain(real("elephant.off"), "elephant", o);
  LodObject obj;
  obj.name = "elephant";
  obj.matrix[12] = 3;  // translated
  obj.chain = c;
  Material red;
  red.name = "red";
  red.base_color[0] = 0.9f;
  red.width = red.height = 2;
  red.pixels = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  obj.material = 0;
  for (Level& l : obj.chain.levels) {  // texture coordinates too
    l.mesh.texcoords.assign(l.mesh.vertex_count() * 2, 0.25f);
    l.mesh.material = 0;
  }
  for (const char* file : {"round.glb", "round.gltf"}) {
    const fs::path path = scratch(file);
    GltfWriteOptions wo;
    wo.binary = std::string(file).ends_with(".glb");
    write_lod_gltf(path.string(), {obj}, {red}, wo);
    const Scene s = load_scene(path.string());
    ASSERT_EQ(s.roots.size(), 1u);
    const Node& top = s.nodes[s.roots[0]];
    ASSERT_EQ(top.lods.size(), 3u);
    EXPECT_EQ(top.matrix[12], 3.0);
    std::vector<double> errors;
    for (const Level& l : obj.chain.levels) errors.push_back(l.hausdorff);
    const std::vector<double> expected = screen_coverage(errors, 1080);
    ASSERT_EQ(top.screen_coverage.size(), 4u);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(top.screen_coverage[k], expected[k], 1e-12);
    for (int k = 0; k < 4; ++k) {
      const Node& n = s.nodes[k == 0 ? s.roots[0] : top.lods[k - 1]];
      const Mesh& m = s.meshes[n.mesh];
      const Mesh& written = obj.chain.levels[std::size_t(k)].mesh;
      EXPECT_EQ(m.triangle_count(), written.triangle_count());
      EXPECT_EQ(m.positions, written.positions);
      EXPECT_EQ(m.indices, written.indices);
      EXPECT_EQ(m.normals, written.normals);
      EXPECT_EQ(m.texcoords, written.texcoords);
      EXPECT_EQ(m.material, 0);
    }
    // chain_of_node reads the chain back: the same meshes and errors.
    const Chain back = chain_of_node(s, top);
    ASSERT_EQ(back.levels.size(), obj.chain.levels.size());
    for (std::size_t k = 0; k < back.levels.size(); ++k) {
      EXPECT_EQ(back.levels[k].mesh.positions, obj.chain.levels[k].mesh.positions);
      EXPECT_EQ(back.levels[k].hausdorff, obj.chain.levels[k].hausdorff);
      EXPECT_EQ(back.levels[k].target_triangles, obj.chain.levels[k].mesh.triangle_count());
    }
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].pixels, red.pixels);
    EXPECT_FLOAT_EQ(s.materials[0].base_color[0], 0.9f);
  }
  // Coverage: level k takes over where its error covers one pixel; non-increasing, last 0.
  const std::vector<double> cov = screen_coverage({0, 0.01, 0.04}, 1000);
  EXPECT_DOUBLE_EQ(cov[0], 0.1);
  EXPECT_DOUBLE_EQ(cov[1], 0.025);
  EXPECT_EQ(cov[2], 0.0);
}

// The errors come back exactly whatever reference height the coverage was written for; a node from
// another writer (coverage only) is inverted at the default height.
TEST(Gltf, GeometricErrorsSurviveAnyReferenceHeight) {
  LodObject obj;
  obj.name = "tri";
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  m.indices = {0, 1, 2};
  const std::vector<double> errors = {0, 0.003, 0.02};
  for (double e : errors) obj.chain.levels.push_back({m, 1, e, 0});
  GltfWriteOptions wo;
  wo.reference_height = 720;
  const fs::path path = scratch("heights.glb");
  write_lod_gltf(path.string(), {obj}, {}, wo);
  Node top = load_scene(path.string()).nodes[0];
  EXPECT_EQ(lod_geometric_errors(top, 3), errors);
  top.geometric_error.clear();  // as another writer leaves it
  top.screen_coverage = screen_coverage(errors, GltfWriteOptions{}.reference_height);
  const std::vector<double> inverted = lod_geometric_errors(top, 3);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(inverted[k], errors[std::size_t(k)], 1e-12);
}

TEST(Refine, OpenSubdivCounts) {
  SKIP_IF_QUICK();
  const fs::path cube = scratch("cube.off");
  write(cube,
        "OFF\n8 6 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
        "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n");
  const std::vector<Mesh> cc = refine(load_polygon_mesh(cube.string()), 2);  // Catmull-Clark
  ASSERT_EQ(cc.size(), 3u);
  EXPECT_EQ(cc[0].triangle_count(), 96u * 2);
  EXPECT_EQ(cc[1].triangle_count(), 24u * 2);
  EXPECT_EQ(cc[2].triangle_count(), 6u * 2);
  // The limit surface shrinks into the cage: every refined vertex stays inside the unit cube.
  for (float x : cc[0].positions) EXPECT_TRUE(x > 0 && x < 1);
  const Mesh tetra = [] {
    Mesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    m.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    return m;
  }();
  const std::vector<Mesh> loop = refine(to_polygons(tetra), 3);  // Loop
  EXPECT_EQ(loop[0].triangle_count(), 4u * 64);
  const Chain chain = measure_chain(loop);
  EXPECT_EQ(chain.levels.back().mesh.triangle_count(), 4u);
  for (std::size_t k = 1; k < chain.levels.size(); ++k)
    EXPECT_GE(chain.levels[k].hausdorff, chain.levels[k - 1].hausdorff);
}

TEST(BadInput, EveryFormatFailsCleanlyAndNamesTheFile) {
  const std::string off_ok = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  struct Case {
    const char* name;
    std::string text;
  };
  const std::vector<Case> cases = {
      {"truncated.off", off_ok.substr(0, off_ok.size() / 2)},
      {"nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"},
      {"empty.off", "OFF\n0 0 0\n"},
      {"absurd.off", "OFF\n3 1000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"},
      {"garbage.obj", "this is not a mesh\n"},
      {"truncated.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"},
      {"truncated.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"},
      {"garbage.gltf",
       "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": "
       "7}}]}], \"nodes\": [{\"mesh\": 0}]}"},
      {"truncated.glb", std::string("glTF\x02\x00\x00\x00\xff\x00\x00\x00", 12)},
      {"notjson.gltf", "{ nope"},
  };
  for (const Case& c : cases) {
    const fs::path p = scratch(c.name);
    write(p, c.text);
    try {
      const Scene s = load_scene(p.string());
      // Readers that accept the bytes must still hand back something chain-able or be rejected there.
      ChainOptions o;
      o.levels = 2;
      for (const Mesh& m : s.meshes) build_chain(m, c.name, o);
      if (s.meshes.empty()) throw InputError(std::string(c.name) + ": no meshes");
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.name), std::string::npos) << e.what();
      continue;
    }
    ADD_FAILURE() << c.name << " was accepted";
  }
}

// The two mesh readers differ only in where OpenMesh runs: the same mesh, or the same error.
// One registry says which files lodgen reads and how; load_scene picks its reader from it and
// refuses the rest by naming the list.
TEST(Formats, OneRegistryPicksTheReader) {
  EXPECT_EQ(input_format_names(), "OFF, OBJ, PLY, STL, glTF, GLB");
  ASSERT_NE(input_format("a/B.OBJ"), nullptr);
  EXPECT_EQ(input_format("a/B.OBJ")->reader, FormatReader::OpenMesh);
  EXPECT_EQ(input_format("x.glb")->reader, FormatReader::Gltf);
  EXPECT_TRUE(is_gltf("x.GLTF"));
  EXPECT_FALSE(is_gltf("x.off"));
  EXPECT_EQ(input_format("notes.txt"), nullptr);
  const fs::path txt = scratch("notes.txt");
  write(txt, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  try {
    load_scene(txt.string());
    ADD_FAILURE() << "read a .txt";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              txt.string() + ": lodgen reads OFF, OBJ, PLY, STL, glTF, GLB files, not '.txt'");
  }
  // A mesh file over max_file_bytes is refused before OpenMesh opens it.
  const fs::path off = scratch("small.off");
  write(off, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  LoadOptions o;
  o.limits.max_file_bytes = 10;
  try {
    load_scene(off.string(), o);
    ADD_FAILURE() << "read past max_file_bytes";
  } catch (const acuity::io::Error& e) {
    EXPECT_NE(e.reason().find("max_file_bytes (10)"), std::string::npos) << e.what();
  }
}

TEST(BadInput, IsolatedAndInProcessReadersAgree) {
  const std::string off_ok = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::vector<std::pair<std::string, std::string>> files = {
      {"ok.off", off_ok},
      {"quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"},
      {"truncated.off", off_ok.substr(0, off_ok.size() / 2)},
      {"nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"},
      {"absurd.off", "OFF\n3 1000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
      {"garbage.obj", "this is not a mesh\n"},
      {"truncated.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"},
      {"truncated.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"},
  };
  std::vector<std::string> paths;
  for (const auto& [name, text] : files) {
    paths.push_back(scratch(name).string());
    write(paths.back(), text);
  }
  paths.push_back((kMeshes / "elephant.off").string());
  paths.push_back(scratch("missing.off").string());
  int read = 0;
  for (const std::string& path : paths) {
    auto attempt = [&](auto reader, Mesh* out) -> std::string {
      try {
        *out = reader(path);
        return "";
      } catch (const std::runtime_error& e) { return e.what(); }  // InputError, or io::Error (missing.off)
    };
    Mesh here, there;
    const std::string error_here = attempt([](const std::string& p) { return load_mesh(p); }, &here);
    const std::string error_there =
        attempt([](const std::string& p) { return load_mesh_isolated(p); }, &there);
    EXPECT_EQ(error_here, error_there) << path;
    EXPECT_EQ(here.positions, there.positions) << path;
    EXPECT_EQ(here.indices, there.indices) << path;
    if (error_here.empty()) {
      ++read;
      LoadOptions o;
      o.isolate_mesh_reader = false;
      EXPECT_EQ(load_scene(path, o).meshes.at(0).indices, here.indices) << path;
    } else {
      EXPECT_NE(error_here.find(fs::path(path).filename().string()), std::string::npos) << error_here;
    }
  }
  EXPECT_EQ(read, 3);  // ok.off, quad.obj and the elephant; every other file is refused
}

TEST(BadInput, FailedWriteLeavesNothing) {
  const fs::path dir = scratch("nowrite");
  fs::create_directories(dir);
  LodObject obj;
  obj.chain.levels.push_back({quad(), 2, 0, 0});
  EXPECT_THROW(write_lod_gltf((dir / "missing" / "out.glb").string(), {obj}, {}), std::runtime_error);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 0);
}
