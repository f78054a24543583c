// lodgen's shading-aware parts: crease splitting, the bounded two-way deviation (positions and
// shading normals) against analytic answers, and fandisk's known case: a level whose Hausdorff
// error is tiny while its normals change, caught by the normal deviation and avoided by the default.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <set>
#include <string>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/gltf.hpp"

using namespace acuity::lodgen;
namespace fs = std::filesystem;

namespace {
// A closed axis-aligned cube of side `s`: 8 shared vertices, 12 triangles, outward.
Mesh cube(float s = 1) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.insert(m.positions.end(),
                       {s * float(i & 1), s * float((i >> 1) & 1), s * float((i >> 2) & 1)});
  m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
               2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return m;
}

// The unit square in z = 0, n x n cells, two triangles each; normals +z.
Mesh grid(int n, float z = 0) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.positions.insert(m.positions.end(), {float(i) / float(n), float(j) / float(n), z});
      m.normals.insert(m.normals.end(), {0, 0, 1});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto v = std::uint32_t(j * (n + 1) + i), w = std::uint32_t(n + 1);
      m.indices.insert(m.indices.end(), {v, v + 1, v + w + 1, v, v + w + 1, v + w});
    }
  return m;
}
}  // namespace

TEST(SplitCreases, CubeSplitsEveryCornerIntoThreeAxisNormals) {
  const Mesh s = split_creases(cube(), 45);
  EXPECT_EQ(s.vertex_count(), 24u);  // 8 corners x 3 faces meeting at 90 degrees
  EXPECT_EQ(s.triangle_count(), 12u);
  for (std::size_t v = 0; v < s.vertex_count(); ++v) {
    int axis = 0;  // exactly one component is +-1
    for (int k = 0; k < 3; ++k) axis += std::abs(std::abs(s.normals[3 * v + k]) - 1) < 1e-6f;
    EXPECT_EQ(axis, 1) << v;
  }
  // Above the cube's 90 degrees: one smooth vertex per corner, normal along the diagonal.
  const Mesh smooth = split_creases(cube(), 100);
  EXPECT_EQ(smooth.vertex_count(), 8u);
  EXPECT_NEAR(std::abs(smooth.normals[0]), 1 / std::sqrt(3.0f), 0.2f);  // area weights differ per corner
  EXPECT_EQ(split_creases(cube(), 180).vertex_count(), 8u);
  // A flat grid has no crease: nothing splits.
  EXPECT_EQ(split_creases(grid(4), 1).vertex_count(), grid(4).vertex_count());
}

TEST(Deviation, OffsetPlaneIsExactAndNormalsAreCompared) {
  const Mesh a = grid(8), b = grid(3, 0.1f);
  const Deviation d = deviation(a, b);
  EXPECT_NEAR(d.hausdorff, 0.1, 1e-6);
  EXPECT_NEAR(d.normal_degrees, 0, 1e-3);
  EXPECT_TRUE(d.complete);
  EXPECT_GT(d.samples, 100u);
  // Tilt b's shading normals by 30 degrees about x: every sample sees 30 degrees.
  Mesh tilted = b;
  for (std::size_t v = 0; v < tilted.vertex_count(); ++v) {
    tilted.normals[3 * v + 1] = -std::sin(float(std::numbers::pi) / 6);
    tilted.normals[3 * v + 2] = std::cos(float(std::numbers::pi) / 6);
  }
  const Deviation t = deviation(a, tilted);
  EXPECT_NEAR(t.normal_degrees, 30, 0.01);
  EXPECT_NEAR(t.normal_p99_degrees, 30, 0.01);
  // One side longer than the other: the Hausdorff distance is the uncovered overhang (0.5).
  Mesh wide = grid(2);
  for (std::size_t v = 0; v < wide.vertex_count(); ++v) wide.positions[3 * v] *= 1.5f;
  EXPECT_NEAR(deviation(a, wide).hausdorff, 0.5, 0.01);
}

TEST(Deviation, BoundedWhateverTheUnitsAndTessellation) {
  // The same shapes in kilometres-as-millimetres: the spacing follows the size, so the sample
  // count and the relative answer do not change.
  Mesh a = grid(8), b = grid(3, 0.1f);
  const Deviation unit = deviation(a, b);
  for (float& x : a.positions) x *= 1e6f;
  for (float& x : b.positions) x *= 1e6f;
  const Deviation big = deviation(a, b);
  EXPECT_EQ(big.samples, unit.samples);
  EXPECT_NEAR(big.hausdorff / 1e6, unit.hausdorff, 1e-6);
  // A fine grid with a small budget: the sample cap holds (vertices strided, faces re-spaced).
  const Mesh fine = grid(300);  // 180000 triangles, 90601 vertices
  DeviationOptions o;
  o.max_samples = 20000;
  const Deviation capped = deviation(fine, grid(3, 0.1f), o);
  EXPECT_LE(capped.samples, 2 * o.max_samples + 4);
  EXPECT_NEAR(capped.hausdorff, 0.1, 1e-6);
  // A tiny spacing on it would mean billions of samples: the time cap stops it and says so.
  o.max_samples = std::size_t(-1) / 4;
  o.spacing = 1e-9;
  o.max_seconds = 0.2;
  const auto t0 = std::chrono::steady_clock::now();
  const Deviation cut = deviation(fine, fine, o);
  EXPECT_FALSE(cut.complete);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
            30.0);  // generous: 2 x 0.2 s plus setup
}

// fandisk (CAD, sharp creases): with smooth normals, a CGAL level with a Hausdorff error of a few
// 1e-5 diameters still moves its shading normals by tens of degrees (the 9.3x case); the
// default chain (crease split, meshopt keeping creases) keeps them within a few degrees.
TEST(Chain, FandiskNormalDeviationCatchesWhatHausdorffMisses) {
  const fs::path path = fs::path(ACUITY_MESH_DIR) / "fandisk.off";
  ASSERT_TRUE(fs::exists(path)) << "missing " << path << ": install libcgal-demo";
  const Mesh fandisk = load_mesh(path.string());
  ChainOptions old;
  old.levels = 3;
  old.decimate.backend = Backend::CgalGarlandHeckbert;
  old.decimate.crease_degrees = 180;  // smooth normals, as lodgen drew them before
  const Chain smooth = build_chain(fandisk, "fandisk", old);
  ASSERT_EQ(smooth.levels.size(), 3u);
  EXPECT_LT(smooth.levels[1].hausdorff, 1e-4);
  EXPECT_GT(smooth.levels[1].normal_deviation, 20);
  ChainOptions now;
  now.levels = 3;
  const Chain sharp = build_chain(fandisk, "fandisk", now);
  ASSERT_EQ(sharp.levels.size(), 3u);
  EXPECT_LT(sharp.levels[1].hausdorff, 1e-3);
  EXPECT_LT(sharp.levels[1].normal_deviation, 5);
  EXPECT_LT(sharp.levels[2].normal_deviation, 8);
  for (std::size_t k = 1; k < sharp.levels.size(); ++k) {
    EXPECT_GE(sharp.levels[k].normal_deviation, sharp.levels[k - 1].normal_deviation);
    EXPECT_GE(sharp.levels[k].normal_deviation_max, sharp.levels[k].normal_deviation);
    EXPECT_TRUE(sharp.levels[k].measured_fully);
  }
}

// The meshopt chain decimates level 0 keeping its seams until that is rejected (on elephant at
// level 3: over 1% flipped triangles), then level 0 welded, as decimate() does; the later levels
// continue from the previous welded level, which costs about their input's size instead of two
// decimations of level 0 (bench_lodgen), and no accuracy: every level is as close to level 0 as
// decimating level 0 to its size directly.
TEST(Chain, MeshoptLevelsContinueTheWeldedLevelOnceRejectedAtNoLoss) {
  const fs::path path = fs::path(ACUITY_MESH_DIR) / "elephant.off";
  ASSERT_TRUE(fs::exists(path)) << "missing " << path << ": install libcgal-demo";
  ChainOptions o;
  o.levels = 5;
  const Chain c = build_chain(load_mesh(path.string()), "elephant", o);
  ASSERT_EQ(c.levels.size(), 5u);
  const auto positions = [](const Mesh& m) {
    std::set<std::array<float, 3>> p;
    for (std::size_t v = 0; v < m.vertex_count(); ++v)
      p.insert({m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]});
    return p;
  };
  DeviationOptions measure;
  measure.spacing = c.diameter / 250;  // as build_chain measures
  double hausdorff = 0, normal = 0;
  for (std::size_t k = 1; k < c.levels.size(); ++k) {
    const Mesh& level = c.levels[k].mesh;
    const Mesh direct = decimate(c.levels[0].mesh, c.levels[k].target_triangles);
    if (k <= 3) {
      EXPECT_EQ(level.indices, direct.indices) << "level " << k;
    } else {
      const auto finer = positions(c.levels[k - 1].mesh);
      for (const auto& p : positions(level)) EXPECT_TRUE(finer.count(p)) << "level " << k;
    }
    EXPECT_LE(level.triangle_count(), c.levels[k].target_triangles + c.levels[k].target_triangles / 20 + 2);
    const Deviation d = deviation(c.levels[0].mesh, direct, measure);
    ASSERT_TRUE(d.complete && c.levels[k].measured_fully);
    hausdorff = std::max(hausdorff, d.hausdorff / c.diameter);  // made non-decreasing, as the chain's
    normal = std::max(normal, d.normal_p99_degrees);
    EXPECT_LE(c.levels[k].hausdorff, hausdorff * 1.0001) << "level " << k;
    EXPECT_LE(c.levels[k].normal_deviation, normal * 1.0001) << "level " << k;
    std::printf("level %zu: chain %.5f / %.1f deg, level 0 decimated %.5f / %.1f deg\n", k,
                c.levels[k].hausdorff, c.levels[k].normal_deviation, hausdorff, normal);
  }
}

// The normal deviation travels beside the geometric error in lodgen's glTF extras.
TEST(Gltf, WritesNormalDeviationBesideGeometricError) {
  LodObject obj;
  obj.name = "grid";
  obj.chain.levels.push_back({grid(4), 0, 0.0, 0.0, 0.0, true, 0.0});
  obj.chain.levels.push_back({grid(2), 0, 0.01, 12.5, 20.0, true, 0.0});
  const fs::path path = fs::temp_directory_path() / "acuity_lodgen_shading_test.gltf";
  GltfWriteOptions wo;
  wo.binary = false;
  write_lod_gltf(path.string(), {obj}, {}, wo);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = text.find("\"acuity_normal_deviation\"");
  ASSERT_NE(at, std::string::npos);
  EXPECT_NE(text.find("12.5", at), std::string::npos);
  EXPECT_NE(text.find("\"acuity_geometric_error\""), std::string::npos);
  fs::remove(path);
}
