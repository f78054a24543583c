#include "acuity/sim/run.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace acuity::sim {

void check_options(const SimulationOptions& o) {
  const auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(what);
  };
  require(o.seconds >= 0.01 && o.seconds <= 3600, "seconds: 0.01 to 3600");
  require(o.fps >= 1 && o.fps <= 1000, "fps: 1 to 1000");
  require(o.viewport >= 16 && o.viewport <= 16384, "viewport: 16 to 16384 px");
  require(o.fov_deg >= 10 && o.fov_deg <= 170, "fov: 10 to 170 deg");
  require(o.saccade_speed >= 0 && std::isfinite(o.saccade_speed), "saccade speed: a finite number >= 0");
}

Run simulate(const SceneAssets& scene, const SimulationOptions& options) {
  check_options(options);
  using clock = std::chrono::steady_clock;
  Run run;
  const auto t0 = clock::now();
  run.simulation = std::make_unique<Simulation>(scene, options);
  run.simulation->run();
  const auto t1 = clock::now();
  if (options.validate > 0) run.judged = judge_decisions(*run.simulation, options.validate, options.seed);
  const auto t2 = clock::now();
  run.simulate_seconds = std::chrono::duration<double>(t1 - t0).count();
  run.judge_seconds = std::chrono::duration<double>(t2 - t1).count();
  run.results = analyse(*run.simulation, run.judged);
  if (!options.output.empty())
    run.written = write_outputs(*run.simulation, run.results, run.judged, options.output);
  return run;
}

}  // namespace acuity::sim
