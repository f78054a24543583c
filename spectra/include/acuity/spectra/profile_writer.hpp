#pragma once
// acuity/spectra/profile_writer.hpp — builds the profile blob of acuity/profile.hpp.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "acuity/file.hpp"
#include "acuity/profile.hpp"

namespace acuity::spectra {

// The optional Clusters section (acuity::ProfileClusterMeta): what each group of a cluster
// hierarchy loses (acuity/spectra/cluster_loss.hpp measures it).
struct ProfileClusterData {
  std::vector<float> bands;          // [Bc] band centres [cycles per object diameter], increasing
  std::vector<float> lost;           // [G Bc] per group and band, the largest over views and orientations
  std::uint32_t window_pixels = 0;   // pixels across each group's window
  std::uint32_t view_count = 0;      // directions measured per group
  std::uint64_t hierarchy_hash = 0;  // acuity::cluster_hierarchy_hash() of the hierarchy measured
  // The optional ClusterViews section (acuity::ProfileClusterViewsMeta), or both empty: the cells'
  // directions [Vc 3] and per group, cell and band the largest loss over the cell [G Vc Bc] (each at
  // most lost's value of its group and band).
  std::vector<float> view_directions;
  std::vector<float> view_lost;
  std::uint32_t view_samples = 0;  // directions measured per group over all cells (>= Vc)
  bool empty() const { return lost.empty(); }
};

// Everything a profile holds, as plain arrays (layouts as in acuity::Profile).
struct ProfileData {
  float sphere[4] = {0, 0, 0, 1};       // centre xyz, radius [object units]
  std::uint32_t snapshot_pixels = 256;  // pixels across the diameter in the snapshots
  std::vector<ProfileLevel> levels;     // [K], level 0 finest
  std::vector<ProfileView> views;       // [V]
  std::vector<float> orientations;      // [T] degrees in [0, 180), increasing
  std::vector<float> bands;             // [B] cycles per object diameter, increasing
  std::vector<float> lost;              // [(K-1) V T B]
  std::vector<float> features;          // [K V T]
  std::vector<ProfileDetail> detail;    // [(K-1) V T B] as lost, or empty (the optional Detail section)
  std::vector<ProfilePooled> pooled;    // [(K-1) V B], or empty (the optional Pooled section)
  std::uint32_t lookup_resolution = 0;  // cube-map cells per face edge; 0 picks one from V
  ProfileClusterData clusters;          // empty: no Clusters section
};

struct InvalidProfile : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// A view looking from `direction` (any length > 0, object space) with the canonical up: the
// object's +Y made orthogonal to the direction, or +Z when looking along Y.
ProfileView make_view(float x, float y, float z);

// A Detail entry from an area [fraction of the diameter squared] (rounded up: the code never
// under-states the area), a frequency offset [octaves] and a turn [orientation spacings] (each
// rounded to 1/128 and clamped to +-127/128).
ProfileDetail encode_detail(float area, float offset_octaves, float turn = 0.0f);

// A Pooled entry from a peak [contrast] and an area [fraction of the diameter squared], the area
// coded as encode_detail() codes it (rounded up).
ProfilePooled encode_pooled(float lost, float area);

// Encodes data as a version-kProfileVersion blob (8-byte aligned sizes, checksummed). Throws
// InvalidProfile naming the first inconsistency; the result always passes open_profile().
Blob encode_profile(const ProfileData& data);

// encode_profile() written atomically to path. Throws InvalidProfile or std::runtime_error.
void write_profile(const std::string& path, const ProfileData& data);

}  // namespace acuity::spectra
