#pragma once
// acuity/profile.hpp — the profile blob: what each level of one object loses, per view, orientation
// and frequency band (docs/design.md section 4). The runtime reads it in place, without copying or
// allocating; spectra/ writes it (acuity/spectra/profile_writer.hpp).
//
// Layout (version 1, little-endian, every section 8-byte aligned); the structs below are the one
// definition of it, shared by the reader (scheduler/src/profile.cpp) and the writer
// (spectra/src/profile_writer.cpp):
//   ProfileHeader        32 bytes at offset 0
//   ProfileSectionEntry  section_count x 24 bytes, right after the header
//   sections             Meta, Levels, Views, Lookup, Orientations, Bands, Lost, Features (any order;
//                        unknown ids are skipped so a newer writer may add sections without a
//                        version bump), the optional Detail (issue 47: older readers skip it) and
//                        the optional Clusters (issue 48: what each group of a cluster hierarchy loses)
//                        and ClusterViews (the same per view cell)
// checksum: FNV-1a 64 over the whole blob with the checksum field read as zero.
// Compatibility: a reader accepts versions <= its own and rejects newer ones (re-bake on upgrade).
// tests/data/profile_v1.acuity is a version-1 profile that every later reader must still open
// (tests/test_profile.cpp, ProfileGolden).
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace acuity {

inline constexpr std::uint32_t kProfileMagic = 0x50554341u;  // bytes 'A' 'C' 'U' 'P'
inline constexpr std::uint32_t kProfileVersion = 1;

// Limits a valid profile stays within.
inline constexpr std::uint32_t kMaxLevels = 32;
inline constexpr std::uint32_t kMaxViews = 4096;
inline constexpr std::uint32_t kMaxOrientations = 32;
inline constexpr std::uint32_t kMaxBands = 32;
inline constexpr std::uint32_t kMaxLookupResolution = 64;
inline constexpr std::uint32_t kLookupCandidates = 3;  // nearest views stored per lookup cell

inline constexpr std::uint32_t kMaxProfileSections = 64;      // entries a reader accepts in the section table
inline constexpr std::uint32_t kMaxClusterGroups = 1u << 22;  // groups in a Clusters section
inline constexpr std::uint32_t kMaxClusterViews = 162;        // view cells in a ClusterViews section

// The file header, at offset 0.
struct ProfileHeader {
  std::uint32_t magic;          // kProfileMagic
  std::uint32_t version;        // format version: 1..kProfileVersion
  std::uint64_t total_size;     // the whole profile, header included [bytes]; trailing bytes are ignored
  std::uint32_t section_count;  // entries in the section table: 0..kMaxProfileSections
  std::uint32_t reserved;       // 0
  std::uint64_t checksum;       // profile_checksum() of the total_size bytes
};

// One entry of the section table, which follows the header.
struct ProfileSectionEntry {
  std::uint32_t id;        // a ProfileSection; unknown ids are skipped
  std::uint32_t reserved;  // 0
  std::uint64_t offset;    // from the start of the profile [bytes]: a multiple of 8, past the table
  std::uint64_t size;      // [bytes]; sections do not overlap
};

static_assert(sizeof(ProfileHeader) == 32 && offsetof(ProfileHeader, magic) == 0 &&
                  offsetof(ProfileHeader, version) == 4 && offsetof(ProfileHeader, total_size) == 8 &&
                  offsetof(ProfileHeader, section_count) == 16 && offsetof(ProfileHeader, reserved) == 20 &&
                  offsetof(ProfileHeader, checksum) == 24,
              "ProfileHeader is part of the file format");
static_assert(sizeof(ProfileSectionEntry) == 24 && offsetof(ProfileSectionEntry, id) == 0 &&
                  offsetof(ProfileSectionEntry, reserved) == 4 &&
                  offsetof(ProfileSectionEntry, offset) == 8 && offsetof(ProfileSectionEntry, size) == 16,
              "ProfileSectionEntry is part of the file format");

enum class ProfileSection : std::uint32_t {
  Meta = 1,
  Levels = 2,
  Views = 3,
  Lookup = 4,
  Orientations = 5,
  Bands = 6,
  Lost = 7,
  Features = 8,
  Detail = 9,     // optional: the loss's extent and frequency within each band (ProfileDetail)
  Clusters = 10,  // optional: what each group of the object's cluster hierarchy loses (ProfileClusterMeta)
  ClusterViews = 11,  // optional, with Clusters: the same per view cell (ProfileClusterViewsMeta)
  Pooled = 12,  // optional: each band's loss pooled over the orientations, with its extent (ProfilePooled)
};

enum class ProfileStatus : std::uint8_t {
  Ok,
  NullInput,        // data is null
  Misaligned,       // data is not 8-byte aligned (memory from malloc/new always is)
  TooSmall,         // shorter than the header, or than its own total_size
  BadMagic,         // not a profile
  NewerVersion,     // written by a newer acuity: re-bake or upgrade the runtime
  BadChecksum,      // bytes changed after writing
  BadSectionTable,  // a section out of bounds, overlapping, misaligned or repeated
  MissingSection,   // a required section is absent
  BadSize,          // a section's size does not match the counts in Meta
  BadCounts,        // a count is 0 or above its limit
  BadValue,         // a value is NaN, infinite, negative or otherwise out of its range
};

struct ProfileError {
  ProfileStatus status = ProfileStatus::Ok;
  char message[160] = {};  // what and where, e.g. "section Lost: size 1024, expected 2048"
};

// Sections other than Meta are arrays; their element types and orders are those of Profile below:
//   Levels ProfileLevel[K], Views ProfileView[V], Lookup u16[6 R R][kLookupCandidates],
//   Orientations f32[T], Bands f32[B], Lost f32[(K-1) V T B], Features f32[K V T],
//   Detail (optional) ProfileDetail[(K-1) V T B],
//   Clusters (optional) ProfileClusterMeta, then f32 bands[Bc], then f32 lost[G Bc] (no padding),
//   ClusterViews (optional, only with Clusters) ProfileClusterViewsMeta, then f32 directions[Vc 3],
//   then f32 lost[G Vc Bc] (no padding),
//   Pooled (optional) ProfilePooled[(K-1) V B].
struct ProfileLevel {
  std::uint32_t triangles;  // cost of drawing this level
  float geometric_error;    // Hausdorff distance to level 0 [object diameters]
};

struct ProfileView {
  float direction[3];  // unit vector from the object's centre towards the camera, object space
  float up[3];         // the snapshot's up vector, unit, orthogonal to direction
};

// Section Meta: the counts every other section's size follows from (48 bytes).
struct ProfileMeta {
  std::uint32_t level_count;        // K >= 1; level 0 is the finest
  std::uint32_t view_count;         // V >= 1
  std::uint32_t orientation_count;  // T >= 1
  std::uint32_t band_count;         // B >= 1
  std::uint32_t lookup_resolution;  // R: the lookup is a cube map of 6 R x R cells
  std::uint32_t snapshot_pixels;    // pixels across the bounding-sphere diameter in the snapshots
  float sphere[4];                  // bounding sphere: centre xyz, radius [object units]
  std::uint32_t reserved[2];        // 0
};
// Section Detail (optional), one entry per Lost entry: where in the band and over how much of the
// image the loss lies (acuity::spectra::LostContrast::measure's area and frequency), so a threshold
// model can be evaluated at the loss's own frequency and area rather than the band's centre and an
// unbounded area, and undo the band filter's shortfall where the loss lies off a band's or an
// orientation's centre. 3 bytes; decode with detail_area(), detail_frequency_octaves() and
// detail_turn().
struct ProfileDetail {
  // Extent of the loss (sum of c^2 / max c^2) as a fraction of the squared diameter: 2^(-area_code / 8),
  // rounded up when written (255: 2^-31.9, nothing lost).
  std::uint8_t area_code;
  // Energy-weighted mean frequency of the loss relative to the band's centre: frequency_code / 128
  // octaves, in [-127, 127] (-128 is invalid).
  std::int8_t frequency_code;
  // Energy-weighted mean angle of the loss's frequency vector from the orientation's centre:
  // orientation_code / 128 orientation spacings, in [-127, 127] (-128 is invalid).
  std::int8_t orientation_code;
};
static_assert(sizeof(ProfileDetail) == 3, "ProfileDetail is part of the file format");

// Section Pooled (optional, issue 47), one entry per level k >= 1, view and band ([(K-1) V B]): the
// band's loss pooled over the orientations as the eye pools it (energy at each point), which the
// area law (SchedulerConfig::area_law) reads: its peak sqrt(max_x sum_t c_t(x)^2) and that energy's
// extent (sum / peak as a fraction of the squared diameter, coded as ProfileDetail's area_code,
// rounded up). A cell-bounded profile stores, per entry, the largest peak L over the cell's members
// and the largest energy c^2 a over them divided by L^2 (a bound under the area law: docs/design.md).
struct ProfilePooled {
  float lost;              // [contrast] finite, >= 0
  std::uint8_t area_code;  // extent 2^(-area_code / 8) of the squared diameter
  std::uint8_t zero[3];    // 0
};
static_assert(sizeof(ProfilePooled) == 8 && offsetof(ProfilePooled, area_code) == 4,
              "ProfilePooled is part of the file format");
// Decoded area [fraction of the diameter squared], frequency offset [octaves] and turn.
inline float detail_area(ProfileDetail d) { return std::exp2(-0.125f * float(d.area_code)); }
inline float detail_frequency_octaves(ProfileDetail d) { return float(d.frequency_code) / 128.0f; }
inline float detail_turn(ProfileDetail d) {
  return float(d.orientation_code) / 128.0f;
}  // [orientation spacings]

// Section Clusters (optional, issue 48 item 2): what each group of a cluster hierarchy (lodgen's
// ACUITY_cluster_hierarchy, acuity/clusters.hpp) loses when drawn coarse, measured by
// `acuity profile` of `acuity lodgen MESH --clusters`'s glTF (acuity/spectra/cluster_loss.hpp).
// This header (32 bytes) is followed by f32 bands[band_count] (band centres [cycles per object
// diameter, the diameter of Meta's sphere], increasing) and f32 lost[group_count * band_count]:
// lost[g * band_count + b] is the largest lost contrast, over every measured view and orientation,
// of group g's clusters against the finest mesh in band b (ClusterLoss, which reads it in place).
struct ProfileClusterMeta {
  std::uint32_t group_count;     // G: the hierarchy's groups [Limit: 1 .. kMaxClusterGroups]
  std::uint32_t band_count;      // Bc [Limit: 1 .. kMaxBands]
  std::uint32_t window_pixels;   // pixels across each group's window in the snapshots [Limit: >= 1]
  std::uint32_t view_count;      // directions measured per group [Limit: >= 1]
  std::uint64_t hierarchy_hash;  // cluster_hierarchy_hash() of the hierarchy measured
  std::uint32_t reserved[2];     // 0
};
static_assert(sizeof(ProfileClusterMeta) == 32 && offsetof(ProfileClusterMeta, view_count) == 12 &&
                  offsetof(ProfileClusterMeta, hierarchy_hash) == 16 &&
                  offsetof(ProfileClusterMeta, reserved) == 24,
              "ProfileClusterMeta is part of the file format");

// Section ClusterViews (optional, only with Clusters; issue 48): the Clusters section's loss per
// view cell, so that the cut reads what a group loses from the direction it is seen from (a group
// hidden behind the object, or seen face-on rather than at the silhouette, loses less). This header
// (16 bytes) is followed by f32 directions[view_count * 3] (unit vectors from the object towards the
// camera, object space; a direction's cell is the directions nearer to it than to any other) and f32
// lost[(g * view_count + v) * Bc + b]: the largest lost contrast of group g in band b (the Clusters
// section's bands) over the orientations and the measured directions in or near v's cell (a bound
// over the cell), never above the Clusters section's lost[g * Bc + b].
struct ProfileClusterViewsMeta {
  std::uint32_t view_count;    // Vc: cells [Limit: 1 .. kMaxClusterViews]
  std::uint32_t sample_count;  // directions measured per group, over all cells [Limit: >= view_count]
  std::uint32_t reserved[2];   // 0
};
static_assert(sizeof(ProfileClusterViewsMeta) == 16 && offsetof(ProfileClusterViewsMeta, sample_count) == 4,
              "ProfileClusterViewsMeta is part of the file format");

static_assert(sizeof(ProfileMeta) == 48 && offsetof(ProfileMeta, lookup_resolution) == 16 &&
                  offsetof(ProfileMeta, snapshot_pixels) == 20 && offsetof(ProfileMeta, sphere) == 24 &&
                  offsetof(ProfileMeta, reserved) == 40,
              "ProfileMeta is part of the file format");
static_assert(sizeof(ProfileLevel) == 8 && offsetof(ProfileLevel, geometric_error) == 4 &&
                  sizeof(ProfileView) == 24 && offsetof(ProfileView, up) == 12,
              "part of the file format");

// A validated, read-only view of a profile blob; every pointer points into the caller's bytes,
// which must outlive it.
struct Profile {
  ProfileMeta meta;
  const ProfileLevel* levels;   // [K]
  const ProfileView* views;     // [V]
  const std::uint16_t* lookup;  // [6 R R][kLookupCandidates] view indices, nearest first
  const float* orientations;    // [T] image-plane angle of the frequency vector [deg], [0, 180)
  const float* bands;           // [B] band centre frequencies [cycles per object diameter], increasing
  const float* lost;            // [(K-1) V T B] lost contrast of level k >= 1 against level 0
  const float* features;  // [K V T] Reddy: fundamental frequency of the smallest feature [cpod]; 0 = none
  const ProfileDetail* detail = nullptr;  // [(K-1) V T B] as lost, or nullptr (the section is optional)
  const ProfilePooled* pooled = nullptr;  // [(K-1) V B], or nullptr (the section is optional)
  // The optional Clusters section: its header (group_count 0 when absent), band centres [Bc] and
  // per-group loss [G Bc] (ProfileClusterMeta), or nullptr.
  ProfileClusterMeta clusters = {};
  const float* cluster_bands = nullptr;
  const float* cluster_lost = nullptr;
  // The optional ClusterViews section: its header (view_count 0 when absent), directions [Vc 3]
  // and per-group, per-view loss [G Vc Bc] (ProfileClusterViewsMeta), or nullptr.
  ProfileClusterViewsMeta cluster_views = {};
  const float* cluster_view_directions = nullptr;
  const float* cluster_view_lost = nullptr;

  // Lost contrast of level k (1 <= k < K) seen from view v, orientation t, band b.
  float lost_contrast(std::uint32_t k, std::uint32_t v, std::uint32_t t, std::uint32_t b) const {
    return lost[(((k - 1) * meta.view_count + v) * meta.orientation_count + t) * meta.band_count + b];
  }
  float feature_frequency(std::uint32_t k, std::uint32_t v, std::uint32_t t) const {
    return features[(k * meta.view_count + v) * meta.orientation_count + t];
  }
};

// Validates every offset, size, count and value before use. On failure returns the status and,
// when error is given, fills it; out is left unchanged. Never reads outside [data, data + size).
ProfileStatus open_profile(const void* data, std::size_t size, Profile* out, ProfileError* error = nullptr);
const char* to_string(ProfileStatus status);

// FNV-1a 64 of the blob with the header's checksum field read as zero (writer and reader share it).
std::uint64_t profile_checksum(const void* data, std::size_t size);

// The view lookup's cube map: the cell a unit direction falls in, and a cell's centre direction
// (unit). Cells are numbered face * R * R + row * R + column; faces +X -X +Y -Y +Z -Z.
inline std::uint32_t cube_cell(const float direction[3], std::uint32_t resolution);
void cube_cell_center(std::uint32_t cell, std::uint32_t resolution, float direction[3]);

// ---- inline definitions ----
[[gnu::always_inline]] inline std::uint32_t cube_cell(const float d[3], std::uint32_t r) {
  // Selects only, no branches: a loop over many directions vectorises.
  const float x = d[0], y = d[1], z = d[2];
  const float ax = x < 0 ? -x : x, ay = y < 0 ? -y : y, az = z < 0 ? -z : z;
  const bool on_x = ax >= ay && ax >= az, on_y = !on_x && ay >= az;  // else on z
  const float major = on_x ? ax : on_y ? ay : az, sign = on_x ? x : on_y ? y : z;
  const float u = on_x ? y : on_y ? z : x, v = on_x ? z : on_y ? x : y;
  const int face = (on_x ? 0 : on_y ? 2 : 4) + (sign >= 0 ? 0 : 1);
  const float fr = static_cast<float>(r);
  const float scale = 0.5f * fr / major, half = 0.5f * fr;  // [-major, major] -> [0, r]
  auto index = [&](float t) {
    const float at = t * scale + half, low = 0.0f < at ? at : 0.0f;  // NaN -> 0
    return static_cast<int>(low < fr - 1.0f ? low : fr - 1.0f);
  };
  const int cell = (face * static_cast<int>(r) + index(v)) * static_cast<int>(r) + index(u);
  return major > 0 ? static_cast<std::uint32_t>(cell) : 0u;  // zero or NaN direction: cell 0
}

}  // namespace acuity
