#pragma once
// The simulation behind `acuity simulate`: a scene, a head path and a gaze trace, run frame by
// frame through four rules (perceptual, Reddy, distance, screen-size), the perceptual rule once more
// switching at once ("ungated": no hysteresis, no wait for a saccade), and the perceptual rule and
// the two baselines at a sweep of their tuning, with the chosen levels judged afterwards by
// rendering both levels at the exact view. What a run means is computed by analyse() (acuity/sim/results.hpp).
//
// Conventions as in acuity/scheduler.hpp: metres, degrees, seconds; the head (camera) looks along
// its local -Z with +Y up; gaze directions are unit vectors in head space (both eyes share the
// head's orientation, so head space is eye space; vergence is ignored).
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "acuity/scheduler.hpp"
#include "acuity/sim/generators.hpp"
#include "acuity/sim/scene.hpp"
#include "acuity/sim/tracks.hpp"

namespace acuity::sim {

struct SimulationOptions {
  double seconds = 20, fps = 60;
  unsigned seed = 1;
  std::string head_file, gaze_file;                // empty: the built-in fly-through and gaze generator
  std::uint32_t movers = 3;                        // objects moving on circles (pursuit targets)
  double eye_separation = 0.064;                   // [m]
  std::uint32_t viewport = 1920;                   // per eye, square [px]
  float fov_deg = 90;                              // per eye, full angle
  float saccade_speed = 100;                       // gaze faster than this is a saccade [deg/s]
  Evaluation evaluation = Evaluation::Tabulated;   // the perceptual rule's thresholds
  ThresholdModel model = ThresholdModel::Default;  // the perceptual rule's threshold model (and its
                                                   // sweep's, ungated's); the others ignore it
  std::uint32_t validate = 200;                    // decisions judged by render-and-analyze (0: none)
  std::uint32_t images = 3;                        // frames rendered as PNG
  std::vector<std::string> third_party;            // asset names whose instances the summary reports apart
  std::string output;  // directory for CSV, JSON, images (write_outputs); empty: none
};

// One rule at one tuning, run on every frame.
struct RuleRun {
  std::string name;      // "perceptual", "screen-size", ...
  double parameter = 0;  // quality q (perceptual), pixel_error, distance_scale; else 0
  bool sweep = false;    // part of the tuning sweep, not a main rule
  std::unique_ptr<Scheduler> scheduler;
  std::vector<std::uint8_t> levels;  // [frame * objects + object]
  std::vector<double> drawn;         // [frame] triangles of the objects in view
  double triangles = 0;              // sum of drawn
  std::uint64_t switches = 0, switches_outside_saccades = 0;
};

// The tunings the comparisons sweep, in quarter octaves: the perceptual rule's quality q 0.35..1.41,
// screen-size's pixel error 1/32..8 px, distance's scale 1/4..32; `wider` quarter octaves more at the
// lossy end of q and the safe end of the pixel error (the simulation's sweeps: 0).
struct Tuning {
  const char* name;  // "perceptual", "screen-size", "distance"
  SelectionRule rule;
  double parameter;
};
std::vector<Tuning> swept_tunings(int wider = 0);
// Every rule of acuity::selection_rules() at its default tuning (Reddy has none: 0).
std::vector<Tuning> main_tunings();
// `c` set to `rule` at tuning `parameter` (quality, pixel error or distance scale; else unused).
void tune(SchedulerConfig* c, SelectionRule rule, double parameter);
// How the perceptual rule of `c` decides on a profile like `profile`, as the commands print it:
// "model stela-csf, exact thresholds" (exact also where c asks for tables the model has none of).
std::string perceptual_text(const SchedulerConfig& c, const Profile& profile);

class Simulation {
 public:
  Simulation(const SceneAssets& scene, const SimulationOptions& options);
  ~Simulation();
  std::size_t frame_count() const { return head_.size(); }
  std::size_t frame_index() const { return next_; }
  bool step();  // runs the next frame; false when done
  void run();   // every remaining frame

  const SceneAssets& scene() const { return scene_; }
  const SimulationOptions& options() const { return options_; }
  const std::vector<RuleRun>& rules() const { return rules_; }
  const RuleRun& rule(const std::string& name) const;
  const Frame& frame(std::size_t f) const { return frames_[f]; }
  ObjectTransform transform(std::uint32_t object, std::size_t frame) const;
  glm::dvec3 velocity(std::uint32_t object, std::size_t frame) const;  // world [m/s]
  bool in_view(std::uint32_t object, std::size_t frame) const {
    return in_view_[frame * objects_ + object] != 0;
  }
  bool saccade(std::size_t f) const { return saccade_[f] != 0; }
  const std::vector<HeadPose>& head() const { return head_; }
  const std::vector<GazeSample>& gaze() const { return gaze_; }
  const GeneratedGaze& generated() const { return generated_; }  // empty for a recorded gaze
  double finest(std::size_t f) const { return finest_[f]; }  // triangles of the objects in view at level 0
  double all_finest() const;                                 // the same summed over the frames run

 private:
  const SceneAssets& scene_;
  SimulationOptions options_;
  std::size_t objects_ = 0, next_ = 0;
  std::vector<HeadPose> head_;
  std::vector<GazeSample> gaze_;
  GeneratedGaze generated_;
  std::vector<Mover> movers_;
  std::vector<int> mover_of_;  // per object: index into movers_, or -1
  std::vector<Frame> frames_;
  std::vector<std::uint8_t> in_view_, saccade_;
  std::vector<RuleRun> rules_;
  std::vector<double> finest_;  // [frame]
};

// Ground truth: for sampled (frame, object) decisions in view, the exact view (from the eyes'
// midpoint, the head's up, the object's pose at that frame) rendered at the display's resolution
// (capped), every level against level 0 scored by the judge's detection model (acuity/sim/detection.hpp:
// stelaCSF per point with its eccentricity from the gaze, pooled over space and bands; 1 = just
// detectable). A rule's decision is a visible loss when its level scores above 1.
struct Judged {
  std::uint32_t frame, object, pixels;
  std::array<float, kMaxLevels> scores;  // [level]; level 0 is 0
};
std::vector<Judged> judge_decisions(const Simulation& sim, std::uint32_t count, unsigned seed);

// A decision worth explaining: the middle frame and the object the generated gaze looks at then,
// or else the first object in view; object -1 when there is none (or no frame).
struct Decision {
  std::size_t frame = 0;
  std::int64_t object = -1;
};
Decision example_decision(const Simulation& sim);

// Why the perceptual rule chose the level of `object` in the last frame run: every level's score,
// limiting band and orientation, distance, eccentricity, retinal velocity; the other rules' levels.
std::string explain_text(const Simulation& sim, std::uint32_t object);
// The same for a fresh run of `scene` with `options` (none judged) up to `frame`; `object` is a
// node name or an instance index. Throws std::runtime_error naming what is missing.
std::string explain_frame(const SceneAssets& scene, SimulationOptions options, std::size_t frame,
                          const std::string& object);

}  // namespace acuity::sim
