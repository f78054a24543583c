#pragma once
// Random numbers for the scheduler's property tests: one generator, seeded, the same sequence on
// every machine for the distributions' implementations of libstdc++.
#include <cmath>
#include <random>

namespace acuity::testing {

struct Rng {
  std::mt19937 g;
  explicit Rng(unsigned seed) : g(seed) {}
  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(g); }
  float log_uniform(float lo, float hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  bool chance(float p) { return uniform(0, 1) < p; }
  // A uniformly random unit quaternion (x y z w).
  void quaternion(float q[4]) {
    std::normal_distribution<float> n;
    float s = 0;
    for (int i = 0; i < 4; ++i) {
      q[i] = n(g);
      s += q[i] * q[i];
    }
    s = std::sqrt(s);
    for (int i = 0; i < 4; ++i) q[i] /= s;
  }
  // A uniformly random unit vector.
  void direction(float v[3]) {
    float q[4];
    quaternion(q);
    const float s = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    for (int i = 0; i < 3; ++i) v[i] = q[i] / s;
  }
};

}  // namespace acuity::testing
