// Profile reader: validates everything before anything is used. See acuity/profile.hpp.
#include "acuity/profile.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "fnv1a.hpp"

static_assert(std::endian::native == std::endian::little, "profiles are little-endian; add byte swapping");

namespace acuity {
namespace {

constexpr std::size_t kChecksumOffset = offsetof(ProfileHeader, checksum);
constexpr std::uint32_t kSectionIds = 12;
constexpr std::uint32_t kRequiredSections =
    8;  // ids 1..8; Detail (9), Clusters (10), ClusterViews (11), Pooled (12) optional
const char* const kSectionNames[kSectionIds + 1] = {
    "?",    "Meta",     "Levels", "Views",    "Lookup",       "Orientations", "Bands",
    "Lost", "Features", "Detail", "Clusters", "ClusterViews", "Pooled"};

ProfileStatus fail(ProfileError* error, ProfileStatus status, const char* format, ...) {
  if (error) {
    error->status = status;
    va_list args;
    va_start(args, format);
    std::vsnprintf(error->message, sizeof(error->message), format, args);
    va_end(args);
  }
  return status;
}

bool finite_nonnegative(const float* values, std::size_t n, std::size_t* bad) {
  for (std::size_t i = 0; i < n; ++i)
    if (!(std::isfinite(values[i]) && values[i] >= 0.0f)) {
      *bad = i;
      return false;
    }
  return true;
}

bool unit(const float v[3]) {
  const float n = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  return std::isfinite(n) && std::abs(n - 1.0f) < 2e-3f;
}

}  // namespace

std::uint64_t profile_checksum(const void* data, std::size_t size) {
  using internal::fnv1a;
  const auto* bytes = static_cast<const unsigned char*>(data);
  const unsigned char zeros[8] = {};  // the checksum field counts as zero
  if (size <= kChecksumOffset) return fnv1a(internal::kFnv1aBasis, bytes, size);
  const std::size_t field = std::min<std::size_t>(8, size - kChecksumOffset);
  const std::uint64_t head = fnv1a(fnv1a(internal::kFnv1aBasis, bytes, kChecksumOffset), zeros, field);
  return fnv1a(head, bytes + kChecksumOffset + field, size - kChecksumOffset - field);
}

namespace {
// The values of a profile whose sections have their sizes: each finite and in its range.
ProfileStatus check_values(const Profile& p, ProfileError* error) {
  const ProfileMeta& m = p.meta;
  const std::uint64_t K = m.level_count, V = m.view_count, T = m.orientation_count, B = m.band_count;
  const std::uint64_t cells = 6ull * m.lookup_resolution * m.lookup_resolution;
  for (std::uint64_t k = 0; k < K; ++k)
    if (!std::isfinite(p.levels[k].geometric_error) || p.levels[k].geometric_error < 0)
      return fail(error, ProfileStatus::BadValue, "Levels: level %llu has an invalid geometric error",
                  static_cast<unsigned long long>(k));
  for (std::uint64_t v = 0; v < V; ++v) {
    const ProfileView& view = p.views[v];
    const float d =
        view.direction[0] * view.up[0] + view.direction[1] * view.up[1] + view.direction[2] * view.up[2];
    if (!unit(view.direction) || !unit(view.up) || !(std::abs(d) < 2e-3f))
      return fail(error, ProfileStatus::BadValue,
                  "Views: view %llu needs a unit direction and a unit up orthogonal to it",
                  static_cast<unsigned long long>(v));
  }
  for (std::uint64_t i = 0; i < cells * kLookupCandidates; ++i)
    if (p.lookup[i] >= V)
      return fail(error, ProfileStatus::BadValue, "Lookup: entry %llu names view %u of %llu",
                  static_cast<unsigned long long>(i), p.lookup[i], static_cast<unsigned long long>(V));
  for (std::uint64_t t = 0; t < T; ++t)
    if (!(p.orientations[t] >= 0 && p.orientations[t] < 180) ||
        (t && !(p.orientations[t] > p.orientations[t - 1])))
      return fail(error, ProfileStatus::BadValue,
                  "Orientations: entry %llu must increase within [0, 180) deg",
                  static_cast<unsigned long long>(t));
  for (std::uint64_t b = 0; b < B; ++b)
    if (!(std::isfinite(p.bands[b]) && p.bands[b] > 0) || (b && !(p.bands[b] > p.bands[b - 1])))
      return fail(error, ProfileStatus::BadValue, "Bands: entry %llu must be finite, positive and increasing",
                  static_cast<unsigned long long>(b));
  std::size_t bad = 0;
  if (!finite_nonnegative(p.lost, (K - 1) * V * T * B, &bad))
    return fail(error, ProfileStatus::BadValue, "Lost: value %zu is negative or not finite", bad);
  if (!finite_nonnegative(p.features, K * V * T, &bad))
    return fail(error, ProfileStatus::BadValue, "Features: value %zu is negative or not finite", bad);
  if (p.detail)
    for (std::uint64_t i = 0; i < (K - 1) * V * T * B; ++i)
      if (p.detail[i].frequency_code == -128 || p.detail[i].orientation_code == -128)
        return fail(error, ProfileStatus::BadValue, "Detail: entry %llu has a code -128 (allowed -127..127)",
                    static_cast<unsigned long long>(i));
  if (p.pooled)
    for (std::uint64_t i = 0; i < (K - 1) * V * B; ++i) {
      const ProfilePooled& e = p.pooled[i];
      if (!(std::isfinite(e.lost) && e.lost >= 0) || e.zero[0] || e.zero[1] || e.zero[2])
        return fail(error, ProfileStatus::BadValue,
                    "Pooled: entry %llu needs a finite loss >= 0 and zero padding",
                    static_cast<unsigned long long>(i));
    }
  if (p.cluster_lost) {
    const ProfileClusterMeta& c = p.clusters;
    for (std::uint32_t b = 0; b < c.band_count; ++b)
      if (!(std::isfinite(p.cluster_bands[b]) && p.cluster_bands[b] > 0) ||
          (b && !(p.cluster_bands[b] > p.cluster_bands[b - 1])))
        return fail(error, ProfileStatus::BadValue,
                    "Clusters: band %u must be finite, positive and increasing", b);
    if (!finite_nonnegative(p.cluster_lost, std::size_t(c.group_count) * c.band_count, &bad))
      return fail(error, ProfileStatus::BadValue, "Clusters: value %zu (group %zu) is negative or not finite",
                  bad, bad / c.band_count);
  }
  if (p.cluster_view_lost) {
    const std::uint32_t Vc = p.cluster_views.view_count, Bc = p.clusters.band_count;
    for (std::uint32_t v = 0; v < Vc; ++v) {
      const float* d = &p.cluster_view_directions[3 * std::size_t(v)];
      const float n = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      if (!(std::abs(n - 1.0f) <= 1e-3f))
        return fail(error, ProfileStatus::BadValue, "ClusterViews: direction %u is not a unit vector", v);
    }
    const std::size_t n = std::size_t(p.clusters.group_count) * Vc * Bc;
    if (!finite_nonnegative(p.cluster_view_lost, n, &bad))
      return fail(error, ProfileStatus::BadValue,
                  "ClusterViews: value %zu (group %zu) is negative or not finite", bad,
                  bad / (std::size_t(Vc) * Bc));
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t g = i / (std::size_t(Vc) * Bc), b = i % Bc;
      if (!(p.cluster_view_lost[i] <= p.cluster_lost[g * Bc + b]))
        return fail(error, ProfileStatus::BadValue,
                    "ClusterViews: value %zu (group %zu) exceeds the Clusters section's bound", i, g);
    }
  }
  return ProfileStatus::Ok;
}

// An optional section's fixed header, copied out, or BadSize naming the section.
template <class Header>
ProfileStatus section_header(const unsigned char* at, std::uint64_t size, const char* name, Header* h,
                             ProfileError* error) {
  if (size < sizeof(Header))
    return fail(error, ProfileStatus::BadSize, "section %s: size %llu, shorter than its %zu-byte header",
                name, static_cast<unsigned long long>(size), sizeof(Header));
  std::memcpy(h, at, sizeof(Header));
  return ProfileStatus::Ok;
}
// BadSize naming the section unless its size is the one its header's counts give.
ProfileStatus section_size(std::uint64_t size, std::uint64_t expected, const char* name,
                           ProfileError* error) {
  if (size == expected) return ProfileStatus::Ok;
  return fail(error, ProfileStatus::BadSize, "section %s: size %llu, expected %llu", name,
              static_cast<unsigned long long>(size), static_cast<unsigned long long>(expected));
}

// The optional Clusters section: its header's counts, then its size from them.
ProfileStatus open_clusters(const unsigned char* at, std::uint64_t size, Profile* p, ProfileError* error) {
  ProfileClusterMeta c;
  if (const ProfileStatus st = section_header(at, size, "Clusters", &c, error); st != ProfileStatus::Ok)
    return st;
  if (c.group_count == 0 || c.group_count > kMaxClusterGroups)
    return fail(error, ProfileStatus::BadCounts, "Clusters: group_count = %u (allowed 1..%u)", c.group_count,
                kMaxClusterGroups);
  if (c.band_count == 0 || c.band_count > kMaxBands)
    return fail(error, ProfileStatus::BadCounts, "Clusters: band_count = %u (allowed 1..%u)", c.band_count,
                kMaxBands);
  if (c.window_pixels == 0 || c.view_count == 0 || c.reserved[0] || c.reserved[1])
    return fail(error, ProfileStatus::BadCounts,
                "Clusters: window_pixels %u and view_count %u must be >= 1, reserved 0", c.window_pixels,
                c.view_count);
  const std::uint64_t expected =
      sizeof c + std::uint64_t(c.band_count) * sizeof(float) * (1 + std::uint64_t(c.group_count));
  if (const ProfileStatus st = section_size(size, expected, "Clusters", error); st != ProfileStatus::Ok)
    return st;
  p->clusters = c;
  p->cluster_bands = reinterpret_cast<const float*>(at + sizeof c);
  p->cluster_lost = p->cluster_bands + c.band_count;
  return ProfileStatus::Ok;
}

// The optional ClusterViews section (after Clusters, whose counts it takes): its header, then its size.
ProfileStatus open_cluster_views(const unsigned char* at, std::uint64_t size, Profile* p,
                                 ProfileError* error) {
  if (!p->cluster_lost)
    return fail(error, ProfileStatus::MissingSection, "section ClusterViews needs the Clusters section");
  ProfileClusterViewsMeta c;
  if (const ProfileStatus st = section_header(at, size, "ClusterViews", &c, error); st != ProfileStatus::Ok)
    return st;
  if (c.view_count == 0 || c.view_count > kMaxClusterViews || c.sample_count < c.view_count ||
      c.reserved[0] || c.reserved[1])
    return fail(error, ProfileStatus::BadCounts,
                "ClusterViews: view_count %u (allowed 1..%u), sample_count %u (>= view_count), reserved 0",
                c.view_count, kMaxClusterViews, c.sample_count);
  const std::uint64_t expected =
      sizeof c + sizeof(float) * std::uint64_t(c.view_count) *
                     (3 + std::uint64_t(p->clusters.group_count) * p->clusters.band_count);
  if (const ProfileStatus st = section_size(size, expected, "ClusterViews", error); st != ProfileStatus::Ok)
    return st;
  p->cluster_views = c;
  p->cluster_view_directions = reinterpret_cast<const float*>(at + sizeof c);
  p->cluster_view_lost = p->cluster_view_directions + 3 * std::size_t(c.view_count);
  return ProfileStatus::Ok;
}
// The section table of a blob of `total` bytes whose table ends at `table_end`: bounds, alignment,
// no overlap, each known id at most once, the required ones present. found[id]: the entry of id.
ProfileStatus read_section_table(const unsigned char* base, std::size_t total, std::uint64_t table_end,
                                 std::uint32_t count, ProfileSectionEntry* found, ProfileError* error) {
  ProfileSectionEntry all[kMaxProfileSections];
  for (std::uint32_t i = 0; i < count; ++i) {
    ProfileSectionEntry s;
    std::memcpy(&s, base + sizeof(ProfileHeader) + i * sizeof(ProfileSectionEntry), sizeof s);
    if (s.offset % 8 != 0 || s.offset < table_end || s.offset > total || s.size > total - s.offset)
      return fail(error, ProfileStatus::BadSectionTable,
                  "section %u (id %u): offset %llu size %llu outside the blob or misaligned", i, s.id,
                  static_cast<unsigned long long>(s.offset), static_cast<unsigned long long>(s.size));
    for (std::uint32_t j = 0; j < i; ++j)
      if (s.size && all[j].size && s.offset < all[j].offset + all[j].size &&
          all[j].offset < s.offset + s.size)
        return fail(error, ProfileStatus::BadSectionTable, "sections %u and %u overlap", j, i);
    all[i] = s;
    if (s.id >= 1 && s.id <= kSectionIds) {
      if (found[s.id].id)
        return fail(error, ProfileStatus::BadSectionTable, "section %s appears twice", kSectionNames[s.id]);
      found[s.id] = s;
    }
  }
  for (std::uint32_t id = 1; id <= kRequiredSections; ++id)
    if (!found[id].id)
      return fail(error, ProfileStatus::MissingSection, "section %s is missing", kSectionNames[id]);
  return ProfileStatus::Ok;
}

}  // namespace

ProfileStatus open_profile(const void* data, std::size_t size, Profile* out, ProfileError* error) {
  if (!data || !out) return fail(error, ProfileStatus::NullInput, "no data");
  if (reinterpret_cast<std::uintptr_t>(data) % 8 != 0)
    return fail(error, ProfileStatus::Misaligned, "data must be 8-byte aligned");
  if (size < sizeof(ProfileHeader))
    return fail(error, ProfileStatus::TooSmall, "%zu bytes is shorter than the %zu-byte header", size,
                sizeof(ProfileHeader));
  const auto* base = static_cast<const unsigned char*>(data);
  ProfileHeader h;
  std::memcpy(&h, base, sizeof h);
  if (h.magic != kProfileMagic)
    return fail(error, ProfileStatus::BadMagic, "not an acuity profile (bad magic)");
  if (h.version > kProfileVersion)
    return fail(error, ProfileStatus::NewerVersion,
                "format version %u is newer than this reader's %u: re-bake the profile or upgrade acuity",
                h.version, kProfileVersion);
  if (h.version == 0) return fail(error, ProfileStatus::BadValue, "format version 0 is invalid");
  if (h.total_size > size)
    return fail(error, ProfileStatus::TooSmall, "truncated: header says %llu bytes, only %zu given",
                static_cast<unsigned long long>(h.total_size), size);
  if (h.section_count > kMaxProfileSections)
    return fail(error, ProfileStatus::BadSectionTable, "%u sections (at most %u)", h.section_count,
                kMaxProfileSections);
  const std::uint64_t table_end =
      sizeof(ProfileHeader) + std::uint64_t(h.section_count) * sizeof(ProfileSectionEntry);
  if (table_end > h.total_size)
    return fail(error, ProfileStatus::BadSectionTable,
                "section table ends at byte %llu, past the blob's %llu",
                static_cast<unsigned long long>(table_end), static_cast<unsigned long long>(h.total_size));
  const std::size_t total = static_cast<std::size_t>(h.total_size);
  if (profile_checksum(base, total) != h.checksum)
    return fail(error, ProfileStatus::BadChecksum, "checksum mismatch: the file was changed or damaged");

  ProfileSectionEntry found[kSectionIds + 1] = {};
  const ProfileStatus table = read_section_table(base, total, table_end, h.section_count, found, error);
  if (table != ProfileStatus::Ok) return table;

  auto check_size = [&](ProfileSection id, std::uint64_t expected) {
    const ProfileSectionEntry& s = found[static_cast<std::uint32_t>(id)];
    if (s.size == expected) return true;
    fail(error, ProfileStatus::BadSize, "section %s: size %llu, expected %llu", kSectionNames[s.id],
         static_cast<unsigned long long>(s.size), static_cast<unsigned long long>(expected));
    return false;
  };
  auto at = [&](ProfileSection id) { return base + found[static_cast<std::uint32_t>(id)].offset; };

  Profile p;
  if (!check_size(ProfileSection::Meta, sizeof(ProfileMeta)))
    return error ? error->status : ProfileStatus::BadSize;
  std::memcpy(&p.meta, at(ProfileSection::Meta), sizeof p.meta);
  const ProfileMeta& m = p.meta;
  struct {
    std::uint32_t value, limit;
    const char* name;
  } counts[] = {{m.level_count, kMaxLevels, "level_count"},
                {m.view_count, kMaxViews, "view_count"},
                {m.orientation_count, kMaxOrientations, "orientation_count"},
                {m.band_count, kMaxBands, "band_count"},
                {m.lookup_resolution, kMaxLookupResolution, "lookup_resolution"}};
  for (const auto& c : counts)
    if (c.value == 0 || c.value > c.limit)
      return fail(error, ProfileStatus::BadCounts, "Meta: %s = %u (allowed 1..%u)", c.name, c.value, c.limit);
  if (m.snapshot_pixels == 0) return fail(error, ProfileStatus::BadCounts, "Meta: snapshot_pixels = 0");
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(m.sphere[i]) || m.sphere[3] < 0)
      return fail(error, ProfileStatus::BadValue,
                  "Meta: bounding sphere is not finite or has a negative radius");

  const std::uint64_t K = m.level_count, V = m.view_count, T = m.orientation_count, B = m.band_count;
  const std::uint64_t cells = 6ull * m.lookup_resolution * m.lookup_resolution;
  if (!check_size(ProfileSection::Levels, K * sizeof(ProfileLevel)) ||
      !check_size(ProfileSection::Views, V * sizeof(ProfileView)) ||
      !check_size(ProfileSection::Lookup, cells * kLookupCandidates * sizeof(std::uint16_t)) ||
      !check_size(ProfileSection::Orientations, T * sizeof(float)) ||
      !check_size(ProfileSection::Bands, B * sizeof(float)) ||
      !check_size(ProfileSection::Lost, (K - 1) * V * T * B * sizeof(float)) ||
      !check_size(ProfileSection::Features, K * V * T * sizeof(float)))
    return error ? error->status : ProfileStatus::BadSize;
  const bool has_detail = found[static_cast<std::uint32_t>(ProfileSection::Detail)].id != 0;
  if (has_detail && !check_size(ProfileSection::Detail, (K - 1) * V * T * B * sizeof(ProfileDetail)))
    return error ? error->status : ProfileStatus::BadSize;
  const bool has_pooled = found[static_cast<std::uint32_t>(ProfileSection::Pooled)].id != 0;
  if (has_pooled && !check_size(ProfileSection::Pooled, (K - 1) * V * B * sizeof(ProfilePooled)))
    return error ? error->status : ProfileStatus::BadSize;

  p.levels = reinterpret_cast<const ProfileLevel*>(at(ProfileSection::Levels));
  p.views = reinterpret_cast<const ProfileView*>(at(ProfileSection::Views));
  p.lookup = reinterpret_cast<const std::uint16_t*>(at(ProfileSection::Lookup));
  p.orientations = reinterpret_cast<const float*>(at(ProfileSection::Orientations));
  p.bands = reinterpret_cast<const float*>(at(ProfileSection::Bands));
  p.lost = reinterpret_cast<const float*>(at(ProfileSection::Lost));
  p.features = reinterpret_cast<const float*>(at(ProfileSection::Features));
  p.detail = has_detail ? reinterpret_cast<const ProfileDetail*>(at(ProfileSection::Detail)) : nullptr;
  p.pooled = has_pooled ? reinterpret_cast<const ProfilePooled*>(at(ProfileSection::Pooled)) : nullptr;
  if (found[static_cast<std::uint32_t>(ProfileSection::Clusters)].id) {
    const ProfileStatus c =
        open_clusters(at(ProfileSection::Clusters),
                      found[static_cast<std::uint32_t>(ProfileSection::Clusters)].size, &p, error);
    if (c != ProfileStatus::Ok) return c;
  }
  if (found[static_cast<std::uint32_t>(ProfileSection::ClusterViews)].id) {
    const ProfileStatus c =
        open_cluster_views(at(ProfileSection::ClusterViews),
                           found[static_cast<std::uint32_t>(ProfileSection::ClusterViews)].size, &p, error);
    if (c != ProfileStatus::Ok) return c;
  }

  const ProfileStatus values = check_values(p, error);
  if (values != ProfileStatus::Ok) return values;

  *out = p;
  if (error) *error = ProfileError{};
  return ProfileStatus::Ok;
}

const char* to_string(ProfileStatus status) {
  switch (status) {
    case ProfileStatus::Ok:
      return "ok";
    case ProfileStatus::NullInput:
      return "null input";
    case ProfileStatus::Misaligned:
      return "misaligned";
    case ProfileStatus::TooSmall:
      return "too small";
    case ProfileStatus::BadMagic:
      return "bad magic";
    case ProfileStatus::NewerVersion:
      return "newer version";
    case ProfileStatus::BadChecksum:
      return "bad checksum";
    case ProfileStatus::BadSectionTable:
      return "bad section table";
    case ProfileStatus::MissingSection:
      return "missing section";
    case ProfileStatus::BadSize:
      return "bad size";
    case ProfileStatus::BadCounts:
      return "bad counts";
    case ProfileStatus::BadValue:
      return "bad value";
  }
  return "unknown";
}

void cube_cell_center(std::uint32_t cell, std::uint32_t r, float d[3]) {
  const std::uint32_t face = cell / (r * r), row = (cell / r) % r, col = cell % r;
  const float u = (static_cast<float>(col) + 0.5f) / static_cast<float>(r) * 2 - 1;
  const float v = (static_cast<float>(row) + 0.5f) / static_cast<float>(r) * 2 - 1;
  const float s = (face % 2 == 0) ? 1.0f : -1.0f;
  float x, y, z;
  switch (face / 2) {
    case 0:
      x = s;
      y = u;
      z = v;
      break;
    case 1:
      y = s;
      z = u;
      x = v;
      break;
    default:
      z = s;
      x = u;
      y = v;
      break;
  }
  const float n = std::sqrt(x * x + y * y + z * z);
  d[0] = x / n;
  d[1] = y / n;
  d[2] = z / n;
}

}  // namespace acuity
