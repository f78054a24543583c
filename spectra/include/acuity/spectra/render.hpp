#pragma once
// acuity/spectra/render.hpp — the embedded snapshot renderer (docs/design.md section 7).
// Deterministic CPU rasteriser: orthographic camera framing the bounding sphere so its diameter
// spans `pixels`, supersampled anti-aliasing, linear luminance, headlight Lambert plus ambient,
// base colour factor and texture. Same inputs, same bytes.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "acuity/profile.hpp"

namespace acuity::spectra {

// A triangle mesh by reference (the caller owns the arrays).
struct MeshView {
  const float* positions = nullptr;  // xyz per vertex [object units]
  std::size_t vertex_count = 0;
  const std::uint32_t* indices = nullptr;  // three per triangle
  std::size_t index_count = 0;
  const float* normals = nullptr;    // xyz per vertex, or null: flat shading
  const float* texcoords = nullptr;  // uv per vertex, or null
};

struct Material {
  float base_color[4] = {0.8f, 0.8f, 0.8f, 1.0f};  // linear RGBA factor (glTF baseColorFactor)
  const std::uint8_t* texture = nullptr;           // sRGB, row 0 at the top (glTF convention), or null
  int texture_width = 0, texture_height = 0, texture_channels = 4;
};

struct RenderSettings {
  std::uint32_t pixels = 256;     // across the bounding sphere's diameter (the image is square)
  std::uint32_t supersample = 4;  // samples per pixel along each axis
  float background = 0.5f;        // luminance behind the object (mid grey: local contrast defined everywhere)
  float ambient = 0.2f;           // fraction of the albedo lit without the headlight
  float sphere[4] = {0, 0, 0, 1};  // framing sphere: centre xyz, radius (the finest level's, for every level)
};

// Linear luminance image, row-major, row 0 at the top.
struct Image {
  std::uint32_t width = 0, height = 0;
  std::vector<float> pixels;
  float at(std::uint32_t x, std::uint32_t y) const { return pixels[std::size_t(y) * width + x]; }
};

// The snapshot seen from view.direction (object to camera) with view.up up. Image x runs along
// right = -direction x up, image y (upwards) along up.
Image render_snapshot(const MeshView& mesh, const Material& material, const ProfileView& view,
                      const RenderSettings& settings);

// The smallest sphere-ish bound used for framing: centre of the bounding box, radius to the
// farthest vertex (finite vertices only).
void bounding_sphere(const MeshView& mesh, float sphere[4]);

}  // namespace acuity::spectra
