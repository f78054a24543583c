// Snapshot rasteriser. Edge functions with a top-left rule at sample centres, so shared edges are
// covered exactly once; depth test keeps the sample nearest the camera; samples are averaged.
#include "acuity/spectra/render.hpp"

#include "color.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace acuity::spectra {
namespace {

struct V3 {
  float x, y, z;
};
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 normalize(V3 a) {
  const float n = std::sqrt(dot(a, a));
  return n > 0 ? V3{a.x / n, a.y / n, a.z / n} : V3{0, 0, 0};
}
V3 at3(const float* p, std::size_t i) { return {p[3 * i], p[3 * i + 1], p[3 * i + 2]}; }

using detail::luminance;
using detail::srgb_to_linear;

// Texture luminance (linear) at uv, nearest texel, wrapping (glTF REPEAT).
float texture_luminance(const Material& m, float u, float v, const float* lut) {
  const int w = m.texture_width, h = m.texture_height, c = m.texture_channels;
  const float fu = u - std::floor(u), fv = v - std::floor(v);
  const int x = std::min(w - 1, static_cast<int>(fu * static_cast<float>(w)));
  const int y = std::min(h - 1, static_cast<int>(fv * static_cast<float>(h)));
  const std::uint8_t* t = m.texture + (std::size_t(y) * w + x) * c;
  if (c < 3) return lut[t[0]];
  return luminance(lut[t[0]], lut[t[1]], lut[t[2]]);
}

bool top_left(float ex, float ey) { return (ey > 0) || (ey == 0 && ex < 0); }

}  // namespace

void bounding_sphere(const MeshView& mesh, float sphere[4]) {
  float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                 std::numeric_limits<float>::max()};
  float hi[3] = {-lo[0], -lo[1], -lo[2]};
  for (std::size_t i = 0; i < mesh.vertex_count; ++i)
    for (int k = 0; k < 3; ++k) {
      const float x = mesh.positions[3 * i + k];
      if (std::isfinite(x)) {
        lo[k] = std::min(lo[k], x);
        hi[k] = std::max(hi[k], x);
      }
    }
  for (int k = 0; k < 3; ++k) sphere[k] = lo[k] <= hi[k] ? 0.5f * (lo[k] + hi[k]) : 0.0f;
  float r2 = 0;
  for (std::size_t i = 0; i < mesh.vertex_count; ++i) {
    const V3 p = at3(mesh.positions, i);
    const V3 d = sub(p, {sphere[0], sphere[1], sphere[2]});
    if (std::isfinite(dot(d, d))) r2 = std::max(r2, dot(d, d));
  }
  sphere[3] = std::sqrt(r2);
}

Image render_snapshot(const MeshView& mesh, const Material& material, const ProfileView& view,
                      const RenderSettings& s) {
  const std::uint32_t ss = std::max(1u, s.supersample), n = std::max(1u, s.pixels), size = n * ss;
  const V3 dir = normalize({view.direction[0], view.direction[1], view.direction[2]});
  const V3 up = normalize({view.up[0], view.up[1], view.up[2]});
  const V3 right = cross({-dir.x, -dir.y, -dir.z}, up);
  const V3 centre{s.sphere[0], s.sphere[1], s.sphere[2]};
  const float radius = s.sphere[3] > 0 ? s.sphere[3] : 1.0f;
  const float scale = 0.5f * static_cast<float>(size) / radius;  // object units -> samples
  const float half = 0.5f * static_cast<float>(size);

  float lut[256];
  for (int i = 0; i < 256; ++i) lut[i] = srgb_to_linear(static_cast<float>(i) / 255.0f);
  const float base = luminance(material.base_color[0], material.base_color[1], material.base_color[2]);
  const bool textured =
      material.texture && mesh.texcoords && material.texture_width > 0 && material.texture_height > 0;

  std::vector<float> depth(std::size_t(size) * size, -std::numeric_limits<float>::infinity());
  std::vector<float> colour(std::size_t(size) * size, s.background);

  // Project every vertex once: sample-space x, y (y down) and depth towards the camera.
  std::vector<float> sx(mesh.vertex_count), sy(mesh.vertex_count), sz(mesh.vertex_count);
  for (std::size_t i = 0; i < mesh.vertex_count; ++i) {
    const V3 p = sub(at3(mesh.positions, i), centre);
    sx[i] = half + dot(p, right) * scale;
    sy[i] = half - dot(p, up) * scale;
    sz[i] = dot(p, dir);
  }

  for (std::size_t t = 0; t + 2 < mesh.index_count; t += 3) {
    std::uint32_t idx[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
    if (idx[0] >= mesh.vertex_count || idx[1] >= mesh.vertex_count || idx[2] >= mesh.vertex_count) continue;
    float x0 = sx[idx[0]], y0 = sy[idx[0]], x1 = sx[idx[1]], y1 = sy[idx[1]], x2 = sx[idx[2]],
          y2 = sy[idx[2]];
    float area = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0);
    if (!std::isfinite(area) || area == 0) continue;
    if (area < 0) {  // both windings are drawn (two-sided): order them one way
      std::swap(idx[1], idx[2]);
      std::swap(x1, x2);
      std::swap(y1, y2);
      area = -area;
    }
    // Flat normal, facing the camera (two-sided lighting).
    const V3 a = at3(mesh.positions, idx[0]), b = at3(mesh.positions, idx[1]),
             c = at3(mesh.positions, idx[2]);
    V3 face = normalize(cross(sub(b, a), sub(c, a)));
    const float face_light = std::abs(dot(face, dir));

    const int min_x = std::max(0, static_cast<int>(std::floor(std::min({x0, x1, x2}))));
    const int max_x =
        std::min(static_cast<int>(size) - 1, static_cast<int>(std::ceil(std::max({x0, x1, x2}))));
    const int min_y = std::max(0, static_cast<int>(std::floor(std::min({y0, y1, y2}))));
    const int max_y =
        std::min(static_cast<int>(size) - 1, static_cast<int>(std::ceil(std::max({y0, y1, y2}))));
    if (min_x > max_x || min_y > max_y) continue;
    const float inv_area = 1.0f / area;
    // Edge i is opposite vertex i; w_i = edge function, positive inside (y-down, clockwise in image).
    const float ex[3] = {x2 - x1, x0 - x2, x1 - x0}, ey[3] = {y2 - y1, y0 - y2, y1 - y0};
    const float ox[3] = {x1, x2, x0}, oy[3] = {y1, y2, y0};
    bool tl[3];
    for (int e = 0; e < 3; ++e) tl[e] = top_left(ex[e], ey[e]);
    for (int py = min_y; py <= max_y; ++py) {
      const float cy = static_cast<float>(py) + 0.5f;
      for (int px = min_x; px <= max_x; ++px) {
        const float cx = static_cast<float>(px) + 0.5f;
        float w[3];
        bool inside = true;
        for (int e = 0; e < 3 && inside; ++e) {
          w[e] = ex[e] * (cy - oy[e]) - ey[e] * (cx - ox[e]);
          inside = w[e] > 0 || (w[e] == 0 && tl[e]);
        }
        if (!inside) continue;
        const float l0 = w[0] * inv_area, l1 = w[1] * inv_area, l2 = 1.0f - l0 - l1;
        const float z = l0 * sz[idx[0]] + l1 * sz[idx[1]] + l2 * sz[idx[2]];
        const std::size_t at = std::size_t(py) * size + px;
        if (!(z > depth[at])) continue;
        depth[at] = z;
        float light = face_light;
        if (mesh.normals) {
          const V3 nn = normalize(
              {l0 * mesh.normals[3 * idx[0]] + l1 * mesh.normals[3 * idx[1]] + l2 * mesh.normals[3 * idx[2]],
               l0 * mesh.normals[3 * idx[0] + 1] + l1 * mesh.normals[3 * idx[1] + 1] +
                   l2 * mesh.normals[3 * idx[2] + 1],
               l0 * mesh.normals[3 * idx[0] + 2] + l1 * mesh.normals[3 * idx[1] + 2] +
                   l2 * mesh.normals[3 * idx[2] + 2]});
          light = std::abs(dot(nn, dir));
        }
        float albedo = base;
        if (textured) {
          const float u = l0 * mesh.texcoords[2 * idx[0]] + l1 * mesh.texcoords[2 * idx[1]] +
                          l2 * mesh.texcoords[2 * idx[2]];
          const float v = l0 * mesh.texcoords[2 * idx[0] + 1] + l1 * mesh.texcoords[2 * idx[1] + 1] +
                          l2 * mesh.texcoords[2 * idx[2] + 1];
          albedo *= texture_luminance(material, u, v, lut);
        }
        colour[at] = albedo * (s.ambient + (1.0f - s.ambient) * light);
      }
    }
  }

  Image out;
  out.width = out.height = n;
  out.pixels.assign(std::size_t(n) * n, 0.0f);
  const float norm = 1.0f / static_cast<float>(ss * ss);
  for (std::uint32_t y = 0; y < n; ++y)
    for (std::uint32_t x = 0; x < n; ++x) {
      float sum = 0;
      for (std::uint32_t j = 0; j < ss; ++j)
        for (std::uint32_t i = 0; i < ss; ++i) sum += colour[std::size_t(y * ss + j) * size + x * ss + i];
      out.pixels[std::size_t(y) * n + x] = sum * norm;
    }
  return out;
}

}  // namespace acuity::spectra
