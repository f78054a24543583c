#pragma once
// Colour conversions shared by the renderer and the snapshot loader.
#include <cmath>

namespace acuity::spectra::detail {

inline float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
// Relative luminance of linear Rec. 709 / sRGB primaries.
inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

}  // namespace acuity::spectra::detail
