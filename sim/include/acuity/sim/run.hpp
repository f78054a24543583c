#pragma once
// acuity/sim/run.hpp — a whole simulation run, as `acuity simulate`, the demo and Python's
// acuity.sim.simulate perform it: every frame through every rule, decisions judged, the results
// analysed and, when options.output is set, every output file written.
#include <memory>
#include <string>
#include <vector>

#include "acuity/sim/results.hpp"

namespace acuity::sim {

struct Run {
  std::unique_ptr<Simulation> simulation;  // refers to the scene: keep the scene alive with it
  std::vector<Judged> judged;              // options.validate decisions
  Results results;
  std::vector<std::string> written;  // write_outputs' paths; empty without options.output
  double simulate_seconds = 0, judge_seconds = 0;
};

// Checks the ranges `acuity simulate` accepts (seconds 0.01-3600, fps 1-1000, viewport 16-16384 px,
// fov 10-170 deg, saccade speed finite and >= 0); throws std::invalid_argument naming the option.
void check_options(const SimulationOptions& options);

// check_options, then the run. Throws what Simulation, judge_decisions and write_outputs throw (std::runtime_error naming the file).
Run simulate(const SceneAssets& scene, const SimulationOptions& options);

}  // namespace acuity::sim
