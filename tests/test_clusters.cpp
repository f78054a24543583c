// lodgen's cluster hierarchies (acuity/lodgen/clusters.hpp): built on closed real meshes (Debian's
// libcgal-demo), every one of 1000 view-dependent cuts per mesh is crack-free; the hierarchy's
// invariants; the glTF round trip (ACUITY_cluster_hierarchy); and each rule of
// check_cluster_hierarchy, directly and through the file reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <unordered_map>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/clusters.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "cluster_check.hpp"
#include "scratch_dir.hpp"

using namespace acuity::lodgen;
using acuity::testing::scratch;
using namespace acuity::testing;
namespace fs = std::filesystem;

namespace {
const fs::path kMeshes = ACUITY_MESH_DIR;

using Built = BuiltHierarchy;
Built build(const std::string& file) { return built_hierarchy((kMeshes / file).string()); }

// Projected error of a group seen from `eye`: error over the distance to its sphere (infinite inside).
double projected(const ClusterGroup& g, const std::array<double, 3>& eye) {
  const double d = std::hypot(eye[0] - g.center[0], eye[1] - g.center[1], eye[2] - g.center[2]) - g.radius;
  return d > 0 ? g.error / d : INFINITY;
}

// The cut: a cluster is drawn when its own error is below the threshold and its parent's is not.
std::vector<std::uint32_t> cut(const ClusterHierarchy& h, const std::array<double, 3>& eye,
                               double threshold) {
  std::vector<std::uint32_t> drawn;
  for (std::size_t c = 0; c < h.clusters.size(); ++c) {
    const Cluster& k = h.clusters[c];
    const bool own_invisible = k.refined == kNoGroup || projected(h.groups[k.refined], eye) <= threshold;
    const bool parent_visible = k.group == kNoGroup || projected(h.groups[k.group], eye) > threshold;
    if (own_invisible && parent_visible) drawn.push_back(std::uint32_t(c));
  }
  return drawn;
}

double diameter_of(const Mesh& m) { return diameter(m); }

class ClosedMesh : public ::testing::TestWithParam<const char*> {};

}  // namespace

TEST_P(ClosedMesh, ThousandRandomCutsAreCrackFree) {
  const Built b = build(GetParam());
  ASSERT_EQ(check_cluster_hierarchy(b.h, b.mesh.vertex_count()), "");
  const Edges e = edges(b.mesh, b.h);
  std::size_t finest_open = 0;
  for (std::uint8_t n : e.finest_count) finest_open += n == 1;
  EXPECT_EQ(finest_open, 0u) << "the test meshes are closed";
  // Levels of each cluster, to see that cuts mix them.
  std::vector<std::uint32_t> level(b.h.clusters.size(), 0);
  for (std::size_t c = 0; c < level.size(); ++c)
    if (b.h.clusters[c].refined != kNoGroup) level[c] = b.h.groups[b.h.clusters[c].refined].level + 1;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < b.mesh.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], double(b.mesh.positions[i]));
    hi[i % 3] = std::max(hi[i % 3], double(b.mesh.positions[i]));
  }
  const double size = diameter_of(b.mesh);
  std::mt19937 rng(48);
  std::uniform_real_distribution<double> u(0, 1);
  CrackCheck crack_check(e);
  const auto first_crack = [&](const std::vector<std::uint32_t>& drawn) { return crack_check.first(drawn); };
  std::vector<bool> is_drawn(b.h.clusters.size(), false);
  std::size_t mixed = 0, coarser = 0;
  std::map<std::vector<std::uint32_t>, int> cuts_seen;
  for (int view = 0; view < 1000; ++view) {
    // An eye from 0.3 to 10 diameters from the box centre in a random direction; a threshold of
    // 1e-4 .. 1e-1 (projected error in radians, about 0.3 to 340 arcminutes).
    std::array<double, 3> dir = {u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1};
    const double n = std::hypot(dir[0], dir[1], dir[2]) + 1e-12;
    const double dist = size * 0.3 * std::pow(10 / 0.3, u(rng));
    std::array<double, 3> eye;
    for (int k = 0; k < 3; ++k) eye[std::size_t(k)] = (lo[k] + hi[k]) / 2 + dir[std::size_t(k)] / n * dist;
    const double threshold = 1e-4 * std::pow(1000.0, u(rng));
    const std::vector<std::uint32_t> drawn = cut(b.h, eye, threshold);
    ASSERT_FALSE(drawn.empty());
    std::uint32_t min_level = UINT32_MAX, max_level = 0;
    for (std::uint32_t c : drawn) {
      min_level = std::min(min_level, level[c]);
      max_level = std::max(max_level, level[c]);
    }
    const std::uint32_t crack = first_crack(drawn);
    ASSERT_EQ(crack, UINT32_MAX) << GetParam() << ": view " << view << " opens an edge of cluster " << crack
                                 << " (level " << level[crack] << ") that the finest mesh closes";
    // Never a mix: no drawn cluster is drawn together with a member of the group that made it.
    for (std::uint32_t c : drawn) is_drawn[c] = true;
    for (std::uint32_t c : drawn) {
      const std::uint32_t g = b.h.clusters[c].refined;
      if (g == kNoGroup) continue;
      for (std::uint32_t m = b.h.groups[g].first_member;
           m < b.h.groups[g].first_member + b.h.groups[g].member_count; ++m)
        ASSERT_FALSE(is_drawn[m]) << GetParam() << ": view " << view << " draws cluster " << c
                                  << " and cluster " << m << ", which group " << g << " replaced by it";
    }
    for (std::uint32_t c : drawn) is_drawn[c] = false;
    // The check sees a crack: the same cut without one of its clusters has one.
    if (view < 10 && drawn.size() > 1) {
      EXPECT_NE(first_crack(std::vector<std::uint32_t>(drawn.begin() + 1, drawn.end())), UINT32_MAX);
    }
    mixed += min_level != max_level;
    coarser += max_level > 0;
    ++cuts_seen[drawn];
  }
  // The views test something: most cuts leave the finest mesh, many mix levels, and they differ.
  EXPECT_GT(coarser, 500u);
  EXPECT_GT(mixed, 200u);
  EXPECT_GT(cuts_seen.size(), 50u);
}

TEST_P(ClosedMesh, HierarchyInvariants) {
  const Built b = build(GetParam());
  const ClusterHierarchy& h = b.h;
  ASSERT_EQ(check_cluster_hierarchy(h, b.mesh.vertex_count()), "");
  // Cluster sizes.
  for (const Cluster& c : h.clusters) EXPECT_LE(c.triangle_count, kMaxClusterTriangles);
  // The finest clusters are the input mesh's triangles, each once (order aside).
  std::vector<std::array<std::uint32_t, 3>> input, finest;
  const std::vector<std::uint32_t> identity = [&] {
    std::vector<std::uint32_t> v(b.mesh.vertex_count());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::uint32_t(i);
    return v;
  }();
  for (std::size_t t = 0; t < b.mesh.triangle_count(); ++t)
    input.push_back(welded_triangle(identity, &b.mesh.indices[3 * t]));
  for (std::size_t t = 0; t < h.finest_triangles(); ++t)
    finest.push_back(welded_triangle(identity, &h.indices[3 * t]));
  std::sort(input.begin(), input.end());
  std::sort(finest.begin(), finest.end());
  EXPECT_EQ(input, finest);
  // Monotone up the hierarchy (also what check_cluster_hierarchy enforces), and each group's sphere
  // holds its members' vertices.
  for (std::size_t g = 0; g < h.groups.size(); ++g) {
    const ClusterGroup& p = h.groups[g];
    for (std::size_t c = p.first_member; c < std::size_t(p.first_member) + p.member_count; ++c) {
      const Cluster& k = h.clusters[c];
      if (k.refined != kNoGroup) { EXPECT_GE(p.error, h.groups[k.refined].error); }
      for (std::size_t i = 3 * std::size_t(k.first_triangle);
           i < 3 * (std::size_t(k.first_triangle) + k.triangle_count); ++i) {
        const float* v = &b.mesh.positions[3 * std::size_t(h.indices[i])];
        EXPECT_LE(std::hypot(v[0] - p.center[0], v[1] - p.center[1], v[2] - p.center[2]),
                  p.radius * (1 + 1e-5))
            << "group " << g;
      }
    }
  }
  // The root is reached: the clusters in no group hold a small part of the mesh, and errors grow.
  std::size_t root_triangles = 0;
  for (const Cluster& c : h.clusters)
    if (c.group == kNoGroup) root_triangles += c.triangle_count;
  EXPECT_LT(double(root_triangles), 0.1 * double(b.mesh.triangle_count())) << root_triangles;
  EXPECT_GE(h.levels(), 4u);
  EXPECT_GT(h.groups.back().error, 0);
  // Deterministic.
  const ClusterHierarchy again = build_clusters(b.mesh, GetParam());
  EXPECT_EQ(again.indices, h.indices);
  EXPECT_EQ(again.clusters.size(), h.clusters.size());
}

INSTANTIATE_TEST_SUITE_P(Real, ClosedMesh,
                         ::testing::Values("fandisk.off", "camel.off", "armadillo.off", "bunny00.off"));

namespace {

// A small valid hierarchy to break: a sphere-like closed mesh from the test data.
const Built& small() {
  static const Built b = build("elephant.off");
  return b;
}

// The fault check_cluster_hierarchy finds in `h` after `edit`.
template <class Edit>
std::string fault_after(Edit edit) {
  ClusterHierarchy h = small().h;
  edit(h);
  return check_cluster_hierarchy(h, small().mesh.vertex_count());
}

// The first group with a member made by another group, and that member.
std::pair<std::size_t, std::size_t> group_with_child(const ClusterHierarchy& h) {
  for (std::size_t g = 0; g < h.groups.size(); ++g)
    for (std::size_t c = h.groups[g].first_member;
         c < std::size_t(h.groups[g].first_member) + h.groups[g].member_count; ++c)
      if (h.clusters[c].refined != kNoGroup) return {g, c};
  return {0, 0};
}

#define EXPECT_HAS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

}  // namespace

TEST(ClusterCheck, RejectsEachRuleNamingTheGroupOrCluster) {
  ASSERT_EQ(fault_after([](ClusterHierarchy&) {}), "");
  const auto [g, member] = group_with_child(small().h);
  ASSERT_GT(g, 0u);
  const std::uint32_t child = small().h.clusters[member].refined;
  // Errors not monotone.
  std::string f = fault_after([&](ClusterHierarchy& h) { h.groups[g].error = h.groups[child].error * 0.5f; });
  EXPECT_HAS(f, "group " + std::to_string(g) + ": error");
  EXPECT_HAS(f, "must not decrease");
  // A sphere that no longer contains the child's.
  f = fault_after([&](ClusterHierarchy& h) { h.groups[g].radius = h.groups[child].radius * 0.5f; });
  EXPECT_HAS(f, "group " + std::to_string(g) + "'s bounding sphere");
  // Indices leaving the vertices.
  f = fault_after([&](ClusterHierarchy& h) { h.indices[7] = std::uint32_t(small().mesh.vertex_count()); });
  EXPECT_HAS(f, "cluster 0: index");
  // Clusters overlapping, and a gap.
  f = fault_after([](ClusterHierarchy& h) { h.clusters[3].first_triangle -= 1; });
  EXPECT_HAS(f, "cluster 3 overlaps");
  f = fault_after([](ClusterHierarchy& h) { h.clusters[3].first_triangle += 1; });
  EXPECT_HAS(f, "cluster 3 leaves a gap");
  // Offsets whose sums would overflow 32 bits, and triangles past the index array.
  f = fault_after([](ClusterHierarchy& h) {
    h.clusters.back().triangle_count = kMaxClusterTriangles;
    h.indices.resize(h.indices.size() - 3);
  });
  EXPECT_HAS(f, "leave the index array");
  f = fault_after([](ClusterHierarchy& h) { h.groups.back().first_member = 0xFFFFFFF0u; });
  EXPECT_HAS(f, "group " + std::to_string(small().h.groups.size() - 1));
  f = fault_after([](ClusterHierarchy& h) { h.groups.back().member_count = 0xFFFFFFFFu; });
  EXPECT_HAS(f, "leave the");
  // Too many triangles in a cluster, an empty one.
  f = fault_after([](ClusterHierarchy& h) { h.clusters[0].triangle_count = 129; });
  EXPECT_HAS(f, "cluster 0: 129 triangles");
  // References out of range or backwards.
  f = fault_after([](ClusterHierarchy& h) { h.clusters[0].group = 1u << 30; });
  EXPECT_HAS(f, "cluster 0 names group");
  f = fault_after([&](ClusterHierarchy& h) { h.clusters[member].refined = std::uint32_t(g); });
  EXPECT_HAS(f, "cluster " + std::to_string(member) + " was made by group");
  f = fault_after([](ClusterHierarchy& h) { h.clusters[0].group = kNoGroup; });
  EXPECT_HAS(f, "group 0 lists cluster 0");
  // Groups overlapping each other.
  f = fault_after([](ClusterHierarchy& h) { h.groups[1].first_member = h.groups[0].first_member; });
  EXPECT_HAS(f, "group 1's members");
  // Non-finite and negative numbers.
  f = fault_after([](ClusterHierarchy& h) { h.groups[0].error = NAN; });
  EXPECT_HAS(f, "group 0: error");
  f = fault_after([](ClusterHierarchy& h) { h.groups[0].radius = -1; });
  EXPECT_HAS(f, "group 0: radius");
  f = fault_after([](ClusterHierarchy& h) { h.groups[0].center[1] = INFINITY; });
  EXPECT_HAS(f, "group 0: its centre");
  // Levels: wrong, or past the limit.
  f = fault_after([](ClusterHierarchy& h) { h.groups[0].level = 3; });
  EXPECT_HAS(f, "group 0: level 3");
  ClusterLimits tight;
  tight.max_levels = 2;
  EXPECT_HAS(check_cluster_hierarchy(small().h, small().mesh.vertex_count(), tight), "max_levels");
  // Counts past the limits, checked first.
  tight = {};
  tight.max_clusters = 10;
  EXPECT_HAS(check_cluster_hierarchy(small().h, small().mesh.vertex_count(), tight), "max_clusters");
  tight = {};
  tight.max_groups = 1;
  EXPECT_HAS(check_cluster_hierarchy(small().h, small().mesh.vertex_count(), tight), "max_groups");
}

namespace {

// A GLB's JSON and binary chunks.
struct Glb {
  nlohmann::json doc;
  std::string bin;
};
Glb split_glb(const std::string& bytes) {
  std::uint32_t json_length = 0, bin_length = 0;
  std::memcpy(&json_length, bytes.data() + 12, 4);
  std::memcpy(&bin_length, bytes.data() + 20 + json_length, 4);
  return {nlohmann::json::parse(bytes.substr(20, json_length)), bytes.substr(28 + json_length, bin_length)};
}
std::string join_glb(const Glb& g) {
  std::string json = g.doc.dump();
  while (json.size() % 4) json += ' ';
  auto u32 = [](std::uint32_t x) { return std::string(reinterpret_cast<const char*>(&x), 4); };
  const std::uint32_t total = std::uint32_t(12 + 8 + json.size() + 8 + g.bin.size());
  return std::string("glTF") + u32(2) + u32(total) + u32(std::uint32_t(json.size())) + "JSON" + json +
         u32(std::uint32_t(g.bin.size())) + std::string("BIN\0", 4) + g.bin;
}

std::string write_small() {
  LodObject o;
  o.name = "elephant";
  o.chain.levels.push_back({small().mesh, small().mesh.triangle_count(), 0.0, 0.0});
  o.clusters = small().h;
  return encode_lod_gltf({o}, {});
}

std::string load_fault(const Glb& g, const std::string& name) {
  const fs::path p = scratch(name);
  std::ofstream(p, std::ios::binary) << join_glb(g);
  try {
    load_scene(p.string());
  } catch (const InputError& e) { return e.what(); }
  return "";
}

}  // namespace

TEST(ClusterGltf, RoundTripAndTheFinestMeshForOtherReaders) {
  const fs::path p = scratch("elephant_clusters.glb");
  std::ofstream(p, std::ios::binary) << write_small();
  const Scene s = load_scene(p.string());
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.clusters.size(), 1u);
  const ClusterHierarchy& h = s.clusters[0];
  EXPECT_EQ(h.indices, small().h.indices);
  ASSERT_EQ(h.clusters.size(), small().h.clusters.size());
  ASSERT_EQ(h.groups.size(), small().h.groups.size());
  for (std::size_t i = 0; i < h.groups.size(); ++i) {
    EXPECT_EQ(h.groups[i].error, small().h.groups[i].error);
    EXPECT_EQ(h.groups[i].radius, small().h.groups[i].radius);
    EXPECT_EQ(h.groups[i].first_member, small().h.groups[i].first_member);
  }
  // What a reader without the extension draws: the primitive's own indices, the finest clusters.
  EXPECT_EQ(s.meshes[0].indices.size(), 3 * small().mesh.triangle_count());
  EXPECT_EQ(s.meshes[0].positions, small().mesh.positions);
  const Glb g = split_glb(write_small());
  EXPECT_EQ(g.doc["extensionsUsed"].size(), 2u);
  EXPECT_FALSE(g.doc.contains("extensionsRequired"));
}

TEST(ClusterGltf, ReaderRejectsBrokenHierarchiesNamingThem) {
  const Glb good = split_glb(write_small());
  const nlohmann::json& ext =
      good.doc["meshes"][0]["primitives"][0]["extensions"]["ACUITY_cluster_hierarchy"];
  // A group's error lowered below its child's: not monotone.
  {
    Glb g = good;
    const auto [group, member] = group_with_child(small().h);
    (void)member;
    const nlohmann::json& view = g.doc["bufferViews"][ext["groups"].get<int>()];
    const std::size_t at = view.value("byteOffset", 0u) + 32 * group + 16;
    const float zero = 0;
    std::memcpy(&g.bin[at], &zero, 4);
    EXPECT_HAS(load_fault(g, "nonmonotone.glb"), "group " + std::to_string(group) + ": error");
  }
  // Counts past the limits: refused before any record is read.
  {
    Glb g = good;
    g.doc["meshes"][0]["primitives"][0]["extensions"]["ACUITY_cluster_hierarchy"]["clusterCount"] = 1e12;
    EXPECT_HAS(load_fault(g, "count.glb"), "max_clusters");
  }
  // A records view whose length does not match its count.
  {
    Glb g = good;
    g.doc["meshes"][0]["primitives"][0]["extensions"]["ACUITY_cluster_hierarchy"]["groupCount"] =
        ext["groupCount"].get<int>() - 1;
    EXPECT_HAS(load_fault(g, "length.glb"), "groups bufferView holds");
  }
  // A cluster index past the buffer.
  {
    Glb g = good;
    g.doc["meshes"][0]["primitives"][0]["extensions"]["ACUITY_cluster_hierarchy"]["clusters"] = 9999;
    EXPECT_HAS(load_fault(g, "view.glb"), "clusters");
  }
  // The primitive's indices not the finest clusters'.
  {
    Glb g = good;
    g.doc["accessors"][g.doc["meshes"][0]["primitives"][0]["indices"].get<int>()]["count"] = 30;
    EXPECT_HAS(load_fault(g, "finest.glb"), "finest clusters");
  }
}

TEST(ClusterBuild, SmallOpenAndBadInput) {
  // One triangle: one finest cluster, which is the root; no group.
  Mesh one;
  one.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  one.indices = {0, 1, 2};
  const ClusterHierarchy h = build_clusters(one, "one");
  ASSERT_EQ(h.clusters.size(), 1u);
  EXPECT_TRUE(h.groups.empty());
  EXPECT_EQ(h.clusters[0].group, kNoGroup);
  EXPECT_EQ(check_cluster_hierarchy(h, 3), "");
  // An open mesh (a border of its own): valid, simplified up the levels, its border kept.
  const Built open = build("plane.off");
  EXPECT_EQ(check_cluster_hierarchy(open.h, open.mesh.vertex_count()), "");
  EXPECT_GE(open.h.levels(), 2u);
  // Bad input and options.
  Mesh bad = one;
  bad.indices[2] = 3;
  EXPECT_THROW(build_clusters(bad, "bad"), InputError);
  EXPECT_THROW(build_clusters(Mesh{}, "empty"), InputError);
  ClusterOptions o;
  o.max_triangles = 130;
  EXPECT_THROW(build_clusters(one, "one", o), std::invalid_argument);
  o = {};
  o.max_kept = 0.4;
  EXPECT_THROW(build_clusters(one, "one", o), std::invalid_argument);
}
