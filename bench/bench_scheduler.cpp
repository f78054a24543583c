// Scheduler::update throughput for 1k .. 1M objects sharing 100 profiles (6 levels, 8 orientations,
// 8 bands; in the *_one_mesh cases every object is an instance of the first), beside the plain loops
// an engine would write for distance LOD and screen-size LOD, in the same run: the tabulated and the
// exact perceptual path, one thread and two threads on disjoint ranges (this thread and a persistent
// worker released per frame by a barrier, as a host job system would split a frame). Run:
//   build/bench/bench_scheduler --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <barrier>
#include <cmath>
#include <memory>
#include <random>
#include <thread>
#include <vector>

#include "acuity/scheduler.hpp"
#include "acuity/spectra/profile_writer.hpp"

using namespace acuity;

namespace {

constexpr int kProfiles = 100, kLevels = 6, kOrientations = 8, kBands = 8;

struct Library {
  std::vector<Blob> blobs;
  std::vector<Profile> profiles;
  Library() {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0, 1);
    for (int i = 0; i < kProfiles; ++i) {
      spectra::ProfileData d;
      d.sphere[3] = 0.5f + u(rng);
      for (int k = 0; k < kLevels; ++k) d.levels.push_back({20000u >> k, 0.002f * float((1 << k) - 1)});
      const float axes[14][3] = {{1, 0, 0},  {-1, 0, 0},  {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                                 {0, 0, -1}, {1, 1, 1},   {1, 1, -1},  {1, -1, 1},  {1, -1, -1},
                                 {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
      for (const auto& a : axes) d.views.push_back(spectra::make_view(a[0], a[1], a[2]));
      for (int t = 0; t < kOrientations; ++t) d.orientations.push_back(180.0f * float(t) / kOrientations);
      for (int b = 0; b < kBands; ++b) d.bands.push_back(2.0f * std::pow(2.0f, float(b)));
      for (int k = 1; k < kLevels; ++k)
        for (int v = 0; v < 14; ++v)
          for (int t = 0; t < kOrientations; ++t)
            for (int b = 0; b < kBands; ++b)
              d.lost.push_back(0.25f * u(rng) /
                               (1.0f + std::exp(-2.0f * (float(b) - float(kBands) + 1.3f * float(k)))));
      for (int k = 0; k < kLevels; ++k)
        for (int v = 0; v < 14 * kOrientations; ++v) d.features.push_back(256.0f / float(1 << k));
      blobs.push_back(spectra::encode_profile(d));
      Profile p;
      open_profile(blobs.back().data(), blobs.back().size, &p);
      profiles.push_back(p);
    }
  }
};

const Library& library() {
  static const Library lib;
  return lib;
}

// Per-object biases: none; a third each at 0.5, 1 and 2, listed in tabulated_biases (tables of
// their own) or not (the exact path for the biased two thirds).
enum class Biases { None, Listed, Unlisted };

// A field of objects 2..200 m ahead, the gaze sweeping; `moving` of them with velocities.
struct Scene {
  std::unique_ptr<Scheduler> scheduler;
  Frame frame;
  std::vector<double> x, y, z;  // for the baseline loops
  std::vector<int> profile_of;
  Scene(std::uint32_t n, SelectionRule rule, float moving, Evaluation evaluation = Evaluation::Tabulated,
        Biases biases = Biases::None, ThresholdModel model = ThresholdModel::Default,
        int meshes = kProfiles) {
    SchedulerConfig c;
    c.model = model;
    c.max_objects = n;
    c.max_profiles = kProfiles;
    c.rule = rule;
    c.evaluation = evaluation;
    const float bias_of[3] = {0.5f, 1.0f, 2.0f};
    if (biases == Biases::Listed) {
      c.tabulated_biases[0] = bias_of[0];
      c.tabulated_biases[1] = bias_of[2];
    }
    scheduler = std::make_unique<Scheduler>(c);
    for (const Profile& p : library().profiles) scheduler->add_profile(p);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(0, 1);
    for (std::uint32_t i = 0; i < n; ++i) {
      ObjectTransform t;
      t.position[0] = (u(rng) - 0.5) * 200;
      t.position[1] = (u(rng) - 0.5) * 20;
      t.position[2] = -2 - u(rng) * 200;
      float q[4] = {u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f};
      const float len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      for (int k = 0; k < 4; ++k) t.rotation[k] = q[k] / len;
      const int p = static_cast<int>(i % std::uint32_t(meshes));
      const ObjectId id = scheduler->add_object(p, t);
      const float v[3] = {u(rng) < moving ? (u(rng) - 0.5f) * 20 : 0.0f, 0, 0};
      scheduler->set_velocity(id, v);
      if (biases != Biases::None) scheduler->set_bias(id, bias_of[i % 3]);
      x.push_back(t.position[0]);
      y.push_back(t.position[1]);
      z.push_back(t.position[2]);
      profile_of.push_back(p);
    }
    frame.gaze[0].valid = true;
    frame.gaze[0].direction[0] = 0.2f;
    frame.gaze[0].direction[2] = -0.98f;
    frame.dt = 1.0f / 90;
  }
};

void BM_scheduler(benchmark::State& state, SelectionRule rule, float moving,
                  Evaluation evaluation = Evaluation::Tabulated, float head_turn_deg_s = 0,
                  Biases biases = Biases::None, ThresholdModel model = ThresholdModel::Default,
                  int meshes = kProfiles, bool sweep = false, float tremble_m = 0) {
  Scene scene(static_cast<std::uint32_t>(state.range(0)), rule, moving, evaluation, biases, model, meshes);
  scene.frame.eyes[0].angular_velocity[1] = head_turn_deg_s;  // yaw: every image moves
  float yaw = 0;                                              // [deg]
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> tremble(-tremble_m, tremble_m);
  for (auto _ : state) {
    if (tremble_m > 0)  // the eye's position each frame within +-tremble_m of the origin, per axis
      for (double& x : scene.frame.eyes[0].position) x = tremble(rng);
    if (sweep) {  // the head yaws back and forth over +-15 deg, frame by frame
      float& speed = scene.frame.eyes[0].angular_velocity[1];
      yaw += speed * scene.frame.dt;
      if (std::abs(yaw) > 15.0f) speed = yaw > 0 ? -head_turn_deg_s : head_turn_deg_s;
      scene.frame.eyes[0].orientation[1] = std::sin(0.5f * yaw * 3.14159265f / 180.0f);
      scene.frame.eyes[0].orientation[3] = std::cos(0.5f * yaw * 3.14159265f / 180.0f);
    }
    scene.scheduler->run_frame(scene.frame);
    benchmark::DoNotOptimize(scene.scheduler->stats().triangles);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

// Two threads on disjoint ranges, as a host job system would split a frame: this thread and one
// worker, both created before the timed loop and kept for every frame (no thread start-up is
// timed). Per frame: begin_frame; a barrier releases the worker, which updates the second half while
// this thread updates the first; a second barrier joins them; end_frame. std::barrier spins briefly
// and then blocks, so on a loaded machine a waiting thread gives its core back instead of spinning.
void BM_scheduler_2threads(benchmark::State& state, float moving) {
  Scene scene(static_cast<std::uint32_t>(state.range(0)), SelectionRule::Perceptual, moving);
  Scheduler& s = *scene.scheduler;
  const std::uint32_t n = s.object_capacity(), half = n / 2;
  std::barrier<> sync(2);
  bool stop = false;  // written before a barrier, read after it
  std::thread worker([&] {
    while (true) {
      sync.arrive_and_wait();  // released: a frame has begun, or stop
      if (stop) return;
      s.update(half, n - half);
      sync.arrive_and_wait();  // joined
    }
  });
  for (auto _ : state) {
    s.begin_frame(scene.frame);
    sync.arrive_and_wait();
    s.update(0, half);
    sync.arrive_and_wait();
    s.end_frame();
    benchmark::DoNotOptimize(s.stats().triangles);
  }
  stop = true;
  sync.arrive_and_wait();
  worker.join();
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

// What an engine's distance LOD is: per object a distance and a threshold table.
void BM_distance_loop(benchmark::State& state) {
  Scene scene(static_cast<std::uint32_t>(state.range(0)), SelectionRule::Distance, 0);
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<std::uint8_t> level(n);
  float thresholds[kProfiles][kLevels];
  for (int p = 0; p < kProfiles; ++p)
    for (int k = 0; k < kLevels; ++k) thresholds[p][k] = 10.0f * float(k);
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      const float d = static_cast<float>(
          std::sqrt(scene.x[i] * scene.x[i] + scene.y[i] * scene.y[i] + scene.z[i] * scene.z[i]));
      std::uint8_t l = 0;
      for (int k = 1; k < kLevels; ++k) l = d >= thresholds[scene.profile_of[i]][k] ? std::uint8_t(k) : l;
      level[i] = l;
    }
    benchmark::DoNotOptimize(level.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

// Unity-style screen-relative height: projected diameter / viewport height against a table.
void BM_screen_size_loop(benchmark::State& state) {
  Scene scene(static_cast<std::uint32_t>(state.range(0)), SelectionRule::ScreenSize, 0);
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<std::uint8_t> level(n);
  float thresholds[kProfiles][kLevels];
  for (int p = 0; p < kProfiles; ++p)
    for (int k = 0; k < kLevels; ++k) thresholds[p][k] = 0.5f / float(1 << k);
  const float radius = 1.0f, half_tan = 1.0f;
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) {
      const float d = static_cast<float>(
          std::sqrt(scene.x[i] * scene.x[i] + scene.y[i] * scene.y[i] + scene.z[i] * scene.z[i]));
      const float height = radius / (d * half_tan);
      std::uint8_t l = 0;
      for (int k = 1; k < kLevels; ++k)
        l = height <= thresholds[scene.profile_of[i]][k] ? std::uint8_t(k) : l;
      level[i] = l;
    }
    benchmark::DoNotOptimize(level.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

// add_profile for one of the library's 14-view profiles: the tabulated path builds its tables, the
// exact path only its logarithms (the ratio is the tables' set-up cost). A fresh scheduler, made
// outside the timing, whenever the current one is full.
void BM_add_profile(benchmark::State& state, Evaluation evaluation) {
  SchedulerConfig c;
  c.max_objects = 1;
  c.max_profiles = 64;
  c.evaluation = evaluation;
  auto scheduler = std::make_unique<Scheduler>(c);
  const Profile& p = library().profiles[0];
  for (auto _ : state) {
    int index = scheduler->add_profile(p);
    if (index < 0) {
      state.PauseTiming();
      scheduler = std::make_unique<Scheduler>(c);
      state.ResumeTiming();
      index = scheduler->add_profile(p);
    }
    benchmark::DoNotOptimize(index);
  }
  state.counters["table_bytes"] = static_cast<double>(scheduler->table_bytes(0));
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int n : {1000, 10000, 100000, 1000000}) b->Arg(n);
  b->Unit(benchmark::kMillisecond);
}

}  // namespace

BENCHMARK(BM_distance_loop)->Apply(sizes);
BENCHMARK(BM_screen_size_loop)->Apply(sizes);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_static, SelectionRule::Perceptual, 0.0f)->Apply(sizes);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_all_moving, SelectionRule::Perceptual, 1.0f)->Apply(sizes);
// Still objects, the head turning at 30 deg/s (a VR head is never quite still): every image moves.
BENCHMARK_CAPTURE(BM_scheduler, perceptual_head_turning, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 30.0f)
    ->Apply(sizes);
// The same head sweeping +-15 deg at 30 deg/s: each frame its own (the other cases repeat one frame,
// so every remembered decision stands; here eccentricities change as a real head moves them).
BENCHMARK_CAPTURE(BM_scheduler, perceptual_head_sweeping, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 30.0f, Biases::None, ThresholdModel::Default, kProfiles, true)
    ->Apply(sizes);
// The still scene through a head held still: tracking noise moves the eye within +-0.2 mm a frame
// (no velocity reported), so sizes and eccentricities change a little every frame.
BENCHMARK_CAPTURE(BM_scheduler, perceptual_static_trembling, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 0.0f, Biases::None, ThresholdModel::Default, kProfiles, false, 2e-4f)
    ->Apply(sizes);
// The still scene through an eye put anywhere within +-0.5 m each frame with no velocity reported: no
// object stays at rest, so this is what looking for rests costs where none hold.
BENCHMARK_CAPTURE(BM_scheduler, perceptual_static_restless, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 0.0f, Biases::None, ThresholdModel::Default, kProfiles, false, 0.5f)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_static_exact, SelectionRule::Perceptual, 0.0f, Evaluation::Exact)
    ->Apply(sizes);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_all_moving_exact, SelectionRule::Perceptual, 1.0f,
                  Evaluation::Exact)
    ->Apply(sizes);
// Two thirds of the objects biased (0.5 or 2): through their own tables, or, not listed, exactly.
BENCHMARK_CAPTURE(BM_scheduler, perceptual_biased_listed, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 0.0f, Biases::Listed)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_biased_unlisted, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 0.0f, Biases::Unlisted)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
// The perceptual rule with the Reddy step model, through its tables and exactly.
BENCHMARK_CAPTURE(BM_scheduler, perceptual_reddy_model_static, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 0.0f, Biases::None, ThresholdModel::Reddy)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_reddy_model_all_moving, SelectionRule::Perceptual, 1.0f,
                  Evaluation::Tabulated, 0.0f, Biases::None, ThresholdModel::Reddy)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_reddy_model_static_exact, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Exact, 0.0f, Biases::None, ThresholdModel::Reddy)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_reddy_model_all_moving_exact, SelectionRule::Perceptual, 1.0f,
                  Evaluation::Exact, 0.0f, Biases::None, ThresholdModel::Reddy)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
// The perceptual rule with stelaCSF: never through tables (its threshold falls with speed at low
// frequencies), so Tabulated evaluates it exactly; against perceptual_static/_all_moving(_exact).
BENCHMARK_CAPTURE(BM_scheduler, perceptual_stela_model_static, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 0.0f, Biases::None, ThresholdModel::StelaCsf)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_stela_model_all_moving, SelectionRule::Perceptual, 1.0f,
                  Evaluation::Tabulated, 0.0f, Biases::None, ThresholdModel::StelaCsf)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
// Every object an instance of one mesh (foliage, rocks): one profile's tables instead of 100 profiles'.
BENCHMARK_CAPTURE(BM_scheduler, perceptual_static_one_mesh, SelectionRule::Perceptual, 0.0f,
                  Evaluation::Tabulated, 0.0f, Biases::None, ThresholdModel::Default, 1)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_scheduler, perceptual_all_moving_one_mesh, SelectionRule::Perceptual, 1.0f,
                  Evaluation::Tabulated, 0.0f, Biases::None, ThresholdModel::Default, 1)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_scheduler_2threads, perceptual_static, 0.0f)->Apply(sizes)->UseRealTime();
BENCHMARK_CAPTURE(BM_scheduler_2threads, perceptual_all_moving, 1.0f)->Apply(sizes)->UseRealTime();
BENCHMARK_CAPTURE(BM_scheduler, reddy_static, SelectionRule::Reddy, 0.0f)->Apply(sizes);
BENCHMARK_CAPTURE(BM_scheduler, distance_rule, SelectionRule::Distance, 0.0f)->Apply(sizes);
BENCHMARK_CAPTURE(BM_scheduler, screen_size_rule, SelectionRule::ScreenSize, 0.0f)->Apply(sizes);
BENCHMARK_CAPTURE(BM_add_profile, tabulated, Evaluation::Tabulated)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_add_profile, exact, Evaluation::Exact)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
