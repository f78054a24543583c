// SchedulerConfig's timing: the hysteresis and the wait for a saccade in seconds of the frames' dt
// (the same times at any frame rate), the frame-count aliases, and the hard cases of both.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "acuity/scheduler.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "profile_fixture.hpp"

using namespace acuity;

namespace {

struct Fixture {
  Blob blob = spectra::encode_profile(acuity::testing::small_profile());
  Profile profile{};
  Fixture() { EXPECT_EQ(open_profile(blob.data(), blob.size, &profile), ProfileStatus::Ok); }
};

ObjectTransform at_z(double z) {
  ObjectTransform t;
  t.position[2] = z;
  return t;
}

// One object, near for `near_frames` frames, then far (a coarser level wanted) from then on: the
// time [s] from the last near frame to the frame that draws the coarser level (the sum of the dt of
// the frames that wanted it), or -1 when it never does within max_frames frames. `dts` repeats.
struct Coarsening {
  double seconds = -1;
  int frames = -1;          // frames that wanted it, the changing one included
  bool held_before = true;  // kFlagHeld on every frame that wanted it before the change
};
Coarsening coarsen_after(const SchedulerConfig& config, std::vector<float> dts, int max_frames = 2000) {
  static const Fixture fx;
  SchedulerConfig exact = config;  // the timing is the rules' and evaluations' alike: skip the tables
  exact.evaluation = Evaluation::Exact;
  Scheduler s(exact);
  const ObjectId id = s.add_object(s.add_profile(fx.profile), at_z(-3));
  Frame f;
  f.gaze[0].valid = true;
  f.gaze[0].has_velocity = true;  // a still, tracked gaze: no saccade
  f.dt = 1.0f / 90;
  for (int i = 0; i < 3; ++i) s.run_frame(f);
  const std::uint8_t near_level = s.level(id);
  const float still[3] = {0, 0, 0};
  s.set_velocity(id, still);
  s.set_transform(id, at_z(-400));
  Coarsening r;
  double t = 0;
  for (int k = 0; k < max_frames; ++k) {
    f.dt = dts[std::size_t(k) % dts.size()];
    if (std::isfinite(f.dt) && f.dt > 0) t += f.dt;
    s.run_frame(f);
    if (s.level(id) != near_level) {
      r.seconds = t;
      r.frames = k + 1;
      return r;
    }
    r.held_before = r.held_before && (s.flags(id) & kFlagHeld);
  }
  return r;
}

SchedulerConfig gated(float hysteresis_s, float wait_s) {
  SchedulerConfig c;
  c.max_objects = 4;
  c.hysteresis_seconds = hysteresis_s;
  c.max_coarsen_wait_seconds = wait_s;
  c.saccade_speed = 200;  // gating on; the gaze never moves, so only the wait lets it go
  return c;
}

}  // namespace

// The same seconds, the same time at 72, 90 and 120 Hz: the change lands on the first frame at or
// after the wait, so within one frame of it at each rate and within the longest frame of each other.
TEST(Timing, SameSecondsSameTimesAt72_90_120Hz) {
  const struct {
    float hysteresis, wait;
    bool gate;
  } cases[] = {
      {0.25f, 0.0f, false}, {0.1f, 0.5f, true}, {0.0f, 0.4f, true}, {0.3f, 0.2f, true}, {0.01f, 0, false}};
  for (const auto& k : cases) {
    double first = -1;
    for (const float hz : {72.0f, 90.0f, 120.0f}) {
      SchedulerConfig c = gated(k.hysteresis, k.wait);
      if (!k.gate) c.saccade_speed = 0;
      c.hysteresis_frames = 7;   // ignored: the seconds replace them ...
      c.max_coarsen_wait = 500;  // ... where > 0
      if (k.hysteresis == 0) c.hysteresis_frames = 0;
      const Coarsening r = coarsen_after(c, {1.0f / hz});
      const double want = double(k.hysteresis) + (k.gate ? double(k.wait) : 0.0);
      SCOPED_TRACE(::testing::Message() << hz << " Hz, hysteresis " << k.hysteresis << " s, wait " << k.wait);
      ASSERT_GT(r.seconds, 0);
      EXPECT_GE(r.seconds, want * (1 - 1e-4) - 1e-6);
      EXPECT_LT(r.seconds, want + 1.0 / hz + 1e-6);  // the first frame at or past it
      EXPECT_TRUE(r.held_before);
      if (first < 0) first = r.seconds;
      EXPECT_LT(std::abs(r.seconds - first), 1.0 / 72 + 1e-6);
    }
  }
}

// A varying frame time (a 72/120 Hz mix with a long frame): still the first frame past the wait.
TEST(Timing, VaryingFrameTimesSumTheirDt) {
  const Coarsening r = coarsen_after(gated(0.2f, 0.3f), {1.0f / 120, 1.0f / 72, 0.05f, 1.0f / 90});
  ASSERT_GT(r.seconds, 0);
  EXPECT_GE(r.seconds, 0.5 * (1 - 1e-4));
  EXPECT_LT(r.seconds, 0.5 + 0.05 + 1e-6);
}

// The aliases as before: hysteresis_frames consecutive frames, then max_coarsen_wait frames from
// the frame the hysteresis was met, whatever the dt (frames count one each).
TEST(Timing, FrameCountAliasesCountFrames) {
  for (const float hz : {72.0f, 120.0f}) {
    SchedulerConfig c;
    c.max_objects = 4;
    c.hysteresis_frames = 5;
    EXPECT_EQ(coarsen_after(c, {1.0f / hz}).frames, 5);
    c.saccade_speed = 200;
    c.max_coarsen_wait = 10;
    EXPECT_EQ(coarsen_after(c, {1.0f / hz}).frames, 15);
    c.hysteresis_frames = 0;  // 0 and 1 alike: the first frame meets it
    EXPECT_EQ(coarsen_after(c, {1.0f / hz}).frames, 11);
    c.max_coarsen_wait = 0;
    EXPECT_EQ(coarsen_after(c, {1.0f / hz}).frames, 1);
    // A frame with no dt is still a frame.
    c.hysteresis_frames = 4;
    EXPECT_EQ(coarsen_after(c, {0.0f}).frames, 4);
  }
  // The defaults: no hysteresis, and 30 frames for a saccade when gating is on.
  SchedulerConfig d;
  d.max_objects = 4;
  d.saccade_speed = 200;
  EXPECT_EQ(coarsen_after(d, {1.0f / 90}).frames, 31);
  // Mixed: seconds for one, frames for the other.
  SchedulerConfig m = gated(0.1f, 0);
  m.max_coarsen_wait = 9;  // 9 frames from the frame 0.1 s was met
  EXPECT_EQ(coarsen_after(m, {0.025f}).frames, 4 + 9);
  m = gated(0, 0.1f);
  m.hysteresis_frames = 3;  // then 0.1 s of later frames
  EXPECT_EQ(coarsen_after(m, {0.025f}).frames, 3 + 4);
}

// At a steady rate n frames wait as n x dt seconds.
TEST(Timing, FramesAndSecondsAgreeAtASteadyRate) {
  for (const float hz : {72.0f, 90.0f, 120.0f}) {
    const float dt = 1.0f / hz;
    SchedulerConfig frames;
    frames.max_objects = 4;
    frames.saccade_speed = 200;
    frames.hysteresis_frames = 12;
    frames.max_coarsen_wait = 20;
    const Coarsening by_frames = coarsen_after(frames, {dt});
    const Coarsening by_seconds = coarsen_after(gated(12 * dt, 20 * dt), {dt});
    EXPECT_EQ(by_frames.frames, 32) << hz;
    EXPECT_EQ(by_seconds.frames, by_frames.frames) << hz;
  }
}

// Hard cases. dt 0, negative, NaN or infinite: no time passes (the level waits). A huge dt counts
// in full (the wait is over at once) and the sums saturate below +inf. Seconds +inf: forever;
// NaN or negative: the frame counts apply.
TEST(Timing, HardCases) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const float bad_dt : {0.0f, -0.01f, nan, inf}) {
    EXPECT_EQ(coarsen_after(gated(0.1f, 0.1f), {bad_dt}).frames, -1) << bad_dt;  // not in 2000 frames
  }
  // One good frame among bad ones: only the good frames' time counts.
  const Coarsening mixed = coarsen_after(gated(0.1f, 0.1f), {nan, 0.05f, 0.0f, -1.0f});
  EXPECT_EQ(mixed.frames, 14);  // the fourth good frame (k = 1, 5, 9, 13) reaches 0.2 s
  const float huge = std::numeric_limits<float>::max();
  EXPECT_EQ(coarsen_after(gated(0.1f, 0.1f), {huge}).frames, 1);
  EXPECT_EQ(coarsen_after(gated(1e30f, 1e30f), {huge}).frames, 1);
  // Forever: a hysteresis of +inf never ends, nor does a wait of +inf (however long the frames).
  EXPECT_EQ(coarsen_after(gated(inf, 0.1f), {huge}, 200).frames, -1);
  EXPECT_EQ(coarsen_after(gated(0.1f, inf), {huge}, 200).frames, -1);
  // Not > 0: the frame counts.
  for (const float off : {nan, -1.0f, -inf}) {
    SchedulerConfig c = gated(off, off);
    c.hysteresis_frames = 2;
    c.max_coarsen_wait = 3;
    EXPECT_EQ(coarsen_after(c, {1.0f / 90}).frames, 5) << off;
  }
}
