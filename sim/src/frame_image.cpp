#include "acuity/sim/frame_image.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <stb_image_write.h>

#include "acuity/file.hpp"

namespace acuity::sim {
namespace {

constexpr std::uint8_t kPalette[8][3] = {{40, 110, 230}, {40, 190, 210}, {70, 190, 70},  {235, 205, 50},
                                         {245, 135, 40}, {220, 50, 50},  {170, 70, 190}, {130, 130, 130}};

void put(RgbImage* im, int x, int y, const std::uint8_t c[3]) {
  if (x < 0 || y < 0 || x >= im->width || y >= im->height) return;
  std::copy(c, c + 3, &im->pixels[(std::size_t(y) * std::size_t(im->width) + std::size_t(x)) * 3]);
}

void append(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  out->insert(out->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
}

}  // namespace

void draw_levels(const Simulation& sim, std::size_t frame, const std::uint8_t* levels, RgbImage* image,
                 int x0) {
  const int n = image->height;
  const double half = 0.5 * n,
               focal = half / std::tan(0.5 * double(sim.options().fov_deg) * 3.14159265358979 / 180);
  const HeadPose& head = sim.head()[frame];
  const glm::dquat to_head = glm::inverse(head.orientation);
  std::vector<float> depth(std::size_t(n) * std::size_t(n), std::numeric_limits<float>::infinity());
  for (int y = 0; y < n; ++y)  // background: a vertical grey gradient
    for (int x = 0; x < n; ++x) {
      const std::uint8_t g = std::uint8_t(70 - 30 * y / n);
      const std::uint8_t c[3] = {g, g, std::uint8_t(g + 8)};
      put(image, x0 + x, y, c);
    }
  const SceneAssets& scene = sim.scene();
  for (std::uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& in = scene.instances[i];
    const Asset& a = scene.assets[std::size_t(in.asset)];
    const std::uint8_t level = std::min<std::uint8_t>(levels[i], std::uint8_t(a.chain.levels.size() - 1));
    const lodgen::Mesh& m = a.chain.levels[level].mesh;
    const ObjectTransform t = sim.transform(i, frame);
    const glm::dquat q(t.rotation[3], t.rotation[0], t.rotation[1], t.rotation[2]);
    const glm::dvec3 p(t.position[0], t.position[1], t.position[2]);
    std::vector<glm::dvec3> h(m.vertex_count());
    for (std::size_t v = 0; v < h.size(); ++v)
      h[v] = to_head * (p +
                        q * (double(t.scale) *
                             glm::dvec3(m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2])) -
                        head.position);
    const std::uint8_t* colour = kPalette[std::min<int>(level, 7)];
    for (std::size_t f = 0; f + 2 < m.indices.size(); f += 3) {
      const glm::dvec3 a3 = h[m.indices[f]], b3 = h[m.indices[f + 1]], c3 = h[m.indices[f + 2]];
      if (a3.z > -0.05 || b3.z > -0.05 || c3.z > -0.05) continue;  // behind or at the near plane
      double sx[3], sy[3];
      const glm::dvec3* v3[3] = {&a3, &b3, &c3};
      for (int k = 0; k < 3; ++k) {
        sx[k] = half + v3[k]->x / -v3[k]->z * focal;
        sy[k] = half - v3[k]->y / -v3[k]->z * focal;
      }
      const double area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sy[1] - sy[0]) * (sx[2] - sx[0]);
      if (!(std::abs(area) > 1e-12)) continue;
      const glm::dvec3 normal = glm::normalize(glm::cross(b3 - a3, c3 - a3));
      const double light = std::abs(glm::dot(normal, glm::normalize(a3 + b3 + c3)));
      const double shade = 0.25 + 0.75 * light;
      const std::uint8_t c[3] = {std::uint8_t(colour[0] * shade), std::uint8_t(colour[1] * shade),
                                 std::uint8_t(colour[2] * shade)};
      const int lx = std::max(0, int(std::floor(std::min({sx[0], sx[1], sx[2]})))),
                hx = std::min(n - 1, int(std::ceil(std::max({sx[0], sx[1], sx[2]}))));
      const int ly = std::max(0, int(std::floor(std::min({sy[0], sy[1], sy[2]})))),
                hy = std::min(n - 1, int(std::ceil(std::max({sy[0], sy[1], sy[2]}))));
      for (int y = ly; y <= hy; ++y)
        for (int x = lx; x <= hx; ++x) {
          const double px = x + 0.5, py = y + 0.5;
          const double w0 = ((sx[1] - px) * (sy[2] - py) - (sy[1] - py) * (sx[2] - px)) / area;
          const double w1 = ((sx[2] - px) * (sy[0] - py) - (sy[2] - py) * (sx[0] - px)) / area;
          const double w2 = 1 - w0 - w1;
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          const float z = float(1.0 / (w0 / -a3.z + w1 / -b3.z + w2 / -c3.z));  // perspective-correct depth
          float& d = depth[std::size_t(y) * std::size_t(n) + std::size_t(x)];
          if (z >= d) continue;
          d = z;
          put(image, x0 + x, y, c);
        }
    }
  }
  // The gaze: a ring of 2 deg radius (white, black rim); nothing during a blink.
  const GazeSample& g = sim.gaze()[frame];
  if (g.confidence > 0 && g.direction.z < -1e-3) {
    const double gx = half + g.direction.x / -g.direction.z * focal,
                 gy = half - g.direction.y / -g.direction.z * focal;
    const double r = focal * std::tan(2.0 * 3.14159265358979 / 180);
    const std::uint8_t white[3] = {255, 255, 255}, black[3] = {0, 0, 0};
    for (int y = int(gy - r - 3); y <= int(gy + r + 3); ++y)
      for (int x = int(gx - r - 3); x <= int(gx + r + 3); ++x) {
        if (x < 0 || x >= n) continue;
        const double d = std::hypot(x + 0.5 - gx, y + 0.5 - gy);
        if (std::abs(d - r) < 1.2)
          put(image, x0 + x, y, white);
        else if (std::abs(d - r) < 2.4 || d < 1.5)
          put(image, x0 + x, y, black);
      }
  }
  for (int l = 0; l < 8; ++l)  // the level swatches, finest first
    for (int y = n - 16; y < n - 4; ++y)
      for (int x = 4 + 14 * l; x < 14 + 14 * l; ++x) put(image, x0 + x, y, kPalette[l]);
}

void write_png(const std::string& path, const RgbImage& image) {
  std::vector<std::uint8_t> png;
  if (!stbi_write_png_to_func(append, &png, image.width, image.height, 3, image.pixels.data(),
                              image.width * 3))
    throw std::runtime_error(path + ": cannot encode PNG");
  io::write_file_atomically(path, png.data(), png.size());
}

}  // namespace acuity::sim
