#pragma once
// The exact-view check both judges share (private to sim/): judge_decisions() for a run's
// decisions, run_sampled() for sampled ones.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "acuity/scheduler.hpp"
#include "acuity/sim/scene.hpp"

namespace acuity::sim {

// An object where it stands: an asset of the scene, its pose, world velocity [m/s] and bounding
// radius [m], seen in `frame` (from its eyes' midpoint, with the first eye's up).
struct ExactView {
  int asset = 0;
  ObjectTransform transform{};
  glm::dvec3 velocity{0.0};
  double radius = 0;
  const Frame* frame = nullptr;
};

struct ExactScores {
  std::uint32_t pixels = 0;                // the snapshot's size
  std::array<float, kMaxLevels> scores{};  // per level; level 0 is 0
};

// Each view rendered at the display's resolution (2 x its angular diameter x `ppd` px/deg, a power
// of two from 64 to 512), every level against level 0, the difference scored by the judge's
// detection model (acuity/sim/detection.hpp): stelaCSF per point of the image with the point's
// eccentricity from the frame's gazes, the object's retinal slip (against the tracked gaze, else
// Daly's pursuit model; a saccade counts as fixation, as the scheduler takes it), the display's white
// at `perceptual`.params.luminance and its Nyquist frequency ppd / 2; without a gaze (a blink, a
// lost tracker) the gaze anywhere within the no-gaze disc, as the rule assumes. Of `perceptual` only
// those, the gaze's confidence floor and the no-gaze radius are read: the judge is not the rule. Views are measured in parallel;
// the result is in their order and does not depend on the thread count.
std::vector<ExactScores> judge_exact_views(const SceneAssets& scene, const std::vector<ExactView>& views,
                                           const SchedulerConfig& perceptual, double ppd);

// The same judge of other triangles of an asset's level 0: view i's `indices[i]` (three per triangle,
// into level 0's vertices: a cluster cut of a hierarchy built on level 0) against level 0 itself.
// Returns one score per view.
std::vector<float> judge_exact_triangles(const SceneAssets& scene, const std::vector<ExactView>& views,
                                         const std::vector<std::vector<std::uint32_t>>& indices,
                                         const SchedulerConfig& perceptual, double ppd);

}  // namespace acuity::sim
