// The profile blob: writer and reader agree; the reader rejects every damaged file cleanly.
#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <random>

#include "acuity/file.hpp"
#include "acuity/profile.hpp"
#include "profile_fixture.hpp"
#include "profile_v1_input.hpp"

using namespace acuity;
using acuity::testing::refresh_checksum;
using acuity::testing::small_profile;

namespace {
unsigned char* bytes(Blob& b) { return reinterpret_cast<unsigned char*>(b.storage.data()); }
ProfileStatus open(const Blob& b, ProfileError* e = nullptr) {
  Profile p;
  return open_profile(b.data(), b.size, &p, e);
}
// Sets section `id`'s size in the table to `size` (a section cut short or grown).
void set_section_size(Blob& b, ProfileSection id, std::uint64_t size) {
  ProfileHeader h;
  std::memcpy(&h, bytes(b), sizeof h);
  for (std::uint32_t i = 0; i < h.section_count; ++i) {
    ProfileSectionEntry s;
    unsigned char* at = bytes(b) + sizeof h + i * sizeof s;
    std::memcpy(&s, at, sizeof s);
    if (s.id != static_cast<std::uint32_t>(id)) continue;
    s.size = size;
    std::memcpy(at, &s, sizeof s);
  }
}
// Offset of section `id`'s data, read from the table.
std::uint64_t section_offset(Blob& b, ProfileSection id) {
  ProfileHeader h;
  std::memcpy(&h, bytes(b), sizeof h);
  for (std::uint32_t i = 0; i < h.section_count; ++i) {
    ProfileSectionEntry s;
    std::memcpy(&s, bytes(b) + sizeof h + i * sizeof s, sizeof s);
    if (s.id == static_cast<std::uint32_t>(id)) return s.offset;
  }
  return 0;
}
}  // namespace

TEST(Profile, RoundTrip) {
  const spectra::ProfileData d = small_profile();
  const Blob blob = spectra::encode_profile(d);
  Profile p;
  ProfileError e;
  ASSERT_EQ(open_profile(blob.data(), blob.size, &p, &e), ProfileStatus::Ok) << e.message;
  EXPECT_EQ(p.meta.level_count, 4u);
  EXPECT_EQ(p.meta.view_count, 6u);
  EXPECT_EQ(p.meta.orientation_count, 4u);
  EXPECT_EQ(p.meta.band_count, 5u);
  EXPECT_EQ(p.meta.sphere[3], 1.5f);
  EXPECT_EQ(p.levels[2].triangles, 250u);
  std::size_t i = 0;
  for (std::uint32_t k = 1; k < 4; ++k)
    for (std::uint32_t v = 0; v < 6; ++v)
      for (std::uint32_t t = 0; t < 4; ++t)
        for (std::uint32_t b = 0; b < 5; ++b) ASSERT_EQ(p.lost_contrast(k, v, t, b), d.lost[i++]);
  EXPECT_EQ(p.feature_frequency(3, 5, 2), d.features[(3 * 6 + 5) * 4 + 2]);
}

namespace {
// d encoded, opened into *p (expected to open).
Blob encoded_and_opened(const spectra::ProfileData& d, Profile* p) {
  ProfileError e;
  Blob b = spectra::encode_profile(d);
  EXPECT_EQ(open_profile(b.data(), b.size, p, &e), ProfileStatus::Ok) << e.message;
  return b;
}
}  // namespace

// The optional Detail section (issue 47): written only when given, read back exactly, absent for
// older writers' profiles, and a damaged one rejected with a message naming it.
TEST(Profile, DetailSectionIsOptionalAndChecked) {
  spectra::ProfileData d = small_profile();
  Profile p;
  ProfileError e;
  const Blob without = encoded_and_opened(d, &p);
  EXPECT_EQ(p.detail, nullptr);
  for (std::size_t i = 0; i < d.lost.size(); ++i)
    d.detail.push_back(
        spectra::encode_detail(std::ldexp(1.0f, -int(i % 20)), 0.01f * float(int(i % 90) - 45)));
  Blob with = spectra::encode_profile(d);
  ASSERT_EQ(open_profile(with.data(), with.size, &p, &e), ProfileStatus::Ok) << e.message;
  ASSERT_NE(p.detail, nullptr);
  for (std::size_t i = 0; i < d.lost.size(); ++i) {
    EXPECT_EQ(detail_area(p.detail[i]), std::ldexp(1.0f, -int(i % 20)));  // powers of 2^(1/8) are exact
    EXPECT_NEAR(detail_frequency_octaves(p.detail[i]), 0.01f * float(int(i % 90) - 45), 0.5f / 128);
  }
  EXPECT_EQ(with.size, without.size + sizeof(ProfileSectionEntry) + (d.lost.size() * 3 + 7) / 8 * 8);
  // Areas round up (never under-stating it), and decode within 2^(1/8) above; offsets clamp.
  for (float a : {0.3f, 0.01f, 1e-6f, 1.0f}) {
    const float back = detail_area(spectra::encode_detail(a, 0));
    EXPECT_GE(back, a);
    EXPECT_LE(back, a * std::exp2(0.125f) * 1.0001f);
  }
  EXPECT_EQ(spectra::encode_detail(0.0f, 5.0f).area_code, 255);
  EXPECT_EQ(spectra::encode_detail(0.5f, 5.0f).frequency_code, 127);
  EXPECT_EQ(spectra::encode_detail(0.5f, -5.0f).frequency_code, -127);
  EXPECT_EQ(spectra::encode_detail(0.5f, 0.0f, -0.25f).orientation_code, -32);
  EXPECT_EQ(detail_turn(spectra::encode_detail(0.5f, 0.0f, 0.5f)), 0.5f);
  {  // an invalid frequency code
    Blob b = with;
    const std::int8_t bad = -128;
    std::memcpy(bytes(b) + section_offset(b, ProfileSection::Detail) + 3 * 7 + 2, &bad, 1);
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::BadValue);
    EXPECT_NE(std::string(e.message).find("Detail: entry 7 has a code -128"), std::string::npos) << e.message;
  }
  {  // a section of the wrong size: the table's entry shrunk by 8 bytes
    Blob b = with;
    set_section_size(b, ProfileSection::Detail, d.lost.size() * sizeof(ProfileDetail) - 8);
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::BadSize);
    EXPECT_NE(std::string(e.message).find("section Detail"), std::string::npos) << e.message;
  }
  d.detail.pop_back();  // the writer wants none or one per lost value
  EXPECT_THROW(spectra::encode_profile(d), spectra::InvalidProfile);
}

// The optional Pooled section (issue 47): written only when given, read back exactly, absent for
// older writers' profiles, and damage (a NaN loss, padding, a wrong size) rejected naming it.
TEST(Profile, PooledSectionIsOptionalAndChecked) {
  spectra::ProfileData d = small_profile();
  Profile p;
  ProfileError e;
  const Blob without = encoded_and_opened(d, &p);
  EXPECT_EQ(p.pooled, nullptr);
  const std::size_t n = (d.levels.size() - 1) * d.views.size() * d.bands.size();
  for (std::size_t i = 0; i < n; ++i)
    d.pooled.push_back(spectra::encode_pooled(0.01f * float(i), std::ldexp(1.0f, -int(i % 20))));
  Blob with = spectra::encode_profile(d);
  ASSERT_EQ(open_profile(with.data(), with.size, &p, &e), ProfileStatus::Ok) << e.message;
  ASSERT_NE(p.pooled, nullptr);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(p.pooled[i].lost, 0.01f * float(i));
    EXPECT_EQ(std::exp2(-0.125f * p.pooled[i].area_code), std::ldexp(1.0f, -int(i % 20)));
  }
  EXPECT_EQ(with.size, without.size + sizeof(ProfileSectionEntry) + n * sizeof(ProfilePooled));
  EXPECT_EQ(spectra::encode_pooled(0.5f, 0.3f).area_code, spectra::encode_detail(0.3f, 0).area_code);
  {  // a NaN loss
    Blob b = with;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(bytes(b) + section_offset(b, ProfileSection::Pooled) + 8 * 3, &nan, 4);
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::BadValue);
    EXPECT_NE(std::string(e.message).find("Pooled: entry 3"), std::string::npos) << e.message;
  }
  {  // padding that is not zero
    Blob b = with;
    const unsigned char one = 1;
    std::memcpy(bytes(b) + section_offset(b, ProfileSection::Pooled) + 8 * 5 + 6, &one, 1);
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::BadValue);
    EXPECT_NE(std::string(e.message).find("Pooled: entry 5"), std::string::npos) << e.message;
  }
  {  // a section of the wrong size
    Blob b = with;
    set_section_size(b, ProfileSection::Pooled, n * sizeof(ProfilePooled) - 8);
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::BadSize);
    EXPECT_NE(std::string(e.message).find("section Pooled"), std::string::npos) << e.message;
  }
  d.pooled.pop_back();  // the writer wants none or one per level, view and band
  EXPECT_THROW(spectra::encode_profile(d), spectra::InvalidProfile);
  d.pooled.push_back(spectra::encode_pooled(-1.0f, 0.5f));
  EXPECT_THROW(spectra::encode_profile(d), spectra::InvalidProfile);
}

// The optional Clusters section (issue 48 item 2): written only when given, read back in place,
// absent for older writers' profiles (and skipped by older readers: an unknown id), and any damage
// to it rejected with a message naming it: every truncation of the section, bit flips in it with a
// valid checksum, wrong counts, sizes and values.
namespace {
spectra::ProfileData with_clusters(std::uint32_t groups = 5, std::uint32_t bands = 7) {
  spectra::ProfileData d = small_profile();
  for (std::uint32_t b = 0; b < bands; ++b) d.clusters.bands.push_back(2.0f * float(1u << b));
  for (std::uint32_t i = 0; i < groups * bands; ++i) d.clusters.lost.push_back(0.001f * float(i % 97));
  d.clusters.window_pixels = 64;
  d.clusters.view_count = 12;
  d.clusters.hierarchy_hash = 0x0123456789abcdefull;
  return d;
}
ProfileSectionEntry section_entry(Blob& b, ProfileSection id) {
  ProfileHeader h;
  std::memcpy(&h, bytes(b), sizeof h);
  for (std::uint32_t i = 0; i < h.section_count; ++i) {
    ProfileSectionEntry s;
    std::memcpy(&s, bytes(b) + sizeof h + i * sizeof s, sizeof s);
    if (s.id == static_cast<std::uint32_t>(id)) return s;
  }
  return {};
}
// The blob with section `id`'s table entry given an id no reader knows (63): what an older reader sees.
Blob with_unknown_id(const Blob& with, ProfileSection id) {
  Blob b = with;
  ProfileHeader h;
  std::memcpy(&h, bytes(b), sizeof h);
  for (std::uint32_t i = 0; i < h.section_count; ++i) {
    unsigned char* at = bytes(b) + sizeof h + i * sizeof(ProfileSectionEntry);
    std::uint32_t s;
    std::memcpy(&s, at, 4);
    if (s == static_cast<std::uint32_t>(id)) s = 63;
    std::memcpy(at, &s, 4);
  }
  refresh_checksum(b);
  return b;
}
// The blob with `size` bytes at `offset` into section `entry` replaced by `value` (checksum valid):
// the status and message of opening it.
std::pair<ProfileStatus, std::string> damaged_section(const Blob& with, const ProfileSectionEntry& entry,
                                                      std::size_t offset, const void* value,
                                                      std::size_t size) {
  Blob b = with;
  std::memcpy(bytes(b) + entry.offset + offset, value, size);
  refresh_checksum(b);
  ProfileError e;
  const ProfileStatus status = open(b, &e);
  return std::pair{status, std::string(e.message)};
}
}  // namespace

TEST(Profile, ClustersSectionIsOptionalAndChecked) {
  const spectra::ProfileData d = with_clusters();
  Profile p;
  ProfileError e;
  const Blob without = spectra::encode_profile(small_profile());
  ASSERT_EQ(open_profile(without.data(), without.size, &p, &e), ProfileStatus::Ok) << e.message;
  EXPECT_EQ(p.cluster_lost, nullptr);
  EXPECT_EQ(p.clusters.group_count, 0u);
  const Blob with = spectra::encode_profile(d);
  ASSERT_EQ(open_profile(with.data(), with.size, &p, &e), ProfileStatus::Ok) << e.message;
  ASSERT_NE(p.cluster_lost, nullptr);
  EXPECT_EQ(p.clusters.group_count, 5u);
  EXPECT_EQ(p.clusters.band_count, 7u);
  EXPECT_EQ(p.clusters.window_pixels, 64u);
  EXPECT_EQ(p.clusters.view_count, 12u);
  EXPECT_EQ(p.clusters.hierarchy_hash, 0x0123456789abcdefull);
  for (std::size_t b = 0; b < 7; ++b) EXPECT_EQ(p.cluster_bands[b], d.clusters.bands[b]);
  for (std::size_t i = 0; i < d.clusters.lost.size(); ++i) ASSERT_EQ(p.cluster_lost[i], d.clusters.lost[i]);
  const std::size_t section = sizeof(ProfileClusterMeta) + 4 * (7 + 35);
  EXPECT_EQ(with.size, without.size + sizeof(ProfileSectionEntry) + (section + 7) / 8 * 8);
  EXPECT_EQ(section_entry(const_cast<Blob&>(with), ProfileSection::Clusters).size, section);

  // An older reader (ids it does not know are skipped) sees the profile without it: the same
  // blob with the section's id changed to an unknown one opens, with no Clusters.
  {
    Blob b = with_unknown_id(with, ProfileSection::Clusters);
    ASSERT_EQ(open_profile(b.data(), b.size, &p, &e), ProfileStatus::Ok) << e.message;
    EXPECT_EQ(p.cluster_lost, nullptr);
  }
  const ProfileSectionEntry entry = section_entry(const_cast<Blob&>(with), ProfileSection::Clusters);
  // Every truncation of the section (its table entry's size cut, checksum valid): rejected, named.
  for (std::uint64_t n = 0; n < entry.size; ++n) {
    Blob b = with;
    set_section_size(b, ProfileSection::Clusters, n);
    refresh_checksum(b);
    ASSERT_NE(open(b, &e), ProfileStatus::Ok) << n;
    ASSERT_NE(std::string(e.message).find("Clusters"), std::string::npos) << n << ": " << e.message;
  }
  // Bit flips inside the section with a valid checksum: either a valid section (a value that stays
  // in range, safe to read) or rejected naming it; never a crash or a silent bad value.
  std::mt19937 rng(11);
  int rejected = 0, accepted = 0;
  for (int i = 0; i < 2000; ++i) {
    Blob b = with;
    const std::size_t at = entry.offset + rng() % entry.size;
    bytes(b)[at] ^= static_cast<unsigned char>(1u << (rng() % 8));
    refresh_checksum(b);
    if (open_profile(b.data(), b.size, &p, &e) == ProfileStatus::Ok) {
      ++accepted;
      for (std::size_t k = 0; k < std::size_t(p.clusters.group_count) * p.clusters.band_count; ++k)
        ASSERT_TRUE(std::isfinite(p.cluster_lost[k]) && p.cluster_lost[k] >= 0);
    } else {
      ++rejected;
      ASSERT_NE(std::string(e.message).find("Clusters"), std::string::npos) << e.message;
    }
  }
  EXPECT_GT(rejected, 100);
  EXPECT_GT(accepted, 100);
  // Specific damage, each with its own message.
  const auto damaged = [&](std::size_t offset, const void* value, std::size_t size) {
    return damaged_section(with, entry, offset, value, size);
  };
  const std::uint32_t zero = 0, many = kMaxClusterGroups + 1, bands_over = kMaxBands + 1;
  const float nan = std::nanf(""), negative = -0.5f, lower = 1.0f;
  EXPECT_EQ(damaged(0, &zero, 4), (std::pair{ProfileStatus::BadCounts,
                                             std::string("Clusters: group_count = 0 (allowed 1..4194304)")}));
  EXPECT_EQ(damaged(0, &many, 4).first, ProfileStatus::BadCounts);
  EXPECT_EQ(damaged(4, &bands_over, 4).first, ProfileStatus::BadCounts);
  EXPECT_EQ(damaged(8, &zero, 4).first, ProfileStatus::BadCounts);    // window_pixels
  EXPECT_EQ(damaged(24, &lower, 4).first, ProfileStatus::BadCounts);  // reserved
  const std::uint32_t four = 4;  // fewer groups than the section holds: its size is wrong
  EXPECT_EQ(damaged(0, &four, 4),
            (std::pair{ProfileStatus::BadSize, std::string("section Clusters: size 200, expected 172")}));
  EXPECT_EQ(damaged(32 + 4 * 3, &lower, 4),
            (std::pair{ProfileStatus::BadValue,
                       std::string("Clusters: band 3 must be finite, positive and increasing")}));
  EXPECT_EQ(damaged(32 + 4 * (7 + 15), &nan, 4),
            (std::pair{ProfileStatus::BadValue,
                       std::string("Clusters: value 15 (group 2) is negative or not finite")}));
  EXPECT_EQ(damaged(32 + 4 * (7 + 34), &negative, 4).first, ProfileStatus::BadValue);
  // The writer wants whole rows of bands.
  spectra::ProfileData bad = d;
  bad.clusters.lost.pop_back();
  EXPECT_THROW(spectra::encode_profile(bad), spectra::InvalidProfile);
  bad = d;
  bad.clusters.view_count = 0;
  EXPECT_THROW(spectra::encode_profile(bad), spectra::InvalidProfile);
}

// The optional ClusterViews section (issue 48: each group's loss per view cell): only with Clusters,
// read back in place, skipped by older readers, and damage rejected naming it (truncations, counts,
// a direction that is not a unit vector, a value above the Clusters section's bound).
TEST(Profile, ClusterViewsSectionIsOptionalAndChecked) {
  spectra::ProfileData d = with_clusters(5, 7);
  const float dirs[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
  for (const auto& v : dirs) d.clusters.view_directions.insert(d.clusters.view_directions.end(), v, v + 3);
  for (std::uint32_t g = 0; g < 5; ++g)
    for (std::uint32_t v = 0; v < 3; ++v)
      for (std::uint32_t b = 0; b < 7; ++b)
        d.clusters.view_lost.push_back(d.clusters.lost[g * 7 + b] * float(v) / 2);
  d.clusters.view_samples = 42;
  Profile p;
  ProfileError e;
  const Blob with = spectra::encode_profile(d);
  ASSERT_EQ(open_profile(with.data(), with.size, &p, &e), ProfileStatus::Ok) << e.message;
  ASSERT_NE(p.cluster_view_lost, nullptr);
  EXPECT_EQ(p.cluster_views.view_count, 3u);
  EXPECT_EQ(p.cluster_views.sample_count, 42u);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_EQ(p.cluster_view_directions[i], d.clusters.view_directions[i]);
  for (std::size_t i = 0; i < d.clusters.view_lost.size(); ++i)
    ASSERT_EQ(p.cluster_view_lost[i], d.clusters.view_lost[i]);
  const ProfileSectionEntry entry = section_entry(const_cast<Blob&>(with), ProfileSection::ClusterViews);
  EXPECT_EQ(entry.size, sizeof(ProfileClusterViewsMeta) + 4 * (9 + 5 * 3 * 7));
  {  // skipped by a reader that does not know it (an unknown id): the Clusters section alone
    Blob b = with_unknown_id(with, ProfileSection::ClusterViews);
    ASSERT_EQ(open_profile(b.data(), b.size, &p, &e), ProfileStatus::Ok) << e.message;
    EXPECT_EQ(p.cluster_view_lost, nullptr);
    EXPECT_NE(p.cluster_lost, nullptr);
  }
  for (std::uint64_t n = 0; n < entry.size; ++n) {  // every truncation
    Blob b = with;
    set_section_size(b, ProfileSection::ClusterViews, n);
    refresh_checksum(b);
    ASSERT_NE(open(b, &e), ProfileStatus::Ok) << n;
    ASSERT_NE(std::string(e.message).find("ClusterViews"), std::string::npos) << n << ": " << e.message;
  }
  const auto damaged = [&](std::size_t offset, const void* value, std::size_t size) {
    return damaged_section(with, entry, offset, value, size);
  };
  const std::uint32_t zero = 0, many = kMaxClusterViews + 1, one = 1;
  const float half = 0.5f, big = 1.0f;
  EXPECT_EQ(damaged(0, &zero, 4).first, ProfileStatus::BadCounts);
  EXPECT_EQ(damaged(0, &many, 4).first, ProfileStatus::BadCounts);
  EXPECT_EQ(damaged(4, &one, 4).first, ProfileStatus::BadCounts);  // fewer samples than cells
  EXPECT_EQ(damaged(8, &one, 4).first, ProfileStatus::BadCounts);  // reserved
  EXPECT_EQ(
      damaged(16 + 12, &half, 4),
      (std::pair{ProfileStatus::BadValue, std::string("ClusterViews: direction 1 is not a unit vector")}));
  // group 1, cell 2, band 3: above the Clusters section's value for group 1, band 3
  EXPECT_EQ(
      damaged(16 + 4 * (9 + (1 * 3 + 2) * 7 + 3), &big, 4),
      (std::pair{ProfileStatus::BadValue,
                 std::string("ClusterViews: value 38 (group 1) exceeds the Clusters section's bound")}));
  // Without the Clusters section it is refused (written alone: the Clusters section's id made unknown).
  {
    Blob b = with_unknown_id(with, ProfileSection::Clusters);
    EXPECT_EQ(open(b, &e), ProfileStatus::MissingSection);
    EXPECT_NE(std::string(e.message).find("ClusterViews needs the Clusters section"), std::string::npos);
  }
  spectra::ProfileData bad = d;  // the writer wants whole rows
  bad.clusters.view_lost.pop_back();
  EXPECT_THROW(spectra::encode_profile(bad), spectra::InvalidProfile);
}

TEST(Profile, LookupFindsTheNearestView) {
  const spectra::ProfileData d = small_profile(2, 18);
  const Blob blob = spectra::encode_profile(d);
  Profile p;
  ASSERT_EQ(open_profile(blob.data(), blob.size, &p), ProfileStatus::Ok);
  std::mt19937 rng(3);
  std::normal_distribution<float> n;
  int exact = 0;
  for (int i = 0; i < 2000; ++i) {
    float q[3] = {n(rng), n(rng), n(rng)};
    const float len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    for (float& x : q) x /= len;
    int truth = 0;
    float best = -2;
    for (int v = 0; v < 18; ++v) {
      const float* w = d.views[v].direction;
      const float dot = q[0] * w[0] + q[1] * w[1] + q[2] * w[2];
      if (dot > best) {
        best = dot;
        truth = v;
      }
    }
    const std::uint16_t* c = p.lookup + cube_cell(q, p.meta.lookup_resolution) * kLookupCandidates;
    bool among = false;
    for (std::uint32_t j = 0; j < kLookupCandidates; ++j) among |= c[j] == truth;
    exact += among;
  }
  EXPECT_GE(exact, 1990);  // the true nearest is among the cell's candidates (cell-size approximation)
}

TEST(Profile, CubeCellsRoundTrip) {
  for (std::uint32_t r : {1u, 3u, 8u})
    for (std::uint32_t c = 0; c < 6 * r * r; ++c) {
      float d[3];
      cube_cell_center(c, r, d);
      EXPECT_EQ(cube_cell(d, r), c);
    }
  const float zero[3] = {0, 0, 0}, nan[3] = {NAN, 0, 0};
  EXPECT_EQ(cube_cell(zero, 4), 0u);
  EXPECT_LT(cube_cell(nan, 4), 96u);
}

TEST(Profile, EveryTruncatedPrefixIsRejected) {
  const Blob blob = spectra::encode_profile(small_profile());
  for (std::size_t n = 0; n < blob.size; ++n) {
    Blob prefix;
    prefix.storage = blob.storage;
    prefix.size = n;
    ProfileError e;
    ASSERT_NE(open(prefix, &e), ProfileStatus::Ok) << n;
    ASSERT_EQ(e.status, ProfileStatus::TooSmall) << n << " " << e.message;  // total_size says more
  }
}

TEST(Profile, RandomBitFlipsNeverCrash) {
  const Blob clean = spectra::encode_profile(small_profile());
  std::mt19937 rng(5);
  int rejected_by_checksum = 0, rejected_by_structure = 0, accepted = 0;
  for (int i = 0; i < 3000; ++i) {
    Blob b = clean;
    const int flips = 1 + i % 4;
    for (int f = 0; f < flips; ++f) {
      const std::size_t at = rng() % b.size;
      bytes(b)[at] ^= static_cast<unsigned char>(1u << (rng() % 8));
    }
    ProfileError e;
    if (open(b, &e) != ProfileStatus::Ok) ++rejected_by_checksum;  // header damage is caught even earlier
    // Now the same damage with a valid checksum: the structural checks must hold on their own.
    refresh_checksum(b);
    Profile p;
    if (open_profile(b.data(), b.size, &p, &e) == ProfileStatus::Ok) {
      ++accepted;  // a flip in a value that stays in range: the view must still be safe to read
      float sum = 0;
      for (std::uint32_t k = 1; k < p.meta.level_count; ++k)
        for (std::uint32_t v = 0; v < p.meta.view_count; ++v) sum += p.lost_contrast(k, v, 0, 0);
      EXPECT_TRUE(std::isfinite(sum));
    } else {
      ++rejected_by_structure;
      EXPECT_GT(std::strlen(e.message), 0u);
    }
  }
  EXPECT_EQ(rejected_by_checksum, 3000);
  EXPECT_GT(rejected_by_structure, 300);
  EXPECT_GT(accepted, 300);
}

TEST(Profile, SpecificDamage) {
  const Blob clean = spectra::encode_profile(small_profile());
  ProfileError e;
  {  // newer version
    Blob b = clean;
    bytes(b)[offsetof(ProfileHeader, version)] = kProfileVersion + 1;
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::NewerVersion);
    EXPECT_NE(std::string(e.message).find("re-bake"), std::string::npos);
  }
  {  // not a profile
    Blob b = clean;
    bytes(b)[0] = 'X';
    EXPECT_EQ(open(b, &e), ProfileStatus::BadMagic);
  }
  {  // NaN in the lost contrast
    Blob b = clean;
    const float nan = NAN;
    std::memcpy(bytes(b) + section_offset(b, ProfileSection::Lost) + 12, &nan, 4);
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::BadValue);
    EXPECT_NE(std::string(e.message).find("Lost"), std::string::npos) << e.message;
  }
  {  // view count 0 in Meta
    Blob b = clean;
    std::memset(bytes(b) + section_offset(b, ProfileSection::Meta) + offsetof(ProfileMeta, view_count), 0, 4);
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::BadCounts);
  }
  {  // lookup naming a view that does not exist
    Blob b = clean;
    const std::uint16_t big = 999;
    std::memcpy(bytes(b) + section_offset(b, ProfileSection::Lookup), &big, 2);
    refresh_checksum(b);
    EXPECT_EQ(open(b, &e), ProfileStatus::BadValue);
  }
  {  // misaligned memory
    std::vector<unsigned char> shifted(clean.size + 1);
    std::memcpy(shifted.data() + 1, clean.data(), clean.size);
    Profile p;
    EXPECT_EQ(open_profile(shifted.data() + 1, clean.size, &p), ProfileStatus::Misaligned);
  }
  Profile p;
  EXPECT_EQ(open_profile(nullptr, 100, &p), ProfileStatus::NullInput);
}

TEST(Profile, WriterRejectsInconsistentData) {
  spectra::ProfileData d = small_profile();
  d.lost.pop_back();
  EXPECT_THROW(spectra::encode_profile(d), spectra::InvalidProfile);
  d = small_profile();
  d.bands[1] = d.bands[0];
  EXPECT_THROW(spectra::encode_profile(d), spectra::InvalidProfile);
  d = small_profile();
  d.levels.clear();
  EXPECT_THROW(spectra::encode_profile(d), spectra::InvalidProfile);
}

TEST(Profile, AtomicFileWriteAndRead) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "acuity_profile_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "a.acuity").string();
  spectra::write_profile(path, small_profile());
  const Blob b = io::read_file(path);
  EXPECT_EQ(open(b), ProfileStatus::Ok);
  // A failing write (directory missing) leaves nothing behind and says where.
  EXPECT_THROW(spectra::write_profile((dir / "missing" / "b.acuity").string(), small_profile()),
               std::runtime_error);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
  try {
    io::read_file((dir / "nope").string());
    ADD_FAILURE() << "read a missing file";
  } catch (const io::Error& e) { EXPECT_EQ(e.path(), (dir / "nope").string()); }
  fs::remove_all(dir);
}

// ---- The golden version-1 profile (tests/data/README.md) ----
namespace {
Blob golden_v1() { return io::read_file(ACUITY_TEST_DATA "/profile_v1.acuity"); }
}  // namespace

TEST(ProfileGolden, HeaderAndSectionTableOfVersion1) {
  using namespace acuity::testing;
  const Blob b = golden_v1();
  ASSERT_GE(b.size, sizeof(ProfileHeader));
  const auto* base = static_cast<const unsigned char*>(b.data());
  ProfileHeader h;
  std::memcpy(&h, base, sizeof h);
  EXPECT_EQ(std::memcmp(base, "ACUP", 4), 0);
  EXPECT_EQ(h.magic, kProfileMagic);
  EXPECT_EQ(h.version, 1u);
  EXPECT_EQ(h.total_size, b.size);
  EXPECT_EQ(h.section_count, 8u);
  EXPECT_EQ(h.reserved, 0u);
  EXPECT_EQ(h.checksum, profile_checksum(base, b.size));
  // The sections in the writer's order, each right after the previous one's 8-byte-padded end;
  // sizes from the counts and the element types of acuity/profile.hpp.
  const std::uint64_t K = kV1Levels, V = kV1Views, T = kV1Orientations, B = kV1Bands, R = 1;
  const std::uint64_t sizes[8] = {sizeof(ProfileMeta),
                                  K * sizeof(ProfileLevel),
                                  V * sizeof(ProfileView),
                                  6 * R * R * kLookupCandidates * 2,
                                  T * 4,
                                  B * 4,
                                  (K - 1) * V * T * B * 4,
                                  K * V * T * 4};
  std::uint64_t offset = sizeof(ProfileHeader) + 8 * sizeof(ProfileSectionEntry);
  for (std::uint32_t i = 0; i < 8; ++i) {
    ProfileSectionEntry s;
    std::memcpy(&s, base + sizeof h + i * sizeof s, sizeof s);
    EXPECT_EQ(s.id, i + 1) << i;  // Meta = 1 ... Features = 8
    EXPECT_EQ(s.reserved, 0u) << i;
    EXPECT_EQ(s.offset, offset) << i;
    EXPECT_EQ(s.size, sizes[i]) << i;
    offset += (sizes[i] + 7) / 8 * 8;
  }
  EXPECT_EQ(offset, h.total_size);
  EXPECT_EQ(h.total_size, 592u);  // the sum above, worked by hand: 224 + 48 + 24 + 72 + 40 + 8 + 8 + 96 + 72
}

TEST(ProfileGolden, EveryValueOfVersion1) {
  using namespace acuity::testing;
  const Blob b = golden_v1();
  Profile p;
  ProfileError e;
  ASSERT_EQ(open_profile(b.data(), b.size, &p, &e), ProfileStatus::Ok) << e.message;
  EXPECT_EQ(p.meta.level_count, kV1Levels);
  EXPECT_EQ(p.meta.view_count, kV1Views);
  EXPECT_EQ(p.meta.orientation_count, kV1Orientations);
  EXPECT_EQ(p.meta.band_count, kV1Bands);
  EXPECT_EQ(p.meta.lookup_resolution, 1u);
  EXPECT_EQ(p.meta.snapshot_pixels, 128u);
  const float sphere[4] = {0.25f, -0.5f, 1.0f, 2.0f};
  for (int i = 0; i < 4; ++i) EXPECT_EQ(p.meta.sphere[i], sphere[i]) << i;
  EXPECT_EQ(p.meta.reserved[0], 0u);
  EXPECT_EQ(p.meta.reserved[1], 0u);
  const ProfileLevel levels[3] = {{1000, 0.0f}, {250, 0.125f}, {60, 0.5f}};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(p.levels[k].triangles, levels[k].triangles) << k;
    EXPECT_EQ(p.levels[k].geometric_error, levels[k].geometric_error) << k;
  }
  // Axis views; up is +Y made orthogonal to the direction, +Z when looking along Y.
  const float dirs[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, -1}}, ups[3][3] = {{0, 1, 0}, {0, 0, 1}, {0, 1, 0}};
  for (int v = 0; v < 3; ++v)
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(p.views[v].direction[i], dirs[v][i]) << v << " " << i;
      EXPECT_EQ(p.views[v].up[i], ups[v][i]) << v << " " << i;
    }
  // One cell per face (+X -X +Y -Y +Z -Z): all three views by non-increasing cosine to the face's
  // axis; the order among equal cosines is the writer's (insertion) and is part of this file.
  const float axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const std::uint16_t lookup[6][3] = {{0, 1, 2}, {1, 2, 0}, {1, 0, 2}, {0, 2, 1}, {0, 1, 2}, {2, 1, 0}};
  for (int c = 0; c < 6; ++c) {
    auto cosine = [&](int v) {
      return axes[c][0] * dirs[v][0] + axes[c][1] * dirs[v][1] + axes[c][2] * dirs[v][2];
    };
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(p.lookup[c * 3 + j], lookup[c][j]) << "cell " << c << " candidate " << j;
      if (j) {
        EXPECT_GE(cosine(lookup[c][j - 1]), cosine(lookup[c][j]))
            << "cell " << c;  // the table is nearest first
      }
    }
    EXPECT_TRUE(lookup[c][0] != lookup[c][1] && lookup[c][1] != lookup[c][2] && lookup[c][0] != lookup[c][2]);
  }
  EXPECT_EQ(p.orientations[0], 0.0f);
  EXPECT_EQ(p.orientations[1], 90.0f);
  EXPECT_EQ(p.bands[0], 4.0f);
  EXPECT_EQ(p.bands[1], 16.0f);
  for (std::uint32_t k = 1; k < kV1Levels; ++k)
    for (std::uint32_t v = 0; v < kV1Views; ++v)
      for (std::uint32_t t = 0; t < kV1Orientations; ++t)
        for (std::uint32_t band = 0; band < kV1Bands; ++band)
          EXPECT_EQ(p.lost_contrast(k, v, t, band), v1_lost(k, v, t, band)) << k << v << t << band;
  for (std::uint32_t k = 0; k < kV1Levels; ++k)
    for (std::uint32_t v = 0; v < kV1Views; ++v)
      for (std::uint32_t t = 0; t < kV1Orientations; ++t)
        EXPECT_EQ(p.feature_frequency(k, v, t), v1_feature(k, v, t)) << k << v << t;
}

TEST(ProfileGolden, TheWriterStillProducesTheseBytes) {
  // While the format is version 1 the writer must reproduce the committed file byte for byte. A
  // new version keeps this file (old profiles must still open) and adds a golden file of its own.
  ASSERT_EQ(kProfileVersion, 1u) << "new format version: add tests/data/profile_v" << kProfileVersion
                                 << ".acuity";
  const Blob golden = golden_v1();
  const Blob now = spectra::encode_profile(acuity::testing::profile_v1_input());
  ASSERT_EQ(now.size, golden.size);
  const auto* a = static_cast<const unsigned char*>(now.data());
  const auto* g = static_cast<const unsigned char*>(golden.data());
  for (std::size_t i = 0; i < golden.size; ++i) ASSERT_EQ(a[i], g[i]) << "first difference at byte " << i;
}
