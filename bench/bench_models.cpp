// Threshold evaluations per second, scalar and batch, float and double, for every model; the
// baseline in the same run is Geisler-Perry's closed form (one exp). Run:
//   build/bench/bench_models --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "acuity/models.hpp"

using namespace acuity;

namespace {
constexpr std::size_t kN = 4096;

template <class T>
struct Inputs {
  std::vector<T> f, e, v, out;
  Inputs() : f(kN), e(kN), v(kN), out(kN) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> uf(0.1, 40), ue(0, 60), uv(0, 30);
    for (std::size_t i = 0; i < kN; ++i) {
      f[i] = T(uf(rng));
      e[i] = T(ue(rng));
      v[i] = T(uv(rng));
    }
  }
};

template <class T>
void BM_threshold_scalar(benchmark::State& state) {
  const auto model = static_cast<ThresholdModel>(state.range(0));
  Inputs<T> in;
  const ModelParams p;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(threshold(in.f[i], in.e[i], in.v[i], model, p));
    i = (i + 1) & (kN - 1);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(to_string(model));
}

template <class T>
void BM_threshold_batch(benchmark::State& state) {
  const auto model = static_cast<ThresholdModel>(state.range(0));
  Inputs<T> in;
  const ModelParams p;
  for (auto _ : state) {
    threshold_batch(kN, in.f.data(), in.e.data(), in.v.data(), in.out.data(), model, p);
    benchmark::DoNotOptimize(in.out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(kN));
  state.SetLabel(to_string(model));
}

void BM_max_visible_frequency(benchmark::State& state) {
  const auto model = static_cast<ThresholdModel>(state.range(0));
  Inputs<double> in;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(max_visible_frequency(0.1, in.e[i], in.v[i], model));
    i = (i + 1) & (kN - 1);
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(to_string(model));
}

void models(benchmark::internal::Benchmark* b) {
  for (int m = 0; m <= int(ThresholdModel::StelaCsf); ++m) b->Arg(m);
}
}  // namespace

BENCHMARK(BM_threshold_scalar<double>)->Apply(models);
BENCHMARK(BM_threshold_scalar<float>)->Apply(models);
BENCHMARK(BM_threshold_batch<double>)->Apply(models);
BENCHMARK(BM_threshold_batch<float>)->Apply(models);
BENCHMARK(BM_max_visible_frequency)->Apply(models);
BENCHMARK_MAIN();
