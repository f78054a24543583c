// The C ABI against the C++ scheduler it wraps: the sized config, all-or-nothing batch calls,
// bias, clamps, transitions and explain give what an acuity::Scheduler given the same input gives.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <thread>
#include <vector>

#include "acuity.h"
#include "acuity/scheduler.hpp"
#include "profile_fixture.hpp"

using namespace acuity;

namespace {

struct Fixture {
  Blob blob = spectra::encode_profile(acuity::testing::small_profile(6));
  Profile profile{};
  Fixture() { EXPECT_EQ(open_profile(blob.data(), blob.size, &profile), ProfileStatus::Ok); }
};

// n objects in a row along -Z, 1 m .. n m away.
struct Scene {
  std::vector<int32_t> profiles;
  std::vector<double> positions;
  std::vector<float> rotations, scales;
  explicit Scene(uint32_t n, int32_t profile = 0) {
    for (uint32_t i = 0; i < n; ++i) {
      profiles.push_back(profile);
      positions.insert(positions.end(), {0.3 * i, 0.0, -1.0 - 3.0 * i});
      rotations.insert(rotations.end(), {0, 0, 0, 1});
      scales.push_back(0.25f);
    }
  }
};

acuity_scheduler* create(const acuity_config& c, const Fixture& f) {
  acuity_scheduler* s = nullptr;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_OK) << acuity_last_error();
  int32_t p = -1;
  EXPECT_EQ(acuity_load_profile(s, f.blob.data(), f.blob.size, &p), ACUITY_OK) << acuity_last_error();
  EXPECT_EQ(p, 0);
  return s;
}

// Scene(16) added to the C scheduler s and to ref (profile 0 in both): the ids, the same in both.
std::vector<uint32_t> add_scene_to_both(acuity_scheduler* s, Scheduler& ref) {
  const Scene scene(16);
  std::vector<uint32_t> ids(16);
  EXPECT_EQ(acuity_add_objects(s, 16, scene.profiles.data(), scene.positions.data(), 0,
                               scene.rotations.data(), 0, scene.scales.data(), ids.data()),
            ACUITY_OK);
  for (uint32_t i = 0; i < 16; ++i) {
    ObjectTransform t;
    for (int k = 0; k < 3; ++k) t.position[k] = scene.positions[3 * i + k];
    t.scale = scene.scales[i];
    EXPECT_EQ(ref.add_object(0, t), ids[i]);
  }
  return ids;
}

acuity_status frame(acuity_scheduler* s, const acuity_eye& eye, float dt) {
  acuity_status st = acuity_begin_frame(s, &eye, 1, dt);
  if (st == ACUITY_OK) st = acuity_update_range(s, 0, 1u << 30);
  if (st == ACUITY_OK) st = acuity_end_frame(s);
  return st;
}

}  // namespace

TEST(CAbi, ConfigDefaultsAreTheCppDefaults) {
  acuity_config c;
  std::memset(&c, 0xAB, sizeof c);
  acuity_config_default(&c);
  const SchedulerConfig d;
  EXPECT_EQ(c.struct_size, sizeof(acuity_config));
  EXPECT_EQ(c.struct_size, ACUITY_CONFIG_SIZE_V7);
  EXPECT_EQ(c.max_views, d.max_views);
  EXPECT_EQ(c.max_view_classes, d.max_view_classes);
  for (std::uint32_t i = 0; i < kMaxTabulatedBiases; ++i)
    EXPECT_EQ(c.tabulated_biases[i], d.tabulated_biases[i]);
  EXPECT_EQ(c.evaluation, uint32_t(ACUITY_EVALUATION_TABULATED));
  EXPECT_EQ(c.max_objects, d.max_objects);
  EXPECT_EQ(c.fallback_level, d.fallback_level);
  EXPECT_EQ(c.min_gaze_confidence, d.min_gaze_confidence);
  EXPECT_EQ(c.max_coarsen_wait, d.max_coarsen_wait);
  EXPECT_EQ(c.hysteresis_seconds, d.hysteresis_seconds);
  EXPECT_EQ(c.max_coarsen_wait_seconds, d.max_coarsen_wait_seconds);
  EXPECT_EQ(c.transition_seconds, d.transition_seconds);
  EXPECT_EQ(c.distance_scale, d.distance_scale);
  EXPECT_EQ(c.pixel_error, d.pixel_error);
  EXPECT_EQ(c.params.ct0, d.params.ct0);
  EXPECT_EQ(c.params.e2, d.params.e2);
  EXPECT_EQ(c.params.csf_fit, unsigned(d.params.fit));
  EXPECT_EQ(c.reserved, 0u);
  EXPECT_EQ(ACUITY_C_API_VERSION, 11);
}

TEST(CAbi, StructSizeGrowthRule) {
  Fixture f;
  acuity_config c;
  acuity_config_default(&c);
  acuity_scheduler* s = reinterpret_cast<acuity_scheduler*>(0x1);
  for (uint32_t bad :
       {0u, 4u, ACUITY_CONFIG_SIZE_V2 - 8, ACUITY_CONFIG_SIZE_V2 + 4, 0xFFFFFFF8u, 0xDEADBEEFu}) {
    c.struct_size = bad;
    EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT) << bad;
    EXPECT_EQ(s, reinterpret_cast<acuity_scheduler*>(0x1)) << "out unchanged on failure";
    EXPECT_NE(std::strstr(acuity_last_error(), "struct_size"), nullptr);
  }
  // A newer caller's larger struct: the tail this library does not know is ignored.
  struct Newer {
    acuity_config v2;
    uint64_t future;
    uint64_t more;
  } n;
  acuity_config_default(&n.v2);
  n.v2.struct_size = sizeof n;
  n.future = 7;
  n.more = ~0ull;
  s = nullptr;
  ASSERT_EQ(acuity_create(&n.v2, &s), ACUITY_OK) << acuity_last_error();
  acuity_destroy(s);
  // Garbage values in known fields are refused.
  acuity_config_default(&c);
  c.model = 9;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
  c.model = ACUITY_MODEL_STELA_CSF + 1;  // the last model is the largest value
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
  c.model = ACUITY_MODEL_STELA_CSF;
  ASSERT_EQ(acuity_create(&c, &s), ACUITY_OK) << acuity_last_error();
  acuity_destroy(s);
  acuity_config_default(&c);
  c.quality = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
  acuity_config_default(&c);
  c.transition_seconds = -1;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
  acuity_config_default(&c);
  c.fallback_level = ACUITY_MAX_LEVELS;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
  acuity_config_default(&c);
  c.params.reserved = 1;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_create(nullptr, &s), ACUITY_INVALID_ARGUMENT);
}

// acuity_config_default writes only the caller's struct: an older caller's smaller struct (here the
// version-2 layout) is not written past, a newer one's larger struct gets zeros past the fields this
// library knows, a size off the growth rule writes nothing; the same for the foveation config.
TEST(CAbi, DefaultsNeverWritePastTheCallersStruct) {
  constexpr unsigned char kGuard = 0xA5;
  unsigned char buffer[sizeof(acuity_config) + 64];
  const auto fill = [&](std::size_t size) {
    std::memset(buffer, kGuard, sizeof buffer);
    acuity_config_default_sized(reinterpret_cast<acuity_config*>(buffer), size);
  };
  const auto untouched = [&](std::size_t from) {
    for (std::size_t i = from; i < sizeof buffer; ++i)
      if (buffer[i] != kGuard) return false;
    return true;
  };
  acuity_config full;
  acuity_config_default(&full);
  EXPECT_EQ(full.struct_size, sizeof full);
  fill(ACUITY_CONFIG_SIZE_V2);  // an older caller
  EXPECT_TRUE(untouched(ACUITY_CONFIG_SIZE_V2));
  uint32_t size = 0;
  std::memcpy(&size, buffer, sizeof size);
  EXPECT_EQ(size, ACUITY_CONFIG_SIZE_V2);
  EXPECT_EQ(
      std::memcmp(buffer + 4, reinterpret_cast<const unsigned char*>(&full) + 4, ACUITY_CONFIG_SIZE_V2 - 4),
      0);
  acuity_scheduler* s = nullptr;  // and it creates a scheduler with the defaults
  ASSERT_EQ(acuity_create(reinterpret_cast<acuity_config*>(buffer), &s), ACUITY_OK) << acuity_last_error();
  acuity_destroy(s);
  fill(sizeof(acuity_config) + 32);  // a newer caller
  EXPECT_TRUE(untouched(sizeof(acuity_config) + 32));
  for (std::size_t i = sizeof(acuity_config); i < sizeof(acuity_config) + 32; ++i)
    EXPECT_EQ(buffer[i], 0) << i;
  for (const std::size_t bad : {std::size_t(0), std::size_t(4), std::size_t(ACUITY_CONFIG_SIZE_V2 - 8),
                                std::size_t(ACUITY_CONFIG_SIZE_V2 + 4), std::size_t(65544)}) {
    fill(bad);
    EXPECT_TRUE(untouched(0)) << bad;
  }
  acuity_config_default_sized(nullptr, sizeof(acuity_config));  // a no-op
  // The foveation config: at least this version's size.
  unsigned char fov[sizeof(acuity_foveation_config) + 16];
  std::memset(fov, kGuard, sizeof fov);
  acuity_foveation_config_default_sized(reinterpret_cast<acuity_foveation_config*>(fov),
                                        sizeof(acuity_foveation_config) - 8);
  for (const unsigned char byte : fov) EXPECT_EQ(byte, kGuard);
  acuity_foveation_config_default_sized(reinterpret_cast<acuity_foveation_config*>(fov),
                                        sizeof(acuity_foveation_config) + 8);
  EXPECT_EQ(fov[sizeof(acuity_foveation_config) + 8], kGuard);
  EXPECT_EQ(fov[sizeof(acuity_foveation_config)], 0);
  acuity_foveation_config plain;
  acuity_foveation_config_default(&plain);
  EXPECT_EQ(plain.struct_size, sizeof plain);
  EXPECT_EQ(std::memcmp(fov + 4, reinterpret_cast<const unsigned char*>(&plain) + 4, sizeof plain - 4), 0);
}

// n objects on a spiral 0.5 .. 150 m away, 0..40 deg off axis, seen by a default eye with gaze;
// levels() runs one frame of a scheduler created from c (every object's bias set to `bias`).
struct Spiral {
  const Fixture& f;
  uint32_t n;
  std::vector<int32_t> profiles;
  std::vector<double> positions;
  std::vector<float> rotations, scales;
  explicit Spiral(const Fixture& fixture, uint32_t count)
      : f(fixture), n(count), profiles(count, 0), scales(count) {
    for (uint32_t i = 0; i < n; ++i) {
      const double z = 0.5 * std::pow(300.0, double(i) / n), a = 0.05 * i;
      positions.insert(positions.end(),
                       {std::sin(a) * 0.7 * z * (i % 7) / 7.0, std::cos(a) * 0.5 * z * (i % 5) / 5.0, -z});
      rotations.insert(rotations.end(), {0, 0, 0, 1});
      scales[i] = 0.1f + 0.4f * float(i % 11) / 11.0f;
    }
  }
  std::vector<uint8_t> levels(acuity_config c, float bias = 1.0f) const {
    c.max_objects = n;
    acuity_scheduler* s = create(c, f);
    std::vector<uint32_t> ids(n);
    EXPECT_EQ(acuity_add_objects(s, n, profiles.data(), positions.data(), 0, rotations.data(), 0,
                                 scales.data(), ids.data()),
              ACUITY_OK);
    const std::vector<float> biases(n, bias);
    EXPECT_EQ(acuity_set_bias(s, n, ids.data(), biases.data()), ACUITY_OK);
    acuity_eye eye;
    acuity_eye_default(&eye);
    eye.gaze_valid = 1;
    EXPECT_EQ(frame(s, eye, 1 / 90.0f), ACUITY_OK);
    std::vector<uint8_t> out(n);
    EXPECT_EQ(acuity_get_levels(s, n, ids.data(), out.data(), nullptr), ACUITY_OK);
    acuity_destroy(s);
    return out;
  }
};

// Never coarser, and different somewhere (so the two runs tell the paths apart).
void expect_finer_somewhere(const std::vector<uint8_t>& finer, const std::vector<uint8_t>& than) {
  int differ = 0;
  for (std::size_t i = 0; i < finer.size(); ++i) {
    EXPECT_LE(finer[i], than[i]);
    differ += finer[i] != than[i];
  }
  EXPECT_GT(differ, 0) << "no object tells the two evaluations apart";
}

// The version-3 field: evaluation reaches the scheduler, a version-2 caller (struct_size 160) gets the
// tabulated default, an unknown value is refused. Seen where the two evaluations choose differently.
TEST(CAbi, EvaluationReachesTheSchedulerAndV2CallersGetTheDefault) {
  Fixture f;
  const Spiral spiral(f, 3000);
  acuity_config c;
  acuity_config_default(&c);
  c.evaluation = ACUITY_EVALUATION_TABULATED;
  const auto tabulated = spiral.levels(c);
  c.evaluation = ACUITY_EVALUATION_EXACT;
  const auto exact = spiral.levels(c);
  c.struct_size = ACUITY_CONFIG_SIZE_V2;  // the field lies past a V2 caller's struct
  const auto v2 = spiral.levels(c);
  expect_finer_somewhere(tabulated, exact);
  EXPECT_EQ(v2, tabulated);
  acuity_config_default(&c);
  c.evaluation = 2;
  acuity_scheduler* s = nullptr;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(s, nullptr);
}

// A scheduler of configuration c for spiral's objects, with f's profile loaded deferred, and an
// eye with a gaze; levels_of_fresh_objects(): the levels the spiral's objects get in a frame where
// they are new (added, the frame run, removed: new objects take their level at once).
struct DeferredSpiral {
  const Spiral& spiral;
  acuity_scheduler* s = nullptr;
  int32_t p = -1;
  acuity_eye eye;
  std::vector<uint32_t> ids;
  DeferredSpiral(const Fixture& f, const Spiral& sp, acuity_config c) : spiral(sp), ids(sp.n) {
    c.max_objects = spiral.n;
    EXPECT_EQ(acuity_create(&c, &s), ACUITY_OK);
    EXPECT_EQ(acuity_load_profile_deferred(s, f.blob.data(), f.blob.size, &p), ACUITY_OK)
        << acuity_last_error();
    acuity_eye_default(&eye);
    eye.gaze_valid = 1;
  }
  ~DeferredSpiral() { acuity_destroy(s); }
  std::vector<uint8_t> levels_of_fresh_objects() {
    EXPECT_EQ(acuity_add_objects(s, spiral.n, spiral.profiles.data(), spiral.positions.data(), 0,
                                 spiral.rotations.data(), 0, spiral.scales.data(), ids.data()),
              ACUITY_OK);
    EXPECT_EQ(frame(s, eye, 1 / 90.0f), ACUITY_OK);
    std::vector<uint8_t> out(spiral.n);
    EXPECT_EQ(acuity_get_levels(s, spiral.n, ids.data(), out.data(), nullptr), ACUITY_OK);
    EXPECT_EQ(acuity_remove_objects(s, spiral.n, ids.data()), ACUITY_OK);
    return out;
  }
};

// Version 10: a profile loaded deferred decides as exact evaluation does until its tables, made on
// another thread, are installed between frames; then (objects added again: new objects take their
// level at once) as a profile loaded with its tables. Misuse is refused and leaves the tables the
// caller's.
TEST(CAbi, DeferredTablesDecideExactlyUntilInstalled) {
  Fixture f;
  const Spiral spiral(f, 3000);
  acuity_config c;
  acuity_config_default(&c);
  const auto tabulated = spiral.levels(c);
  acuity_config exact_config = c;
  exact_config.evaluation = ACUITY_EVALUATION_EXACT;
  const auto exact = spiral.levels(exact_config);
  expect_finer_somewhere(tabulated, exact);
  DeferredSpiral d(f, spiral, c);
  acuity_scheduler* s = d.s;
  const int32_t p = d.p;
  ASSERT_GE(p, 0);
  acuity_tables* made = nullptr;
  std::thread worker([&] { EXPECT_EQ(acuity_make_tables(s, p, &made), ACUITY_OK) << acuity_last_error(); });
  EXPECT_EQ(d.levels_of_fresh_objects(), exact);  // while the tables are made
  worker.join();
  ASSERT_NE(made, nullptr);
  acuity_tables* none = nullptr;
  EXPECT_EQ(acuity_make_tables(s, 1, &none), ACUITY_INVALID_ARGUMENT);  // no such profile
  EXPECT_EQ(none, nullptr);
  EXPECT_EQ(acuity_install_tables(s, 1, made), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_begin_frame(s, &d.eye, 1, 1 / 90.0f), ACUITY_OK);
  EXPECT_EQ(acuity_install_tables(s, p, made), ACUITY_INVALID_ARGUMENT);  // inside a frame
  EXPECT_NE(std::string(acuity_last_error()).find("begin_frame"), std::string::npos);
  EXPECT_EQ(acuity_end_frame(s), ACUITY_OK);
  EXPECT_EQ(acuity_install_tables(s, p, made), ACUITY_OK) << acuity_last_error();
  EXPECT_EQ(d.levels_of_fresh_objects(), tabulated);
  ASSERT_EQ(acuity_make_tables(s, p, &made), ACUITY_OK);
  EXPECT_EQ(acuity_install_tables(s, p, made), ACUITY_INVALID_ARGUMENT);  // it has tables
  acuity_tables_destroy(made);
  acuity_tables_destroy(nullptr);
  const Spiral one(f, 1);
  DeferredSpiral exactly(f, one, exact_config);
  EXPECT_EQ(acuity_make_tables(exactly.s, exactly.p, &none),
            ACUITY_INVALID_ARGUMENT);  // exact evaluation: none
}

// A deferred profile's tables made one view at a time, those acuity_wanted_tables lists (two at a
// call here, so the list continues across calls): after one frame's views are installed, the same
// objects decide as with every table; nothing more is wanted then. acuity_drop_idle_tables frees
// them again (the objects decide as before, their views listed again).
TEST(CAbi, ViewTablesMadeAsWantedDecideAsAllTables) {
  Fixture f;
  const Spiral spiral(f, 3000);
  acuity_config c;
  acuity_config_default(&c);
  const auto tabulated = spiral.levels(c);
  DeferredSpiral d(f, spiral, c);
  acuity_scheduler* s = d.s;
  const int32_t p = d.p;
  ASSERT_GE(p, 0);
  const auto exactly = d.levels_of_fresh_objects();  // their views wanted (removed objects' wants kept)
  int32_t profiles[2];
  uint32_t views[2], count = 99, listed = 0;
  EXPECT_EQ(acuity_begin_frame(s, &d.eye, 1, 1 / 90.0f), ACUITY_OK);
  EXPECT_EQ(acuity_wanted_tables(s, profiles, views, 2, &count), ACUITY_INVALID_ARGUMENT);  // in a frame
  EXPECT_EQ(acuity_end_frame(s), ACUITY_OK);
  EXPECT_EQ(acuity_wanted_tables(s, nullptr, views, 2, &count), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_wanted_tables(s, nullptr, nullptr, 0, &count), ACUITY_OK);
  EXPECT_EQ(count, 0u);
  std::vector<uint8_t> seen(256, 0);  // per view: times listed
  for (;;) {
    ASSERT_EQ(acuity_wanted_tables(s, profiles, views, 2, &count), ACUITY_OK) << acuity_last_error();
    if (count == 0) break;
    for (uint32_t i = 0; i < count; ++i) {
      EXPECT_EQ(profiles[i], p);
      ASSERT_LT(views[i], seen.size());
      EXPECT_EQ(seen[views[i]]++, 0) << "view " << views[i] << " listed twice";
      acuity_tables* made = nullptr;
      ASSERT_EQ(acuity_make_view_tables(s, p, views[i], &made), ACUITY_OK) << acuity_last_error();
      EXPECT_EQ(acuity_install_tables(s, p, made), ACUITY_OK) << acuity_last_error();
      ++listed;
    }
  }
  EXPECT_GT(listed, 0u);
  // The same objects again, fresh (they take their level at once), now through their views' tables.
  EXPECT_EQ(d.levels_of_fresh_objects(), tabulated);
  EXPECT_EQ(acuity_wanted_tables(s, profiles, views, 2, &count), ACUITY_OK);
  EXPECT_EQ(count, 0u);
  acuity_tables* none = nullptr;
  EXPECT_EQ(acuity_make_view_tables(s, p, 1u << 31, &none), ACUITY_INVALID_ARGUMENT);  // no such view
  EXPECT_NE(std::string(acuity_last_error()).find("view"), std::string::npos);
  EXPECT_EQ(none, nullptr);
  // Every view dropped: the objects decide as before their tables, and their views are listed again.
  size_t freed = 0;
  EXPECT_EQ(acuity_begin_frame(s, &d.eye, 1, 1 / 90.0f), ACUITY_OK);
  EXPECT_EQ(acuity_drop_idle_tables(s, 0, &freed), ACUITY_INVALID_ARGUMENT);  // in a frame
  EXPECT_EQ(acuity_end_frame(s), ACUITY_OK);
  EXPECT_EQ(acuity_drop_idle_tables(nullptr, 0, &freed), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_drop_idle_tables(s, 100, &freed), ACUITY_OK);  // read within 100 frames: kept
  EXPECT_EQ(freed, 0u);
  EXPECT_EQ(acuity_drop_idle_tables(s, 0, &freed), ACUITY_OK);
  EXPECT_GT(freed, 0u);
  EXPECT_EQ(acuity_drop_idle_tables(s, 0, nullptr), ACUITY_OK);
  EXPECT_EQ(d.levels_of_fresh_objects(), exactly);
  uint32_t again = 0;
  for (;;) {
    ASSERT_EQ(acuity_wanted_tables(s, profiles, views, 2, &count), ACUITY_OK);
    if (count == 0) break;
    again += count;
  }
  EXPECT_EQ(again, listed);
}

// The version-4 field: objects of a tabulated bias read its tables, as a C++ scheduler configured the
// same way does (never coarser than exact, and not the exact path); a version-3 caller (struct_size
// 168) gets no such tables, so its bias-2 objects take the exact path. Bad entries are refused.
TEST(CAbi, TabulatedBiasesReachTheSchedulerAndV3CallersGetNone) {
  Fixture f;
  const Spiral spiral(f, 3000);
  acuity_config c;
  acuity_config_default(&c);
  c.tabulated_biases[0] = 2.0f;
  const auto tables = spiral.levels(c, 2.0f);
  c.struct_size = ACUITY_CONFIG_SIZE_V3;
  const auto v3 = spiral.levels(c, 2.0f);
  acuity_config_default(&c);
  c.evaluation = ACUITY_EVALUATION_EXACT;
  const auto exact = spiral.levels(c, 2.0f);
  expect_finer_somewhere(tables, exact);
  EXPECT_EQ(v3, exact);
  SchedulerConfig sc;
  sc.max_objects = spiral.n;
  sc.tabulated_biases[0] = 2.0f;
  Scheduler ref(sc);
  ASSERT_EQ(ref.add_profile(f.profile), 0);
  for (uint32_t i = 0; i < spiral.n; ++i) {
    ObjectTransform t;
    for (int k = 0; k < 3; ++k) t.position[k] = spiral.positions[3 * i + k];
    t.scale = spiral.scales[i];
    ref.set_bias(ref.add_object(0, t), 2.0f);
  }
  Frame fr;
  fr.gaze[0].valid = true;
  fr.dt = 1 / 90.0f;
  ref.run_frame(fr);
  for (uint32_t i = 0; i < spiral.n; ++i) EXPECT_EQ(tables[i], ref.level(i)) << i;
  for (const float bad :
       {-1.0f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    acuity_config_default(&c);
    c.tabulated_biases[2] = bad;
    acuity_scheduler* s = nullptr;
    EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT) << bad;
    EXPECT_NE(std::strstr(acuity_last_error(), "tabulated_biases"), nullptr);
  }
  acuity_config_default(&c);
  c.reserved4 = 1;
  acuity_scheduler* s = nullptr;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
}

// The version-6 fields: the waits in seconds of dt reach the scheduler (one object moved far waits
// as a C++ scheduler configured alike); a version-4 caller (struct_size 184) keeps the frame counts;
// negative or non-finite seconds are refused.
TEST(CAbi, TimingSecondsReachTheSchedulerAndV4CallersKeepFrames) {
  Fixture f;
  const auto frames_to_coarsen = [&](const acuity_config& c) {
    acuity_scheduler* s = create(c, f);
    const int32_t profile = 0;
    const double near[3] = {0, 0, -2}, far[3] = {0, 0, -300};
    const float rotation[4] = {0, 0, 0, 1}, still[3] = {0, 0, 0};
    uint32_t id = 0;
    EXPECT_EQ(acuity_add_objects(s, 1, &profile, near, 0, rotation, 0, nullptr, &id), ACUITY_OK);
    EXPECT_EQ(acuity_set_velocities(s, 1, &id, still, 0), ACUITY_OK);
    acuity_eye eye;
    acuity_eye_default(&eye);
    eye.gaze_valid = 1;
    eye.gaze_has_velocity = 1;  // a still gaze: no saccade
    EXPECT_EQ(frame(s, eye, 1.0f / 60), ACUITY_OK);
    uint8_t near_level = 0, level = 0;
    EXPECT_EQ(acuity_get_levels(s, 1, &id, &near_level, nullptr), ACUITY_OK);
    EXPECT_EQ(acuity_set_transforms(s, 1, &id, far, 0, rotation, 0, nullptr), ACUITY_OK);
    int n = 0;
    for (level = near_level; level == near_level && n < 200; ++n) {
      EXPECT_EQ(frame(s, eye, 1.0f / 60), ACUITY_OK);
      EXPECT_EQ(acuity_get_levels(s, 1, &id, &level, nullptr), ACUITY_OK);
    }
    acuity_destroy(s);
    return n;
  };
  acuity_config c;
  acuity_config_default(&c);
  c.saccade_speed_deg_s = 200;
  c.hysteresis_frames = 2;
  c.max_coarsen_wait = 3;
  c.hysteresis_seconds = 0.1f;        // 6 frames at 60 Hz ...
  c.max_coarsen_wait_seconds = 0.2f;  // ... then 12 more
  EXPECT_EQ(frames_to_coarsen(c), 18);
  c.struct_size = ACUITY_CONFIG_SIZE_V4;  // the seconds lie past a version-4 caller's struct
  EXPECT_EQ(frames_to_coarsen(c), 2 + 3);
  acuity_config_default(&c);
  c.saccade_speed_deg_s = 200;
  c.max_coarsen_wait = 3;
  c.hysteresis_seconds = 0.1f;  // seconds for one, frames (from the frame it was met) for the other
  EXPECT_EQ(frames_to_coarsen(c), 6 + 3);
  for (const float bad :
       {-0.5f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    for (const bool wait : {false, true}) {
      acuity_config_default(&c);
      (wait ? c.max_coarsen_wait_seconds : c.hysteresis_seconds) = bad;
      acuity_scheduler* s = nullptr;
      EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT) << bad;
      EXPECT_EQ(s, nullptr);
      EXPECT_NE(std::strstr(acuity_last_error(), wait ? "max_coarsen_wait_seconds" : "hysteresis_seconds"),
                nullptr);
    }
  }
}

// Version 7: views beyond the eyes give the levels per class a C++ scheduler given the same views
// gives (a shadow class of an orthographic and a perspective view, a mirror class AsEye); the checks
// refuse a bad view before beginning anything; a version-6 caller (struct_size 192) has no views.
TEST(CAbi, ViewLevelsAreTheCppSchedulers) {
  Fixture f;
  acuity_config c;
  acuity_config_default(&c);
  c.max_objects = 16;
  c.max_views = 3;
  c.max_view_classes = 2;
  SchedulerConfig sc;
  sc.max_objects = 16;
  sc.max_views = 3;
  sc.max_view_classes = 2;
  acuity_scheduler* s = create(c, f);
  Scheduler ref(sc);
  ASSERT_EQ(ref.add_profile(f.profile), 0);
  const std::vector<uint32_t> ids = add_scene_to_both(s, ref);
  acuity_view views[3];
  View cpp[3];
  for (int i = 0; i < 3; ++i) {
    const View d;
    acuity_view& v = views[i];
    v.view_class = i == 2 ? 1 : 0;
    v.projection = i == 0 ? ACUITY_PROJECTION_ORTHOGRAPHIC : ACUITY_PROJECTION_PERSPECTIVE;
    v.rule = i == 2 ? ACUITY_VIEW_RULE_AS_EYE : ACUITY_VIEW_RULE_FOOTPRINT;
    v.pixel_error = 1.5f;
    const double position[3] = {0.5 * i, 20.0 - 8 * i, 1.0 + i};
    const float down[4] = {-0.7071068f, 0, 0, 0.7071068f};  // -Z turned to -Y: looking down
    std::memcpy(v.position, position, sizeof position);
    if (i < 2)
      std::memcpy(v.orientation, down, sizeof down);
    else
      std::memcpy(v.orientation, d.orientation, sizeof d.orientation);
    std::memcpy(v.fov_deg, d.fov_deg, sizeof v.fov_deg);
    const float extent[4] = {-30, 30, 10, -60};
    std::memcpy(v.extent_m, extent, sizeof extent);
    v.viewport[0] = 512u << i;
    v.viewport[1] = 512u;
    View& w = cpp[i];
    w.view_class = v.view_class;
    w.projection = static_cast<ViewProjection>(v.projection);
    w.rule = static_cast<ViewRule>(v.rule);
    w.pixel_error = v.pixel_error;
    std::memcpy(w.position, v.position, sizeof v.position);
    std::memcpy(w.orientation, v.orientation, sizeof v.orientation);
    std::memcpy(w.extent_m, v.extent_m, sizeof v.extent_m);
    std::memcpy(w.viewport, v.viewport, sizeof v.viewport);
  }
  acuity_eye eye;
  acuity_eye_default(&eye);
  eye.gaze_valid = 1;
  ASSERT_EQ(acuity_begin_frame_views(s, &eye, 1, 1 / 90.0f, views, 3, sizeof(acuity_view)), ACUITY_OK)
      << acuity_last_error();
  ASSERT_EQ(acuity_update_range(s, 0, 16), ACUITY_OK);
  ASSERT_EQ(acuity_end_frame(s), ACUITY_OK);
  Frame fr;
  fr.gaze[0].valid = true;
  fr.dt = 1 / 90.0f;
  fr.views = cpp;
  fr.view_count = 3;
  ref.run_frame(fr);
  std::set<int> seen;
  for (uint32_t cls = 0; cls < 2; ++cls) {
    std::vector<uint8_t> levels(16);
    ASSERT_EQ(acuity_get_view_levels(s, cls, 16, ids.data(), levels.data()), ACUITY_OK);
    for (uint32_t i = 0; i < 16; ++i) {
      EXPECT_EQ(levels[i], ref.view_level_array(cls)[ids[i]]) << cls << " " << i;
      seen.insert(levels[i]);
    }
  }
  EXPECT_GE(seen.size(), 3u) << "the levels should differ across objects and classes";
  // Refusals: nothing begun (a plain begin_frame works next).
  const auto refused = [&](const acuity_view* v, uint32_t n, size_t size, const char* what) {
    EXPECT_EQ(acuity_begin_frame_views(s, &eye, 1, 0.01f, v, n, size), ACUITY_INVALID_ARGUMENT) << what;
    EXPECT_NE(std::strstr(acuity_last_error(), what), nullptr) << acuity_last_error();
  };
  refused(nullptr, 1, sizeof(acuity_view), "null views");
  refused(views, 4, sizeof(acuity_view), "more than max_views");
  refused(views, 1, ACUITY_VIEW_SIZE_V7 - 8, "view_size");
  acuity_view bad = views[1];
  bad.view_class = 2;
  refused(&bad, 1, sizeof bad, "views[0]");
  bad = views[1];
  bad.projection = 2;
  refused(&bad, 1, sizeof bad, "views[0]");
  bad = views[1];
  bad.rule = 9;
  refused(&bad, 1, sizeof bad, "views[0]");
  uint8_t level = 0;
  EXPECT_EQ(acuity_get_view_levels(s, 2, 1, ids.data(), &level), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(frame(s, eye, 0.01f), ACUITY_OK) << acuity_last_error();
  // A newer caller's larger views: the known fields read at its stride.
  struct Newer {
    acuity_view v;
    uint64_t future;
  } newer[3];
  for (int i = 0; i < 3; ++i) newer[i] = {views[i], ~0ull};
  ASSERT_EQ(acuity_begin_frame_views(s, &eye, 1, 0.01f, &newer[0].v, 3, sizeof(Newer)), ACUITY_OK);
  ASSERT_EQ(acuity_update_range(s, 0, 16), ACUITY_OK);
  ASSERT_EQ(acuity_end_frame(s), ACUITY_OK);
  acuity_destroy(s);
  // A version-6 caller: no views (max_views and max_view_classes are 0).
  c.struct_size = ACUITY_CONFIG_SIZE_V6;
  s = create(c, f);
  EXPECT_EQ(acuity_begin_frame_views(s, &eye, 1, 0.01f, views, 1, sizeof(acuity_view)),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_get_view_levels(s, 0, 0, ids.data(), &level), ACUITY_INVALID_ARGUMENT);
  acuity_destroy(s);
  acuity_config_default(&c);
  c.max_views = 1025;
  EXPECT_EQ(acuity_create(&c, &s), ACUITY_INVALID_ARGUMENT);
}

// Every config field reaches the C++ scheduler: the C scheduler and a C++ one configured the same
// way choose the same levels, fades and previous levels for a moving eye.
TEST(CAbi, SameLevelsAndTransitionsAsTheCppScheduler) {
  Fixture f;
  acuity_config c;
  acuity_config_default(&c);
  c.max_objects = 16;
  c.model = ACUITY_MODEL_KELLY_DALY;
  c.view_blend = ACUITY_VIEW_BLEND_MAX3;
  c.quality = 0.8f;
  c.min_gaze_confidence = 0.25f;
  c.transition_seconds = 0.1f;
  c.hysteresis_frames = 2;
  c.max_coarsen_wait = 5;
  c.params.e2 = 3.0;
  c.params.csf_fit = ACUITY_CSF_LAIRD2006;
  SchedulerConfig sc;
  sc.max_objects = 16;
  sc.model = ThresholdModel::KellyDaly;
  sc.view_blend = ViewBlend::Max3;
  sc.quality = 0.8f;
  sc.min_gaze_confidence = 0.25f;
  sc.transition_seconds = 0.1f;
  sc.hysteresis_frames = 2;
  sc.max_coarsen_wait = 5;
  sc.params.e2 = 3.0;
  sc.params.fit = CsfFit::Laird2006;
  acuity_scheduler* s = create(c, f);
  Scheduler ref(sc);
  ASSERT_EQ(ref.add_profile(f.profile), 0);
  const std::vector<uint32_t> ids = add_scene_to_both(s, ref);
  const float bias[2] = {2.0f, 0.5f};
  const uint8_t lo[2] = {1, 0}, hi[2] = {2, 0};
  ASSERT_EQ(acuity_set_bias(s, 2, &ids[3], bias), ACUITY_OK);
  ASSERT_EQ(acuity_set_clamps(s, 2, &ids[5], lo, hi), ACUITY_OK);
  ref.set_bias(ids[3], 2.0f);
  ref.set_bias(ids[4], 0.5f);
  ref.set_clamps(ids[5], 1, 2);
  ref.set_clamps(ids[6], 0, 0);
  int changes = 0;
  for (int n = 0; n < 40; ++n) {
    acuity_eye eye;
    acuity_eye_default(&eye);
    eye.position[2] = 2.0 - 1.5 * n;  // walks through the row
    eye.gaze_valid = 1;
    eye.gaze_direction[0] = 0.3f * std::sin(0.4f * float(n));
    Frame fr;
    fr.eyes[0].position[2] = eye.position[2];
    fr.gaze[0].valid = true;
    std::memcpy(fr.gaze[0].direction, eye.gaze_direction, sizeof eye.gaze_direction);
    fr.dt = 1.0f / 60;
    ASSERT_EQ(frame(s, eye, fr.dt), ACUITY_OK) << acuity_last_error();
    ref.run_frame(fr);
    std::vector<uint8_t> levels(16), flags(16), previous(16);
    std::vector<float> fades(16);
    ASSERT_EQ(acuity_get_levels(s, 16, ids.data(), levels.data(), flags.data()), ACUITY_OK);
    ASSERT_EQ(acuity_get_transitions(s, 16, ids.data(), previous.data(), fades.data()), ACUITY_OK);
    for (uint32_t i = 0; i < 16; ++i) {
      EXPECT_EQ(levels[i], ref.level(ids[i])) << n << " " << i;
      EXPECT_EQ(flags[i], ref.flags(ids[i]));
      EXPECT_EQ(previous[i], ref.previous_level(ids[i]));
      EXPECT_EQ(fades[i], ref.transition(ids[i]));
      changes += (flags[i] & ACUITY_FLAG_CHANGED) != 0;
    }
    // The frame's stats: the C++ scheduler's, and the counts of the flags returned.
    acuity_frame_stats st;
    st.struct_size = sizeof st;
    ASSERT_EQ(acuity_get_frame_stats(s, &st), ACUITY_OK);
    const FrameStats& want = ref.stats();
    EXPECT_EQ(st.struct_size, sizeof st);
    EXPECT_EQ(st.triangles, want.triangles);
    EXPECT_EQ(st.triangles, acuity_frame_triangles(s));
    EXPECT_EQ(st.changed, want.changed);
    EXPECT_EQ(st.invalid, want.invalid);
    EXPECT_EQ(st.budget_forced, want.budget_forced);
    EXPECT_EQ(st.at_rest, want.at_rest);
    EXPECT_EQ(st.gaze_used, want.gaze_used ? 1 : 0);
    std::uint32_t changed = 0;
    for (uint32_t i = 0; i < 16; ++i) changed += (flags[i] & ACUITY_FLAG_CHANGED) != 0;
    EXPECT_EQ(st.changed, changed) << n;
    EXPECT_GE(levels[5], 1);
    EXPECT_LE(levels[5], 2);
    EXPECT_EQ(levels[6], 0);
    if (n == 39) {
      acuity_object_explain e;
      ObjectExplain x;
      ASSERT_EQ(acuity_explain(s, ids[9], &e), ACUITY_OK);
      ASSERT_TRUE(ref.explain(ids[9], &x));
      EXPECT_EQ(e.level, x.level);
      EXPECT_EQ(e.level_count, 6);
      EXPECT_EQ(e.distance_m, x.distance_m);
      EXPECT_EQ(e.eccentricity_deg, x.eccentricity_deg);
      for (int k = 0; k < e.level_count; ++k) EXPECT_EQ(e.levels[k].score, x.levels[k].score);
    }
  }
  EXPECT_GT(changes, 0) << "the walk changes levels, so transitions were exercised";
  acuity_destroy(s);
}

// acuity_get_frame_stats's struct_size: the version-5 size and any larger multiple of 8 up to 65536
// are taken (bytes past the known fields left as they were); anything else, or null, is refused
// with *out untouched.
TEST(CAbi, FrameStatsFollowTheGrowthRule) {
  Fixture f;
  acuity_config c;
  acuity_config_default(&c);
  c.max_objects = 4;
  acuity_scheduler* s = create(c, f);
  Scene scene(3);
  std::vector<uint32_t> ids(3);
  ASSERT_EQ(acuity_add_objects(s, 3, scene.profiles.data(), scene.positions.data(), 0, scene.rotations.data(),
                               0, scene.scales.data(), ids.data()),
            ACUITY_OK);
  acuity_eye eye;
  acuity_eye_default(&eye);
  ASSERT_EQ(frame(s, eye, 1.0f / 60), ACUITY_OK) << acuity_last_error();
  ASSERT_GT(acuity_frame_triangles(s), 0u);
  struct Newer {
    acuity_frame_stats known;
    std::uint64_t later[2];  // fields a newer caller knows of
  } newer;
  std::memset(&newer, 0xab, sizeof newer);
  newer.known.struct_size = sizeof newer;
  ASSERT_EQ(acuity_get_frame_stats(s, &newer.known), ACUITY_OK);
  EXPECT_EQ(newer.known.triangles, acuity_frame_triangles(s));
  EXPECT_EQ(newer.known.struct_size, sizeof newer);
  EXPECT_EQ(newer.known.reserved[0], 0);
  for (const std::uint64_t later : newer.later) EXPECT_EQ(later, 0xababababababababull);
  for (const uint32_t size : {0u, 8u, 24u, ACUITY_FRAME_STATS_SIZE_V5 + 4u, 65544u, 0xffffffffu}) {
    acuity_frame_stats st;
    std::memset(&st, 0xcd, sizeof st);
    st.struct_size = size;
    EXPECT_EQ(acuity_get_frame_stats(s, &st), ACUITY_INVALID_ARGUMENT) << size;
    EXPECT_NE(std::string(acuity_last_error()).find("struct_size"), std::string::npos);
    EXPECT_EQ(st.triangles, 0xcdcdcdcdcdcdcdcdull) << size;
  }
  acuity_frame_stats st;
  st.struct_size = sizeof st;
  EXPECT_EQ(acuity_get_frame_stats(nullptr, &st), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_get_frame_stats(s, nullptr), ACUITY_INVALID_ARGUMENT);
  acuity_destroy(s);
}

TEST(CAbi, FadeRisesByDtOverTransitionSeconds) {
  Fixture f;
  acuity_config c;
  acuity_config_default(&c);
  c.max_objects = 1;
  c.transition_seconds = 0.5f;
  acuity_scheduler* s = create(c, f);
  Scene scene(1);
  uint32_t id = 0;
  ASSERT_EQ(acuity_add_objects(s, 1, scene.profiles.data(), scene.positions.data(), 0, scene.rotations.data(),
                               0, nullptr, &id),
            ACUITY_OK);
  acuity_eye eye;
  acuity_eye_default(&eye);
  ASSERT_EQ(frame(s, eye, 0.125f), ACUITY_OK);
  eye.position[2] = 500;  // far away: a coarser level, fade restarts at 0
  eye.position[0] = 0.3;
  ASSERT_EQ(frame(s, eye, 0.125f), ACUITY_OK);
  uint8_t level = 0, previous = 0, flags = 0;
  float fade = -1;
  ASSERT_EQ(acuity_get_levels(s, 1, &id, &level, &flags), ACUITY_OK);
  ASSERT_EQ(acuity_get_transitions(s, 1, &id, &previous, &fade), ACUITY_OK);
  ASSERT_TRUE(flags & ACUITY_FLAG_CHANGED);
  EXPECT_GT(level, previous);
  EXPECT_EQ(fade, 0.0f);
  for (int n = 1; n <= 5; ++n) {
    ASSERT_EQ(frame(s, eye, 0.125f), ACUITY_OK);
    ASSERT_EQ(acuity_get_transitions(s, 1, &id, nullptr, &fade), ACUITY_OK);
    EXPECT_FLOAT_EQ(fade, std::min(1.0f, 0.25f * float(n)));
  }
  acuity_destroy(s);
}

// A failing batch call changes nothing: bad ids, stale ids, bad values, bad profile indices.
TEST(CAbi, BatchCallsAreAllOrNothing) {
  Fixture f;
  acuity_config c;
  acuity_config_default(&c);
  c.max_objects = 4;
  acuity_scheduler* s = create(c, f);
  Scene scene(4);
  uint32_t ids[4] = {9, 9, 9, 9};
  // A profile index never loaded, in the middle: nothing added, ids untouched.
  Scene bad(3);
  bad.profiles[1] = 5;
  EXPECT_EQ(acuity_add_objects(s, 3, bad.profiles.data(), bad.positions.data(), 0, bad.rotations.data(), 0,
                               nullptr, ids),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(ids[0], 9u);
  bad.profiles[1] = -1;
  EXPECT_EQ(acuity_add_objects(s, 3, bad.profiles.data(), bad.positions.data(), 0, bad.rotations.data(), 0,
                               nullptr, ids),
            ACUITY_INVALID_ARGUMENT);
  ASSERT_EQ(acuity_add_objects(s, 3, scene.profiles.data(), scene.positions.data(), 0, scene.rotations.data(),
                               0, nullptr, ids),
            ACUITY_OK);
  // Two more do not fit in 4: FULL, and the one that would fit was not kept.
  uint32_t more[2] = {9, 9};
  EXPECT_EQ(acuity_add_objects(s, 2, scene.profiles.data(), scene.positions.data(), 0, scene.rotations.data(),
                               0, nullptr, more),
            ACUITY_FULL);
  ASSERT_EQ(acuity_add_objects(s, 1, scene.profiles.data(), scene.positions.data(), 0, scene.rotations.data(),
                               0, nullptr, more),
            ACUITY_OK);
  ids[3] = more[0];
  // Bias: the third value is NaN, so the first two are not applied either (levels unchanged).
  acuity_eye eye;
  acuity_eye_default(&eye);
  eye.position[2] = 5;  // outside every bounding sphere
  ASSERT_EQ(frame(s, eye, 0.01f), ACUITY_OK);
  uint8_t before[4], after[4];
  ASSERT_EQ(acuity_get_levels(s, 4, ids, before, nullptr), ACUITY_OK);
  const float biases[3] = {1000.0f, 1000.0f, std::nanf("")};
  EXPECT_EQ(acuity_set_bias(s, 3, ids, biases), ACUITY_INVALID_ARGUMENT);
  const float zero[1] = {0.0f};
  EXPECT_EQ(acuity_set_bias(s, 1, ids, zero), ACUITY_INVALID_ARGUMENT);
  const uint8_t lo[2] = {5, 5}, hi[2] = {5, 1};
  EXPECT_EQ(acuity_set_clamps(s, 2, ids, lo, hi), ACUITY_INVALID_ARGUMENT);
  ASSERT_EQ(frame(s, eye, 0.01f), ACUITY_OK);
  ASSERT_EQ(acuity_get_levels(s, 4, ids, after, nullptr), ACUITY_OK);
  EXPECT_EQ(std::memcmp(before, after, 4), 0);
  // The same bias alone does coarsen: so the refusal above was what kept the levels.
  ASSERT_EQ(acuity_set_bias(s, 2, ids, biases), ACUITY_OK);
  ASSERT_EQ(frame(s, eye, 0.01f), ACUITY_OK);
  ASSERT_EQ(acuity_get_levels(s, 4, ids, after, nullptr), ACUITY_OK);
  EXPECT_GT(after[0], before[0]);
  // Stale and duplicate ids.
  const uint32_t stale_last[2] = {ids[1], 77};
  EXPECT_EQ(acuity_remove_objects(s, 2, stale_last), ACUITY_INVALID_ARGUMENT);
  const uint32_t twice[2] = {ids[1], ids[1]};
  EXPECT_EQ(acuity_remove_objects(s, 2, twice), ACUITY_INVALID_ARGUMENT);
  uint8_t l = 0;
  EXPECT_EQ(acuity_get_levels(s, 1, &ids[1], &l, nullptr), ACUITY_OK) << "not removed by the failed calls";
  ASSERT_EQ(acuity_remove_objects(s, 1, &ids[1]), ACUITY_OK);
  uint8_t untouched[2] = {42, 42};
  float fades[2] = {-1, -1};
  EXPECT_EQ(acuity_get_levels(s, 2, ids, untouched, nullptr), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(untouched[0], 42);
  EXPECT_EQ(acuity_get_transitions(s, 2, ids, untouched, fades), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(fades[0], -1.0f);
  acuity_object_explain e;
  EXPECT_EQ(acuity_explain(s, ids[1], &e), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_explain(s, 0xFFFFFFFFu, &e), ACUITY_INVALID_ARGUMENT);
  const double p[3] = {0, 0, std::numeric_limits<double>::infinity()};
  const float r[4] = {0, 0, 0, 1};
  EXPECT_EQ(acuity_set_transforms(s, 1, &ids[1], p, 0, r, 0, nullptr), ACUITY_INVALID_ARGUMENT);
  // Frame order.
  EXPECT_EQ(acuity_update_range(s, 0, 4), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_end_frame(s), ACUITY_INVALID_ARGUMENT);
  ASSERT_EQ(acuity_begin_frame(s, &eye, 1, 0.01f), ACUITY_OK);
  EXPECT_EQ(acuity_begin_frame(s, &eye, 1, 0.01f), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_update_range(s, 0xFFFFFFF0u, 0x20u), ACUITY_OK);  // clipped, no wrap-around
  EXPECT_EQ(acuity_update_range(s, 0, 4), ACUITY_OK);
  EXPECT_EQ(acuity_end_frame(s), ACUITY_OK);
  acuity_destroy(s);
}
