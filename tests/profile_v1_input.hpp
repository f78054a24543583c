#pragma once
// The input of the golden version-1 profile, tests/data/profile_v1.acuity (written by
// tests/data/make_profile_v1.cpp, read back by tests/test_profile.cpp, ProfileGolden). Small, with
// axis-aligned views and every value exactly representable in float, so each field read back can
// be compared for equality with the formula that made it. Never change it: the committed file
// pins what a version-1 profile is.
#include <cstdint>

#include "acuity/spectra/profile_writer.hpp"

namespace acuity::testing {

inline constexpr std::uint32_t kV1Levels = 3, kV1Views = 3, kV1Orientations = 2, kV1Bands = 2;

// Values that encode their own indices, so a layout mistake shows as a wrong number.
inline float v1_lost(std::uint32_t k, std::uint32_t v, std::uint32_t t, std::uint32_t b) {
  return static_cast<float>(1000 * k + 100 * v + 10 * t + b) / 1024.0f;
}
inline float v1_feature(std::uint32_t k, std::uint32_t v, std::uint32_t t) {
  return static_cast<float>(100 * k + 10 * v + t) / 8.0f;
}

inline spectra::ProfileData profile_v1_input() {
  spectra::ProfileData d;
  d.sphere[0] = 0.25f;
  d.sphere[1] = -0.5f;
  d.sphere[2] = 1.0f;
  d.sphere[3] = 2.0f;
  d.snapshot_pixels = 128;
  d.lookup_resolution = 1;  // one cell per cube face: the cell centres are the six axes
  d.levels = {{1000, 0.0f}, {250, 0.125f}, {60, 0.5f}};
  d.views = {spectra::make_view(1, 0, 0), spectra::make_view(0, 1, 0), spectra::make_view(0, 0, -1)};
  d.orientations = {0.0f, 90.0f};
  d.bands = {4.0f, 16.0f};
  for (std::uint32_t k = 1; k < kV1Levels; ++k)
    for (std::uint32_t v = 0; v < kV1Views; ++v)
      for (std::uint32_t t = 0; t < kV1Orientations; ++t)
        for (std::uint32_t b = 0; b < kV1Bands; ++b) d.lost.push_back(v1_lost(k, v, t, b));
  for (std::uint32_t k = 0; k < kV1Levels; ++k)
    for (std::uint32_t v = 0; v < kV1Views; ++v)
      for (std::uint32_t t = 0; t < kV1Orientations; ++t) d.features.push_back(v1_feature(k, v, t));
  return d;
}

}  // namespace acuity::testing
