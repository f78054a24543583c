#pragma once
// Decisions sampled over the conditions instead of along a walk, as issue 15's independent judge
// drew its own: each a random asset of the scene at a random turn, angular size, eccentricity and
// retinal speed, seen once by one eye whose gaze is tracked and still. Every rule at every tuning of
// the simulation's sweeps (swept_tunings) chooses a level for it; each decision is judged at its
// exact view as the simulation's are (judge_decisions); the comparisons are the simulation's
// (at_equal_loss, the oracle, least_triangles), with triangles summed over the decisions.
#include <cstdint>
#include <string>
#include <vector>

#include "acuity/sim/results.hpp"

namespace acuity::sim {

struct SampleOptions {
  std::uint32_t count = 400;
  unsigned seed = 1;
  double min_diameter_deg = 1, max_diameter_deg = 40;  // angular diameter, log-uniform
  double max_eccentricity_deg = 40;                    // the gaze to the object's centre, uniform
  double moving = 0.4;                                 // the fraction of decisions moving
  double min_speed_deg_s = 1, max_speed_deg_s = 30;    // their retinal speed, log-uniform, any direction
  std::uint32_t viewport = 1920;                       // the eye's, square [px]
  float fov_deg = 90;                                  // full angle
  Evaluation evaluation = Evaluation::Tabulated;       // the perceptual rule's
  ThresholdModel model = ThresholdModel::Default;      // the perceptual rule's (its sweep's, margins')
};

struct SampledDecision {
  int asset = 0;
  double diameter_deg = 0, eccentricity_deg = 0, speed_deg_s = 0;  // speed 0: still
  ObjectTransform transform{};
  float velocity[3] = {0, 0, 0};  // world [m/s]
};

struct SampledRun {
  SampleOptions options;
  Frame frame;  // the one eye at the origin looking along -Z, the gaze straight ahead
  std::vector<SampledDecision> decisions;
  std::vector<Judged> judged;  // [decision]: frame 0, object = the decision's index
  // The main rules (perceptual q = 1, reddy, distance scale 1, screen-size 1 px; sweep false), then
  // the sweeps; point.rate: visible losses over the decisions, point.triangles: summed over them.
  std::vector<RuleEntry> rules;
  std::vector<std::vector<std::uint8_t>> levels;  // [rule][decision]
  std::vector<std::uint32_t> visible;             // [rule] decisions judged a visible loss
  double all_finest = 0;                          // every decision at level 0
  SchedulerConfig perceptual;                     // the perceptual rule's (q = 1), whose params judge
  // The perceptual rule (q = 1) with one safety margin changed at a time, over the same judged
  // decisions: what each margin costs in triangles and which losses it prevents. The configuration's
  // (the area law, the gaze's uncertainty, the tables, Max3), then the eccentricity to the sphere's
  // nearest point (each decision seen with the gaze turned away from its object by its angular
  // radius, centre_gaze_frame(): the nearest point where the centre was) and, given profiles without
  // cell bounds, the cell bounds (the same decisions on those profiles).
  struct MarginChange {
    std::string name;
    std::vector<std::uint8_t> levels;  // [decision]
    double triangles = 0;
    std::uint32_t visible = 0;
  };
  std::vector<MarginChange> margins;
};

// Samples, chooses and judges (the judging renders every decision: seconds each on 2 cores).
// own_views (nullable): the scene's assets, in its order, profiled without cell bounds
// (bake::AssetOptions::bound_cells false), to price the cell bounds. Throws std::runtime_error for
// a scene without assets, options out of range or own_views of other assets.
SampledRun run_sampled(const SceneAssets& scene, const SampleOptions& options,
                       const SceneAssets* own_views = nullptr);

// Decision i's frame with the gaze turned away from the object by its angular radius (in the plane
// of the gaze and the object's centre; any direction when they coincide), so that its sphere's
// nearest point lies at the eccentricity its centre had: what the rule would decide if it judged an
// object at its centre's eccentricity, with the same view, size and display density.
Frame centre_gaze_frame(const SceneAssets& scene, const SampledRun& run, std::size_t i);

// What `acuity demo --sampled N` prints: the main rules' triangles and visible losses, the
// baselines and the perceptual sweep at the perceptual rule's rate and at 1%, the oracle and the
// least any rule as safe can draw.
std::string sampled_text(const SceneAssets& scene, const SampledRun& run);

}  // namespace acuity::sim
