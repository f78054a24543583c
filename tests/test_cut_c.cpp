// The C ABI of cluster cuts (acuity.h: acuity_hierarchy_create, acuity_select_cut): the same cuts as
// the C++ Scheduler::select_cut with memory, bit for bit, frame after frame; the drawn triangles
// follow the gaze; hysteresis through the caller's memory; the contract on sizes and bad records.
// On a made-up hierarchy (no lodgen: this runs in the runtime-only configuration).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "acuity.h"
#include "acuity/blob.hpp"
#include "acuity/scheduler.hpp"

namespace {

// Eight finest clusters of 100 triangles in a row along x (object units), paired into four groups;
// each group makes one cluster of 100 (level 1), paired into two groups; they make two clusters,
// one group, which makes the root. Spheres nest, errors grow; band b of 4 loses error x 2^b / 4.
struct Made {
  std::vector<acuity_cluster> clusters;
  std::vector<acuity_cluster_group> groups;
  std::vector<float> bands = {2, 4, 8, 16}, lost;
  float diameter = 8;
  Made() {
    const uint32_t N = ACUITY_NO_GROUP;
    const auto cluster = [&](uint32_t group, uint32_t refined) {
      clusters.push_back({uint32_t(clusters.size()) * 100, 100, group, refined});
    };
    for (uint32_t c = 0; c < 8; ++c) cluster(c / 2, N);
    for (uint32_t g = 0; g < 4; ++g) cluster(4 + g / 2, g);
    cluster(6, 4);
    cluster(6, 5);
    cluster(N, 6);
    const auto group = [&](float x, float r, float e, uint32_t first, uint32_t level) {
      groups.push_back({{x, 0, 0}, r, e, first, 2, level});
    };
    for (uint32_t g = 0; g < 4; ++g) group(-3.0f + 2.0f * float(g), 1.2f, 0.004f, 2 * g, 0);
    group(-2, 2.3f, 0.02f, 8, 1);
    group(2, 2.3f, 0.02f, 10, 1);
    group(0, 4.4f, 0.1f, 12, 2);
    for (const acuity_cluster_group& g : groups)
      for (int b = 0; b < 4; ++b) lost.push_back(std::min(1.0f, g.error * float(1 << b) / 4));
  }
  acuity_hierarchy* create() const {
    acuity_hierarchy* h = nullptr;
    EXPECT_EQ(acuity_hierarchy_create(clusters.data(), uint32_t(clusters.size()), groups.data(),
                                      uint32_t(groups.size()), bands.data(), uint32_t(bands.size()), diameter,
                                      lost.data(), &h),
              ACUITY_OK)
        << acuity_last_error();
    return h;
  }
};

// The eye 24 m in front of the object (+Z; its 8 m span 19 degrees), looking at it, the gaze
// `right_deg` to the right.
acuity_eye eye_gazing(float right_deg) {
  acuity_eye e;
  acuity_eye_default(&e);
  e.position[2] = 24;
  e.gaze_valid = 1;
  e.gaze_confidence = 1;
  e.gaze_direction[0] = std::sin(right_deg * 3.14159265f / 180);
  e.gaze_direction[2] = -std::cos(right_deg * 3.14159265f / 180);
  return e;
}

// Profile bytes copied into 8-byte-aligned storage, as open_profile needs them.
acuity::Blob aligned(const std::vector<char>& bytes) {
  acuity::Blob blob;
  blob.storage.resize((bytes.size() + 7) / 8);
  blob.size = bytes.size();
  std::memcpy(blob.storage.data(), bytes.data(), bytes.size());
  return blob;
}

// A C scheduler for one object, the default configuration otherwise (null on failure).
acuity_scheduler* one_object_scheduler() {
  acuity_config c;
  acuity_config_default(&c);
  c.max_objects = 1;
  acuity_scheduler* s = nullptr;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_OK);
  return s;
}

acuity::Frame frame_of(const acuity_eye& e, float dt) {
  acuity::Frame f;
  for (int k = 0; k < 3; ++k) f.eyes[0].position[k] = e.position[k];
  for (int k = 0; k < 3; ++k) f.gaze[0].direction[k] = e.gaze_direction[k];
  f.gaze[0].valid = true;
  f.dt = dt;
  return f;
}

}  // namespace

TEST(CutC, SameCutsAsCppFrameAfterFrameAndTheyFollowTheGaze) {
  const Made m;
  acuity_config c;
  acuity_config_default(&c);
  c.max_objects = 1;
  c.hysteresis_seconds = 0.05f;
  acuity_scheduler* s = nullptr;
  ASSERT_EQ(acuity_create(&c, &s), ACUITY_OK);
  acuity::SchedulerConfig cc;
  cc.max_objects = 1;
  cc.hysteresis_seconds = 0.05f;
  acuity::Scheduler ref(cc);
  acuity_hierarchy* h = m.create();
  const std::size_t G = m.groups.size(), C = m.clusters.size();
  ASSERT_EQ(acuity_cut_memory_size(h),
            G * (sizeof(acuity::CutGroupMemory) + sizeof(acuity::CutCandidate) + 1));
  std::vector<uint32_t> memory_words((acuity_cut_memory_size(h) + 3) / 4, 0);  // 4-byte aligned, zeroed
  std::vector<acuity::CutGroupMemory> ref_memory(G);
  std::vector<uint8_t> ref_scratch(G);
  std::vector<uint32_t> drawn(C), ref_drawn(C);
  std::vector<acuity::Cluster> rc(C);
  std::vector<acuity::ClusterGroup> rg(G);
  std::memcpy(static_cast<void*>(rc.data()), m.clusters.data(), sizeof(acuity_cluster) * C);
  std::memcpy(static_cast<void*>(rg.data()), m.groups.data(), sizeof(acuity_cluster_group) * G);
  const std::vector<uint32_t> roots = acuity::cluster_roots(rc);
  const acuity::ClusterView view{rc, rg, roots};
  const acuity::ClusterLoss loss{m.bands, m.diameter, m.lost};
  const double position[3] = {0, 0, 0};
  const float rotation[4] = {0, 0, 0, 1};
  // Triangles drawn left (x < 0) and right, per frame.
  const auto halves = [&](uint32_t n) {
    std::pair<uint64_t, uint64_t> lr{0, 0};
    for (uint32_t k = 0; k < n; ++k) {
      const acuity_cluster& cl = m.clusters[drawn[k]];
      const uint32_t g = cl.refined == ACUITY_NO_GROUP ? cl.group : cl.refined;
      (m.groups[g].center[0] < 0 ? lr.first : lr.second) += cl.triangle_count;
      if (m.groups[g].center[0] == 0) lr.second -= cl.triangle_count / 2, lr.first += cl.triangle_count / 2;
    }
    return lr;
  };
  std::vector<std::pair<uint64_t, uint64_t>> seen;
  uint32_t held = 0;
  for (int frame = 0; frame < 24; ++frame) {
    const float gaze = frame < 12 ? -20.0f : 20.0f;  // left of the object, then right
    const acuity_eye e = eye_gazing(gaze);
    ASSERT_EQ(acuity_begin_frame(s, &e, 1, 1 / 60.0f), ACUITY_OK);
    ref.begin_frame(frame_of(e, 1 / 60.0f));
    acuity_cut_result r;
    r.struct_size = sizeof r;
    ASSERT_EQ(acuity_select_cut(s, h, position, rotation, 1, nullptr, memory_words.data(),
                                acuity_cut_memory_size(h), uint32_t(C), drawn.data(), &r),
              ACUITY_OK)
        << acuity_last_error();
    acuity::ObjectTransform t;
    const acuity::CutResult x = ref.select_cut(view, loss, t, nullptr, ref_memory, ref_scratch, ref_drawn);
    ASSERT_EQ(r.status, ACUITY_CUT_OK);
    ASSERT_EQ(r.clusters, x.clusters);
    EXPECT_EQ(r.triangles, x.triangles);
    EXPECT_EQ(r.flags, x.flags);
    EXPECT_EQ(r.held, x.held);
    EXPECT_EQ(r.groups_evaluated, x.groups_evaluated);
    for (uint32_t k = 0; k < r.clusters; ++k) ASSERT_EQ(drawn[k], ref_drawn[k]) << "frame " << frame;
    EXPECT_EQ(std::memcmp(memory_words.data(), ref_memory.data(), G * sizeof(acuity::CutGroupMemory)), 0);
    held += r.held;
    seen.push_back(halves(r.clusters));
    ASSERT_EQ(acuity_end_frame(s), ACUITY_OK);
  }
  // Gaze left: the left half finer; gaze right, after the hysteresis: the right half.
  EXPECT_GT(seen[11].first, seen[11].second);
  EXPECT_GT(seen[23].second, seen[23].first);
  EXPECT_GT(held, 0u) << "the left half waited to coarsen";
  EXPECT_EQ(seen[12].first, seen[11].first) << "held on the first frame after the gaze left";
  acuity_hierarchy_destroy(h);
  acuity_destroy(s);
}

TEST(CutC, ContractOnSizesAndBadRecords) {
  const Made m;
  acuity_config c;
  acuity_config_default(&c);
  c.max_objects = 1;
  acuity_scheduler* s = nullptr;
  ASSERT_EQ(acuity_create(&c, &s), ACUITY_OK);
  acuity_hierarchy* h = m.create();
  std::vector<uint32_t> memory((acuity_cut_memory_size(h) + 3) / 4 + 1, 0);
  std::vector<uint32_t> drawn(m.clusters.size());
  const double p[3] = {0, 0, 0};
  const float q[4] = {0, 0, 0, 1};
  acuity_cut_result r;
  r.struct_size = sizeof r;
  const size_t bytes = acuity_cut_memory_size(h);
  const uint32_t C = uint32_t(m.clusters.size());
  EXPECT_EQ(acuity_select_cut(s, h, p, q, 1, nullptr, memory.data(), bytes, C, drawn.data(), &r),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_NE(std::string(acuity_last_error()).find("no frame"), std::string::npos);
  const acuity_eye e = eye_gazing(0);
  ASSERT_EQ(acuity_begin_frame(s, &e, 1, 0), ACUITY_OK);
  EXPECT_EQ(acuity_select_cut(s, h, p, q, 1, nullptr, memory.data(), bytes - 1, C, drawn.data(), &r),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_select_cut(s, h, p, q, 1, nullptr, reinterpret_cast<char*>(memory.data()) + 1, bytes, C,
                              drawn.data(), &r),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_select_cut(s, h, p, q, 1, nullptr, memory.data(), bytes, C - 1, drawn.data(), &r),
            ACUITY_INVALID_ARGUMENT);
  r.struct_size = 24;
  EXPECT_EQ(acuity_select_cut(s, h, p, q, 1, nullptr, memory.data(), bytes, C, drawn.data(), &r),
            ACUITY_INVALID_ARGUMENT);
  // A newer caller's larger struct: only the known fields written.
  struct {
    acuity_cut_result r;
    uint64_t later;
  } wide;
  wide.r.struct_size = sizeof wide;
  wide.later = 0x1234;
  ASSERT_EQ(acuity_select_cut(s, h, p, q, 1, nullptr, memory.data(), bytes, C, drawn.data(), &wide.r),
            ACUITY_OK);
  EXPECT_EQ(wide.later, 0x1234u);
  EXPECT_EQ(wide.r.struct_size, sizeof wide);
  EXPECT_GT(wide.r.clusters, 0u);
  // Invalid object values: the finest cut, not an error.
  r.struct_size = sizeof r;
  const float bad_q[4] = {0, 0, 0, 2};
  ASSERT_EQ(acuity_select_cut(s, h, p, bad_q, 1, nullptr, memory.data(), bytes, C, drawn.data(), &r),
            ACUITY_OK);
  EXPECT_EQ(r.status, ACUITY_CUT_INVALID_INPUT);
  EXPECT_EQ(r.clusters, 8u);
  EXPECT_EQ(r.flags & ACUITY_FLAG_INVALID_INPUT, ACUITY_FLAG_INVALID_INPUT);
  // Bad records: rejected naming the group or cluster; nothing created.
  Made bad = m;
  bad.groups[5].error = 0.001f;  // below the errors of the groups that made its members
  acuity_hierarchy* none = nullptr;
  EXPECT_EQ(acuity_hierarchy_create(bad.clusters.data(), C, bad.groups.data(), uint32_t(bad.groups.size()),
                                    bad.bands.data(), 4, bad.diameter, bad.lost.data(), &none),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_NE(std::string(acuity_last_error()).find("group 5"), std::string::npos) << acuity_last_error();
  EXPECT_EQ(none, nullptr);
  bad = m;
  bad.clusters[3].group = 9;
  EXPECT_EQ(acuity_hierarchy_create(bad.clusters.data(), C, bad.groups.data(), uint32_t(bad.groups.size()),
                                    bad.bands.data(), 4, bad.diameter, bad.lost.data(), &none),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_NE(std::string(acuity_last_error()).find("cluster 3"), std::string::npos) << acuity_last_error();
  bad = m;
  bad.bands[2] = bad.bands[1];
  EXPECT_EQ(acuity_hierarchy_create(bad.clusters.data(), C, bad.groups.data(), uint32_t(bad.groups.size()),
                                    bad.bands.data(), 4, bad.diameter, bad.lost.data(), &none),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_hierarchy_create(m.clusters.data(), C, m.groups.data(), uint32_t(m.groups.size()),
                                    m.bands.data(), 4, 0.0f, m.lost.data(), &none),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_hierarchy_create(m.clusters.data(), 0, nullptr, 0, m.bands.data(), 4, 8, nullptr, &none),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(none, nullptr);
  EXPECT_EQ(acuity_cut_memory_size(nullptr), 0u);
  acuity_hierarchy_destroy(nullptr);
  acuity_hierarchy_destroy(h);
  acuity_destroy(s);
}

// The loss derived from a profile (acuity_hierarchy_create_from_profile) is provisional_group_loss's:
// the same cut as a hierarchy created with that loss given; bad profile bytes are BAD_PROFILE.
TEST(CutC, LossFromAProfileIsTheProvisionalLoss) {
  std::ifstream in(std::string(ACUITY_TEST_DATA) + "/profile_v1.acuity", std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), 592u);
  const acuity::Blob blob = aligned(bytes);
  acuity::Profile p{};
  ASSERT_EQ(acuity::open_profile(blob.data(), blob.size, &p), acuity::ProfileStatus::Ok);
  Made m;
  for (acuity_cluster_group& g : m.groups) g.error *= 2 * p.meta.sphere[3] / m.diameter;  // within its chain
  std::vector<acuity::ClusterGroup> records(m.groups.size());
  std::memcpy(static_cast<void*>(records.data()), m.groups.data(),
              sizeof(acuity_cluster_group) * records.size());
  acuity::ClusterLoss loss;
  const std::vector<float> lost = acuity::provisional_group_loss(p, records, &loss);
  acuity_hierarchy *from_profile = nullptr, *given = nullptr;
  const uint32_t C = uint32_t(m.clusters.size()), G = uint32_t(m.groups.size());
  ASSERT_EQ(acuity_hierarchy_create_from_profile(m.clusters.data(), C, m.groups.data(), G, bytes.data(),
                                                 bytes.size(), &from_profile),
            ACUITY_OK)
      << acuity_last_error();
  ASSERT_EQ(acuity_hierarchy_create(m.clusters.data(), C, m.groups.data(), G, loss.bands_cpod.data(),
                                    uint32_t(loss.bands_cpod.size()), loss.diameter, lost.data(), &given),
            ACUITY_OK)
      << acuity_last_error();
  acuity_scheduler* s = one_object_scheduler();
  ASSERT_NE(s, nullptr);
  std::vector<uint32_t> memory_a(acuity_cut_memory_size(given), 0),
      memory_b(acuity_cut_memory_size(given), 0);
  std::vector<uint32_t> a(C), b(C);
  const double position[3] = {0, 0, 0};
  const float rotation[4] = {0, 0, 0, 1};
  std::set<uint64_t> triangles;
  for (float distance : {2.0f, 20.0f, 200.0f, 2000.0f, 20000.0f}) {
    acuity_eye e = eye_gazing(0);
    e.position[2] = distance * p.meta.sphere[3];
    ASSERT_EQ(acuity_begin_frame(s, &e, 1, 0), ACUITY_OK);
    acuity_cut_result ra, rb;
    ra.struct_size = rb.struct_size = sizeof ra;
    ASSERT_EQ(acuity_select_cut(s, given, position, rotation, 1, nullptr, memory_a.data(),
                                4 * memory_a.size(), C, a.data(), &ra),
              ACUITY_OK);
    ASSERT_EQ(acuity_select_cut(s, from_profile, position, rotation, 1, nullptr, memory_b.data(),
                                4 * memory_b.size(), C, b.data(), &rb),
              ACUITY_OK);
    ASSERT_EQ(ra.clusters, rb.clusters);
    EXPECT_TRUE(std::equal(a.begin(), a.begin() + ra.clusters, b.begin()));
    triangles.insert(ra.triangles);
    ASSERT_EQ(acuity_end_frame(s), ACUITY_OK);
  }
  EXPECT_GE(triangles.size(), 2u) << "the distances give different cuts";
  acuity_hierarchy* none = nullptr;
  std::vector<char> bad = bytes;
  bad[100] ^= 1;
  EXPECT_EQ(acuity_hierarchy_create_from_profile(m.clusters.data(), C, m.groups.data(), G, bad.data(),
                                                 bad.size(), &none),
            ACUITY_BAD_PROFILE);
  EXPECT_EQ(none, nullptr);
  acuity_hierarchy_destroy(given);
  acuity_hierarchy_destroy(from_profile);
  acuity_destroy(s);
}

namespace {
// profile_v1.acuity with a Clusters section for `m` (and a ClusterViews section of two cells, +z and
// -z, when cells is non-empty: [G 2 B]) appended, as `acuity profile` of a cluster glTF writes them.
std::vector<char> with_cluster_sections(const std::vector<char>& v1, const Made& m, std::uint64_t hash,
                                        const std::vector<float>& cells) {
  acuity::ProfileHeader h;
  std::memcpy(&h, v1.data(), sizeof h);
  const std::size_t old_table_end = sizeof h + h.section_count * sizeof(acuity::ProfileSectionEntry);
  std::vector<acuity::ProfileSectionEntry> table(h.section_count);
  std::memcpy(static_cast<void*>(table.data()), v1.data() + sizeof h, old_table_end - sizeof h);
  const std::size_t added = cells.empty() ? 1 : 2;
  const std::size_t shift = added * sizeof(acuity::ProfileSectionEntry);
  for (acuity::ProfileSectionEntry& e : table) e.offset += shift;
  std::vector<char> body(old_table_end + shift, 0);
  body.insert(body.end(), v1.begin() + std::ptrdiff_t(old_table_end),
              v1.begin() + std::ptrdiff_t(h.total_size));
  const auto append = [&](acuity::ProfileSection id, const std::vector<char>& bytes) {
    body.resize((body.size() + 7) / 8 * 8, 0);
    table.push_back({static_cast<std::uint32_t>(id), 0, body.size(), bytes.size()});
    body.insert(body.end(), bytes.begin(), bytes.end());
  };
  const auto bytes_of = [](const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    return std::vector<char>(c, c + n);
  };
  const acuity::ProfileClusterMeta meta{
      uint32_t(m.groups.size()), uint32_t(m.bands.size()), 64, 12, hash, {0, 0}};
  std::vector<char> section = bytes_of(&meta, sizeof meta);
  for (const std::vector<float>* v : {&m.bands, &m.lost}) {
    const std::vector<char> b = bytes_of(v->data(), v->size() * sizeof(float));
    section.insert(section.end(), b.begin(), b.end());
  }
  append(acuity::ProfileSection::Clusters, section);
  if (!cells.empty()) {
    const acuity::ProfileClusterViewsMeta vm{2, acuity::kMinCellSamples, {0, 0}};
    const float dirs[6] = {0, 0, 1, 0, 0, -1};
    section = bytes_of(&vm, sizeof vm);
    const std::vector<char> d = bytes_of(dirs, sizeof dirs), c = bytes_of(cells.data(), cells.size() * 4);
    section.insert(section.end(), d.begin(), d.end());
    section.insert(section.end(), c.begin(), c.end());
    append(acuity::ProfileSection::ClusterViews, section);
  }
  h.section_count = uint32_t(table.size());
  h.total_size = body.size();
  h.checksum = 0;
  std::memcpy(body.data(), &h, sizeof h);
  std::memcpy(body.data() + sizeof h, table.data(), table.size() * sizeof(acuity::ProfileSectionEntry));
  h.checksum = acuity::profile_checksum(body.data(), body.size());
  std::memcpy(body.data(), &h, sizeof h);
  return body;
}
}  // namespace

// The measured loss of a cluster profile (its Clusters section, and its cells): read by
// acuity_hierarchy_create_from_profile as measured_group_loss reads it for C++, so the cuts are
// select_cut's with that loss, bit for bit; the eye in the cell that loses nothing draws the roots
// alone; a section that measured another hierarchy is BAD_PROFILE.
TEST(CutC, LossFromAClusterProfileIsTheMeasuredLoss) {
  std::ifstream in(std::string(ACUITY_TEST_DATA) + "/profile_v1.acuity", std::ios::binary);
  const std::vector<char> v1((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Made m;
  const uint32_t C = uint32_t(m.clusters.size()), G = uint32_t(m.groups.size()), B = uint32_t(m.bands.size());
  std::vector<acuity::Cluster> cr(C);
  std::vector<acuity::ClusterGroup> gr(G);
  std::memcpy(static_cast<void*>(cr.data()), m.clusters.data(), sizeof(acuity_cluster) * C);
  std::memcpy(static_cast<void*>(gr.data()), m.groups.data(), sizeof(acuity_cluster_group) * G);
  const std::uint64_t hash = acuity::cluster_hierarchy_hash(cr, gr);
  std::vector<float> cells;  // cell +z loses nothing, cell -z the loss over all views
  for (uint32_t g = 0; g < G; ++g)
    for (int v = 0; v < 2; ++v)
      for (uint32_t b = 0; b < B; ++b) cells.push_back(v == 0 ? 0.0f : m.lost[g * B + b]);
  const std::vector<char> bytes = with_cluster_sections(v1, m, hash, cells);
  const acuity::Blob blob = aligned(bytes);
  acuity::Profile p{};
  ASSERT_EQ(acuity::open_profile(blob.data(), blob.size, &p), acuity::ProfileStatus::Ok);
  acuity::ClusterLoss loss;
  ASSERT_EQ(acuity::measured_group_loss(p, cr, gr, &loss), acuity::GroupLossStatus::Measured);
  ASSERT_EQ(loss.view_directions.size(), 6u);
  acuity_hierarchy* h = nullptr;
  ASSERT_EQ(acuity_hierarchy_create_from_profile(m.clusters.data(), C, m.groups.data(), G, bytes.data(),
                                                 bytes.size(), &h),
            ACUITY_OK)
      << acuity_last_error();
  acuity_scheduler* s = one_object_scheduler();
  ASSERT_NE(s, nullptr);
  acuity::SchedulerConfig cc;
  cc.max_objects = 1;
  acuity::Scheduler cpp(cc);
  const std::vector<std::uint32_t> roots = acuity::cluster_roots(cr);
  std::vector<uint32_t> memory(acuity_cut_memory_size(h), 0), drawn(C), expected(C);
  std::vector<acuity::CutGroupMemory> remembered(G);
  std::vector<std::uint8_t> scratch(G);
  const double position[3] = {0, 0, 0};
  const float rotation[4] = {0, 0, 0, 1};
  std::set<uint64_t> triangles;
  for (float z : {24.0f, -24.0f, 240.0f, -240.0f}) {
    acuity_eye e = eye_gazing(0);
    e.position[2] = z;
    if (z < 0) {  // turned to look along +z at the object
      e.orientation[1] = 1;
      e.orientation[3] = 0;
    }
    ASSERT_EQ(acuity_begin_frame(s, &e, 1, 0), ACUITY_OK);
    acuity::Frame f = frame_of(e, 0);
    for (int k = 0; k < 4; ++k) f.eyes[0].orientation[k] = e.orientation[k];
    cpp.begin_frame(f);
    acuity_cut_result r;
    r.struct_size = sizeof r;
    ASSERT_EQ(acuity_select_cut(s, h, position, rotation, 1, nullptr, memory.data(), 4 * memory.size(), C,
                                drawn.data(), &r),
              ACUITY_OK);
    acuity::ObjectTransform t;
    const acuity::CutResult x =
        cpp.select_cut({cr, gr, roots}, loss, t, nullptr, remembered, scratch, expected);
    ASSERT_EQ(x.status, acuity::CutStatus::Ok);
    ASSERT_EQ(r.clusters, x.clusters) << z;
    EXPECT_TRUE(std::equal(drawn.begin(), drawn.begin() + r.clusters, expected.begin())) << z;
    if (z > 0) { EXPECT_EQ(r.clusters, roots.size()) << "the eye in the cell that loses nothing"; }
    triangles.insert(r.triangles);
    ASSERT_EQ(acuity_end_frame(s), ACUITY_OK);
    cpp.end_frame();
  }
  EXPECT_GE(triangles.size(), 2u);
  acuity_hierarchy* none = nullptr;
  const std::vector<char> other = with_cluster_sections(v1, m, hash ^ 1, {});
  EXPECT_EQ(acuity_hierarchy_create_from_profile(m.clusters.data(), C, m.groups.data(), G, other.data(),
                                                 other.size(), &none),
            ACUITY_BAD_PROFILE);
  EXPECT_NE(std::string(acuity_last_error()).find("another hierarchy"), std::string::npos)
      << acuity_last_error();
  EXPECT_EQ(none, nullptr);
  acuity_hierarchy_destroy(h);
  acuity_destroy(s);
}

// A cut under a triangle budget (acuity_select_cut_budget): the C++ budgeted cut's, bit for bit,
// with its counts; a budget above the cut, or 0, changes nothing; a version-8 caller's 32-byte
// result gets the version-8 fields and no byte more.
TEST(CutC, BudgetIsTheCppBudgetAndVersion8ResultsStayThatSize) {
  const Made m;
  acuity_scheduler* s = one_object_scheduler();
  ASSERT_NE(s, nullptr);
  acuity_hierarchy* h = m.create();
  const std::size_t G = m.groups.size(), C = m.clusters.size();
  std::vector<acuity::Cluster> rc(C);
  std::vector<acuity::ClusterGroup> rg(G);
  std::memcpy(static_cast<void*>(rc.data()), m.clusters.data(), sizeof(acuity_cluster) * C);
  std::memcpy(static_cast<void*>(rg.data()), m.groups.data(), sizeof(acuity_cluster_group) * G);
  const std::vector<uint32_t> roots = acuity::cluster_roots(rc), made = acuity::cluster_made_index(rc, G);
  const acuity::ClusterView view{rc, rg, roots, made};
  const acuity::ClusterLoss loss{m.bands, m.diameter, m.lost};
  acuity::SchedulerConfig cc;
  cc.max_objects = 1;
  acuity::Scheduler cpp(cc);
  std::vector<uint32_t> memory((acuity_cut_memory_size(h) + 3) / 4, 0), drawn(C), expected(C);
  std::vector<acuity::CutGroupMemory> remembered(G);
  std::vector<acuity::CutCandidate> candidates(G);
  std::vector<std::uint8_t> scratch(G);
  const double p[3] = {0, 0, 0};
  const float q[4] = {0, 0, 0, 1};
  const acuity_eye e = eye_gazing(-10);
  ASSERT_EQ(acuity_begin_frame(s, &e, 1, 0), ACUITY_OK);
  cpp.begin_frame(frame_of(e, 0));
  acuity_cut_result r;
  r.struct_size = sizeof r;
  ASSERT_EQ(acuity_select_cut(s, h, p, q, 1, nullptr, memory.data(), acuity_cut_memory_size(h), uint32_t(C),
                              drawn.data(), &r),
            ACUITY_OK);
  const uint64_t perceptual = r.triangles;
  ASSERT_GT(perceptual, 300u) << "the view refines some groups";
  std::set<uint32_t> coarsened;
  for (uint64_t budget :
       {uint64_t(0), perceptual + 50, perceptual, perceptual - 100, perceptual / 2, uint64_t(1)}) {
    ASSERT_EQ(acuity_select_cut_budget(s, h, p, q, 1, nullptr, budget, memory.data(),
                                       acuity_cut_memory_size(h), uint32_t(C), drawn.data(), &r),
              ACUITY_OK)
        << acuity_last_error();
    acuity::ObjectTransform t;
    const acuity::CutResult x = cpp.select_cut(view, loss, t, nullptr, remembered,
                                               acuity::CutBudget{budget, candidates}, scratch, expected);
    ASSERT_EQ(x.status, acuity::CutStatus::Ok);
    ASSERT_EQ(r.clusters, x.clusters) << budget;
    EXPECT_TRUE(std::equal(drawn.begin(), drawn.begin() + r.clusters, expected.begin())) << budget;
    EXPECT_EQ(r.triangles, x.triangles);
    EXPECT_EQ(r.budget_coarsened, x.budget_coarsened);
    EXPECT_EQ(r.budget_forced, x.budget_forced);
    EXPECT_EQ(r.flags, x.flags);
    EXPECT_EQ(std::memcmp(memory.data(), remembered.data(), G * sizeof(acuity::CutGroupMemory)), 0);
    if (budget == 0 || budget >= perceptual) {
      EXPECT_EQ(r.triangles, perceptual) << budget;
      EXPECT_EQ(r.budget_coarsened, 0u);
    } else {
      EXPECT_LE(r.triangles, budget == 1 ? 100u : budget) << "the root alone at the least";
      EXPECT_GT(r.budget_coarsened, 0u);
    }
    coarsened.insert(r.budget_coarsened);
  }
  EXPECT_GE(coarsened.size(), 3u);
  // A version-8 caller: 32 bytes written, the next 8 untouched.
  struct {
    unsigned char v8[ACUITY_CUT_RESULT_SIZE_V8];
    uint64_t after;
  } old;
  const uint32_t v8 = ACUITY_CUT_RESULT_SIZE_V8;
  std::memcpy(old.v8, &v8, sizeof v8);
  old.after = 0x5555;
  ASSERT_EQ(acuity_select_cut_budget(s, h, p, q, 1, nullptr, 1, memory.data(), acuity_cut_memory_size(h),
                                     uint32_t(C), drawn.data(), reinterpret_cast<acuity_cut_result*>(old.v8)),
            ACUITY_OK);
  EXPECT_EQ(old.after, 0x5555u);
  uint32_t clusters = 0;
  std::memcpy(&clusters, old.v8 + offsetof(acuity_cut_result, clusters), sizeof clusters);
  EXPECT_EQ(clusters, 1u) << "a budget of 1 triangle: the root";
  acuity_hierarchy_destroy(h);
  acuity_destroy(s);
}
