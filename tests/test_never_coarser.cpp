// The tabulated path is never coarser than the exact one (docs/design.md section 6), searched where
// its tables are hardest: eyes close to the bounding sphere, fast images, slip from a measured
// pursuing gaze, q far from 1, every threshold model and view blend, listed biases and two eyes; on
// two real profiles (made by `acuity lodgen` + `acuity profile`, tests/data/README.md) and random
// synthetic ones. The full run makes over 10^6 decisions (ACUITY_QUICK_TESTS: a tenth).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "acuity/scheduler.hpp"
#include "acuity/spectra/profile_writer.hpp"

#include "random_scene.hpp"

using namespace acuity;

namespace {

constexpr double kPi = 3.14159265358979323846;

using acuity::testing::Rng;

// A profile's bytes (8-byte aligned, as open_profile needs) and the profile read from them.
struct OwnedProfile {
  std::vector<std::uint64_t> bytes;
  Profile profile{};
};

OwnedProfile from_bytes(const void* data, std::size_t size) {
  OwnedProfile p;
  p.bytes.resize((size + 7) / 8);
  std::memcpy(p.bytes.data(), data, size);
  EXPECT_EQ(open_profile(p.bytes.data(), size, &p.profile), ProfileStatus::Ok);
  return p;
}

OwnedProfile read_profile(const std::string& name) {
  std::ifstream f(std::string(ACUITY_TEST_DATA) + "/" + name, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_FALSE(bytes.empty()) << name;
  return from_bytes(bytes.data(), bytes.size());
}

// A random profile shaped like a real one (level k loses contrast above about 2^-k of the top band),
// with random losses per view, orientation and band, some of them 0.
OwnedProfile synthetic_profile(unsigned seed) {
  Rng r(seed);
  spectra::ProfileData d;
  d.sphere[0] = 0.1f;
  d.sphere[1] = 0.2f;
  d.sphere[2] = -0.1f;
  d.sphere[3] = r.log_uniform(0.2f, 2.0f);
  const std::uint32_t K = 3 + seed % 4, T = seed % 2 ? 8 : 4, B = 6 + seed % 3, V = 14;
  for (std::uint32_t k = 0; k < K; ++k) d.levels.push_back({100000u >> k, 0.002f * float((1u << k) - 1)});
  for (std::uint32_t v = 0; v < V; ++v) {
    float a[3];
    r.direction(a);
    d.views.push_back(spectra::make_view(a[0], a[1], a[2]));
  }
  for (std::uint32_t t = 0; t < T; ++t) d.orientations.push_back(180.0f * float(t) / float(T));
  const float lowest = r.log_uniform(0.5f, 4.0f);
  for (std::uint32_t b = 0; b < B; ++b) d.bands.push_back(lowest * std::pow(2.0f, float(b)));
  for (std::uint32_t k = 1; k < K; ++k)
    for (std::uint32_t v = 0; v < V; ++v)
      for (std::uint32_t t = 0; t < T; ++t)
        for (std::uint32_t b = 0; b < B; ++b) {
          const float shape = 1.0f / (1.0f + std::exp(-2.0f * (float(b) - (float(B) - 1.3f * float(k)))));
          const float lost = r.log_uniform(0.02f, 0.5f) * shape + r.log_uniform(1e-4f, 0.02f) * float(k);
          d.lost.push_back(r.chance(0.05f) ? 0.0f : lost);
        }
  for (std::uint32_t k = 0; k < K; ++k)
    for (std::uint32_t v = 0; v < V; ++v)
      for (std::uint32_t t = 0; t < T; ++t)
        d.features.push_back(256.0f / float(1u << k) * (1.0f + 0.1f * float(t % 3)));
  // The area law's inputs (SchedulerConfig::area_law): every other profile a Pooled section (a
  // band's loss pooled over orientations, between the largest channel and their energy, over a
  // random extent), one in four only Detail (the law's bound from the channels), one in four none.
  if (seed % 2 == 0) {
    for (std::uint32_t kv = 0; kv < (K - 1) * V; ++kv)
      for (std::uint32_t b = 0; b < B; ++b) {
        float top = 0, energy = 0;
        for (std::uint32_t t = 0; t < T; ++t) {
          const float c = d.lost[(kv * T + t) * B + b];
          top = std::max(top, c);
          energy += c * c;
        }
        const float peak = top + r.uniform(0, 1) * (std::sqrt(energy) - top);
        d.pooled.push_back(spectra::encode_pooled(peak, r.log_uniform(1e-5f, 1.0f)));
      }
  } else if (seed % 4 == 1) {
    for (std::size_t i = 0; i < d.lost.size(); ++i)
      d.detail.push_back(spectra::encode_detail(r.log_uniform(1e-5f, 1.0f), 0.0f, 0.0f));
  }
  const Blob blob = spectra::encode_profile(d);
  return from_bytes(blob.data(), blob.size);
}

struct Count {
  long total = 0, coarser = 0, differ = 0;
};

// The same objects and frame through a tabulated and an exact scheduler (hysteresis off): counts
// the levels that differ and the tabulated ones coarser than exact, printing each of those.
struct PathPair {
  Scheduler tab, exact;
  int tab_profile, exact_profile;
  PathPair(const SchedulerConfig& c, const Profile& p)
      : tab(with(c, Evaluation::Tabulated)),
        exact(with(c, Evaluation::Exact)),
        tab_profile(tab.add_profile(p)),
        exact_profile(exact.add_profile(p)) {}
  static SchedulerConfig with(SchedulerConfig c, Evaluation e) {
    c.evaluation = e;
    return c;
  }
  void add(const ObjectTransform& t, const float v[3], float bias) {
    const ObjectId a = tab.add_object(tab_profile, t), b = exact.add_object(exact_profile, t);
    ASSERT_EQ(a, b);
    tab.set_velocity(a, v);
    exact.set_velocity(b, v);
    tab.set_bias(a, bias);
    exact.set_bias(b, bias);
  }
  void run(const Frame& f, Count* n, const char* what) {
    tab.run_frame(f);
    exact.run_frame(f);
    for (ObjectId id = 0; id < tab.object_capacity(); ++id) {
      if (!tab.alive(id)) continue;
      ++n->total;
      n->differ += tab.level(id) != exact.level(id);
      if (tab.level(id) > exact.level(id)) {
        ++n->coarser;
        ObjectExplain x{};
        exact.explain(id, &x);
        std::printf(
            "coarser (%s): object %u tabulated %d exact %d; %.4g m, %.4g deg across, e %.3g deg, "
            "image %.4g deg/s, retinal %.4g deg/s\n",
            what, id, tab.level(id), exact.level(id), double(x.distance_m), double(x.angular_diameter_deg),
            double(x.eccentricity_deg), double(x.image_velocity_deg_s), double(x.retinal_velocity_deg_s));
      }
      tab.remove_object(id);
      exact.remove_object(id);
    }
  }
};

// An object of profile p whose bounding sphere (radius r [m]) has its centre at c (world, eye at the
// origin), in a random pose.
ObjectTransform sphere_at(const Profile& p, Rng& rng, const double c[3], double r) {
  ObjectTransform t;
  rng.quaternion(t.rotation);
  t.scale = float(r / p.meta.sphere[3]);
  const float* s = p.meta.sphere;
  const float* q = t.rotation;
  // The profile's centre, scaled and rotated (q v q*), is subtracted so the sphere lands at c.
  const float v[3] = {s[0] * t.scale, s[1] * t.scale, s[2] * t.scale};
  const float u[3] = {2 * (q[1] * v[2] - q[2] * v[1]), 2 * (q[2] * v[0] - q[0] * v[2]),
                      2 * (q[0] * v[1] - q[1] * v[0])};
  const float rotated[3] = {v[0] + q[3] * u[0] + (q[1] * u[2] - q[2] * u[1]),
                            v[1] + q[3] * u[1] + (q[2] * u[0] - q[0] * u[2]),
                            v[2] + q[3] * u[2] + (q[0] * u[1] - q[1] * u[0])};
  for (int k = 0; k < 3; ++k) t.position[k] = c[k] - double(rotated[k]);
  return t;
}

// A velocity [m/s] moving an object at distance d [m] across the view at `deg_s` in a random direction.
void across(Rng& rng, double d, float deg_s, float v[3]) {
  float a[3];
  rng.direction(a);
  for (int k = 0; k < 3; ++k) v[k] = deg_s * float(kPi / 180 * d) * a[k];
}

struct Profiles {
  std::vector<OwnedProfile> all;
  Profiles() {
    all.push_back(read_profile("bull.acuity"));
    all.push_back(read_profile("elephant.acuity"));
    for (unsigned s = 0; s < 4; ++s) all.push_back(synthetic_profile(1000 + s));
  }
};

const Profiles& profiles() {
  static const Profiles p;
  return p;
}

}  // namespace

// The three objects of issue 46 (eye at the origin looking along -Z, 1920 px over 90 deg), each in
// 500 random poses and directions of motion per profile: an eye 1.42 radii from the centre with the
// image at 137 deg/s (with and without gaze, q 1); 36.5 m away, radius 0.98 m, 9.9 deg/s, no gaze,
// q 2; still at 3.18 m, radius 0.158 m, the gaze pursuing at 20 deg/s, q 0.5.
TEST(NeverCoarser, TheObjectsFoundCoarser) {
  struct Case {
    const char* name;
    double d, r;
    float speed, q, pursuit;
    bool gaze;
  };
  const Case cases[] = {{"1.42 radii, 137 deg/s, gaze", 0.382, 0.268, 137, 1.0f, 0, true},
                        {"1.42 radii, 137 deg/s, no gaze", 0.382, 0.268, 137, 1.0f, 0, false},
                        {"36.5 m, 9.9 deg/s, no gaze, q 2", 36.5, 0.98, 9.9f, 2.0f, 0, false},
                        {"still, pursuit 20 deg/s, q 0.5", 3.18, 0.158, 0, 0.5f, 20, true}};
  Rng rng(46);
  for (const Case& k : cases) {
    Count n;
    for (const OwnedProfile& p : profiles().all) {
      SchedulerConfig c;
      c.max_objects = 500;
      c.quality = k.q;
      PathPair pair(c, p.profile);
      for (int i = 0; i < 500; ++i) {
        // Straight ahead, or up to 20 deg off the view axis.
        const float yaw = rng.chance(0.5f) ? 0.0f : rng.uniform(-20, 20) * float(kPi / 180);
        const double centre[3] = {k.d * std::sin(yaw), 0, -k.d * std::cos(yaw)};
        float v[3] = {0, 0, 0};
        if (k.speed > 0) across(rng, k.d, k.speed, v);
        pair.add(sphere_at(p.profile, rng, centre, k.r), v, 1.0f);
      }
      Frame f;
      f.dt = 1.0f / 90;
      f.gaze[0].valid = k.gaze;
      f.gaze[0].has_velocity = k.pursuit > 0;
      f.gaze[0].angular_velocity[1] = k.pursuit;
      pair.run(f, &n, k.name);
    }
    EXPECT_EQ(n.coarser, 0) << k.name;
    std::printf("%-34s %ld coarser, %ld differ of %ld\n", k.name, n.coarser, n.differ, n.total);
  }
}

// Random scenes over the corners: per scene a configuration (model, view blend, q in [0.25, 4],
// hysteresis margin, tabulated biases 0.5 and 2) and a frame (one or two eyes, the head turning at
// 1-200 deg/s or not; gaze, none, or a measured one moving at up to 40 deg/s), then objects 0.1-60 deg across or with the eye 1.01-3 radii
// from the centre, still or moving at 0.05-300 deg/s, of bias 1, a tabulated one or none of those.
TEST(NeverCoarser, TheCornersOfTheTables) {
  const bool quick = std::getenv("ACUITY_QUICK_TESTS") != nullptr;
  const int scenes = 24, frames = quick ? 1 : 4, objects = quick ? 4200 : 10500;
  const ThresholdModel models[] = {ThresholdModel::Default, ThresholdModel::GeislerPerry,
                                   ThresholdModel::Reddy, ThresholdModel::KellyDaly};
  Count n;
  for (int scene = 0; scene < scenes; ++scene) {
    Rng rng(4600u + unsigned(scene));
    const OwnedProfile& p = profiles().all[std::size_t(scene) % profiles().all.size()];
    SchedulerConfig c;
    c.max_objects = std::uint32_t(objects);
    c.model = scene % 2 ? models[std::size_t(scene / 2) % 4] : ThresholdModel::Default;
    c.view_blend = rng.chance(0.3f) ? ViewBlend::Max3 : ViewBlend::Nearest;
    c.quality = rng.chance(0.3f) ? 1.0f : rng.log_uniform(0.25f, 4.0f);
    c.hysteresis_margin = rng.chance(0.2f) ? 0.3f : 0.0f;
    c.tabulated_biases[0] = 0.5f;
    c.tabulated_biases[1] = 2.0f;
    PathPair pair(c, p.profile);
    const float radius = p.profile.meta.sphere[3];
    for (int frame = 0; frame < frames; ++frame) {
      Frame f;
      f.dt = 1.0f / 90;
      f.eye_count = rng.chance(0.3f) ? 2 : 1;
      f.eyes[1].position[0] = 0.064;
      if (rng.chance(0.4f)) {  // the head turns (both eyes): world-still images are still on the retina
        rng.direction(f.eyes[0].angular_velocity);
        const float speed = rng.log_uniform(1.0f, 200.0f);
        for (int k = 0; k < 3; ++k) f.eyes[1].angular_velocity[k] = f.eyes[0].angular_velocity[k] *= speed;
      }
      const bool gaze = rng.chance(0.7f), pursuing = gaze && rng.chance(0.4f);
      for (Gaze& g : f.gaze) {
        const float x = rng.uniform(-0.6f, 0.6f), y = rng.uniform(-0.4f, 0.4f),
                    s = std::sqrt(x * x + y * y + 1);
        g.direction[0] = x / s;
        g.direction[1] = y / s;
        g.direction[2] = -1 / s;
        g.valid = gaze;
        g.has_velocity = pursuing;
        if (pursuing) {
          rng.direction(g.angular_velocity);
          const float speed = rng.log_uniform(0.1f, 40.0f);
          for (float& w : g.angular_velocity) w *= speed;
        }
      }
      for (int i = 0; i < objects; ++i) {
        const double scale = rng.log_uniform(0.05f, 5.0f), r = scale * radius;
        const double d = rng.chance(0.4f) ? r * rng.log_uniform(1.01f, 3.0f)
                                          : r / std::sin(0.5 * rng.log_uniform(0.1f, 60.0f) * kPi / 180);
        const double yaw = rng.uniform(-50, 50) * kPi / 180, pitch = rng.uniform(-40, 40) * kPi / 180;
        const double centre[3] = {d * std::sin(yaw) * std::cos(pitch), d * std::sin(pitch),
                                  -d * std::cos(yaw) * std::cos(pitch)};
        float v[3] = {0, 0, 0};
        if (rng.chance(0.6f)) across(rng, d, rng.log_uniform(0.05f, 300.0f), v);
        const float b = rng.uniform(0, 1);
        pair.add(sphere_at(p.profile, rng, centre, r), v,
                 b < 0.15f   ? 0.5f
                 : b < 0.3f  ? 2.0f
                 : b < 0.35f ? 1.3f
                             : 1.0f);
      }
      char what[64];
      std::snprintf(what, sizeof what, "scene %d, frame %d", scene, frame);
      pair.run(f, &n, what);
    }
  }
  EXPECT_EQ(n.coarser, 0);
  EXPECT_LE(n.differ * 1000, n.total * 5) << n.differ << " of " << n.total << " differ";
  EXPECT_GE(n.total, quick ? 100000 : 1000000);
  std::printf("%ld decisions: %ld coarser, %ld differ (%.3f%%)\n", n.total, n.coarser, n.differ,
              100.0 * double(n.differ) / double(n.total));
}
