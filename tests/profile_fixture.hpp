#pragma once
// A small, fully specified profile for tests: K levels, V views spread over the sphere, T
// orientations, B octave bands, lost contrast growing with the level.
#include <cmath>
#include <cstddef>
#include <cstring>

#include "acuity/spectra/profile_writer.hpp"

namespace acuity::testing {

inline spectra::ProfileData small_profile(std::uint32_t K = 4, std::uint32_t V = 6, std::uint32_t T = 4,
                                          std::uint32_t B = 5) {
  spectra::ProfileData d;
  d.sphere[0] = 0.5f;
  d.sphere[1] = -1;
  d.sphere[2] = 2;
  d.sphere[3] = 1.5f;
  for (std::uint32_t k = 0; k < K; ++k) d.levels.push_back({1000u >> k, 0.01f * float(k)});
  const float dirs[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (std::uint32_t v = 0; v < V; ++v) {
    const float* a = dirs[v % 6];
    const float tilt = 0.3f * float(v / 6);
    d.views.push_back(spectra::make_view(a[0] + tilt, a[1] + tilt * 0.5f, a[2] - tilt));
  }
  for (std::uint32_t t = 0; t < T; ++t) d.orientations.push_back(180.0f * float(t) / float(T));
  for (std::uint32_t b = 0; b < B; ++b) d.bands.push_back(4.0f * std::pow(2.0f, float(b)));
  for (std::uint32_t k = 1; k < K; ++k)
    for (std::uint32_t v = 0; v < V; ++v)
      for (std::uint32_t t = 0; t < T; ++t)
        for (std::uint32_t b = 0; b < B; ++b)
          d.lost.push_back(0.002f * float(k * k) * float(1 + b) * (1.0f + 0.1f * float(v + t)));
  for (std::uint32_t k = 0; k < K; ++k)
    for (std::uint32_t v = 0; v < V; ++v)
      for (std::uint32_t t = 0; t < T; ++t) d.features.push_back(64.0f / float(1 << k) + float(t));
  return d;
}

// Rewrites the checksum after a deliberate change, so the structural checks are what is tested.
inline void refresh_checksum(Blob& blob) {
  const std::uint64_t sum = profile_checksum(blob.data(), blob.size);
  std::memcpy(reinterpret_cast<unsigned char*>(blob.storage.data()) + offsetof(ProfileHeader, checksum), &sum,
              sizeof sum);
}

}  // namespace acuity::testing
