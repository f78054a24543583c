#pragma once
// Meshes with known answers for tests and benchmarks: an icosphere (radius r, subdivided).
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace acuity::testing {

struct TestMesh {
  std::vector<float> positions, normals;
  std::vector<std::uint32_t> indices;
};

inline TestMesh icosphere(int subdivisions, float radius = 1.0f) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<float> p = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t,
                          0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
  std::vector<std::uint32_t> f = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                                  11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
                                  3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  auto normalize = [&](std::uint32_t i) {
    const float n = std::sqrt(p[3 * i] * p[3 * i] + p[3 * i + 1] * p[3 * i + 1] + p[3 * i + 2] * p[3 * i + 2]);
    for (int k = 0; k < 3; ++k) p[3 * i + k] /= n;
  };
  for (std::uint32_t i = 0; i < 12; ++i) normalize(i);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const std::uint32_t i = static_cast<std::uint32_t>(p.size() / 3);
      for (int k = 0; k < 3; ++k) p.push_back(0.5f * (p[3 * a + k] + p[3 * b + k]));
      normalize(i);
      mid[key] = i;
      return i;
    };
    std::vector<std::uint32_t> g;
    for (std::size_t i = 0; i < f.size(); i += 3) {
      const std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      for (std::uint32_t x : {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca}) g.push_back(x);
    }
    f = std::move(g);
  }
  TestMesh m;
  m.normals = p;
  for (float& x : p) x *= radius;
  m.positions = std::move(p);
  m.indices = std::move(f);
  return m;
}

}  // namespace acuity::testing
