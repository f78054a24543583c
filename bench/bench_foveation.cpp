// One eye's foveation plan (shading-rate and mip-bias maps) for a 2000 x 2000 display over 100 deg
// at tile 16, against the baseline measured in the same run: filling the same two maps with a
// constant. The budget is 0.1 ms per eye on one core. Run:
//   build/bench/bench_foveation --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "acuity/foveation_plan.hpp"

using namespace acuity;

namespace {
Eye display_eye() {
  Eye eye;
  eye.fov_deg[0] = -50;
  eye.fov_deg[1] = 50;
  eye.fov_deg[2] = 50;
  eye.fov_deg[3] = -50;
  eye.viewport[0] = eye.viewport[1] = 2000;
  return eye;
}

struct Buffers {
  std::uint32_t cols = 0, rows = 0;
  std::vector<std::uint8_t> rate;
  std::vector<float> bias;
  FoveationMaps maps;
  explicit Buffers(const Eye& eye, std::uint32_t tile) {
    foveation_map_size(eye, tile, &cols, &rows);
    rate.resize(2 * std::size_t(cols) * rows);
    bias.resize(std::size_t(cols) * rows);
    maps.tile_px = tile;
    maps.capacity = cols * rows;
    maps.shading_rate = rate.data();
    maps.mip_bias = bias.data();
  }
};

// state.range(0): 0 gaze centred, 1 gaze 20 deg right and 10 up, 2 no gaze, 3 head turning 100 deg/s.
void BM_plan_foveation(benchmark::State& state) {
  auto planner = std::make_unique<FoveationPlanner>();
  init_foveation_planner(FoveationConfig{}, planner.get());
  Eye eye = display_eye();
  Buffers b(eye, static_cast<std::uint32_t>(state.range(1)));
  Gaze gaze;
  gaze.valid = state.range(0) != 2;
  if (state.range(0) == 1) {
    gaze.direction[0] = 0.34f;
    gaze.direction[1] = 0.17f;
    gaze.direction[2] = -0.92f;
  }
  if (state.range(0) == 3) eye.angular_velocity[1] = 100;
  for (auto _ : state) {
    plan_foveation(*planner, eye, gaze, &b.maps);
    benchmark::DoNotOptimize(b.rate.data());
    benchmark::DoNotOptimize(b.bias.data());
    benchmark::ClobberMemory();
  }
  state.counters["saved"] = 1.0 - b.maps.shaded / b.maps.pixels;
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.cols) * b.rows);
}
BENCHMARK(BM_plan_foveation)->ArgsProduct({{0, 1, 2, 3}, {16}})->Args({0, 8})->Args({0, 32});

// Baseline: the same maps filled with a constant.
void BM_fill_constant(benchmark::State& state) {
  Buffers b(display_eye(), static_cast<std::uint32_t>(state.range(0)));
  for (auto _ : state) {
    std::fill(b.rate.begin(), b.rate.end(), std::uint8_t(1));
    std::fill(b.bias.begin(), b.bias.end(), 0.0f);
    benchmark::DoNotOptimize(b.rate.data());
    benchmark::DoNotOptimize(b.bias.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(b.cols) * b.rows);
}
BENCHMARK(BM_fill_constant)->Arg(16);

// Building the tables: once per configuration.
void BM_init_planner(benchmark::State& state) {
  auto planner = std::make_unique<FoveationPlanner>();
  for (auto _ : state) benchmark::DoNotOptimize(init_foveation_planner(FoveationConfig{}, planner.get()));
}
BENCHMARK(BM_init_planner)->Unit(benchmark::kMillisecond);
// The same with stelaCSF, whose inverse is a scan and a root search (models.hpp).
void BM_init_planner_stela(benchmark::State& state) {
  auto planner = std::make_unique<FoveationPlanner>();
  FoveationConfig config;
  config.model = ThresholdModel::StelaCsf;
  for (auto _ : state) benchmark::DoNotOptimize(init_foveation_planner(config, planner.get()));
}
BENCHMARK(BM_init_planner_stela)->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();
