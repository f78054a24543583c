#pragma once
// What a simulation run means, and the files it leaves. analyse() computes the results from a run
// and its judged decisions without changing either; summary_text() formats them as `acuity
// simulate` prints them; write_outputs() writes every output file. Triangles are counted over the
// objects in view; rates of visible losses are fractions of the judged decisions.
#include <cstdint>
#include <string>
#include <vector>

#include "acuity/sim/simulation.hpp"

namespace acuity::sim {

// A baseline tuned to a rule's rate of visible losses: its cheapest sweep entry at or below it.
struct Match {
  int rule = -1;     // index into Simulation::rules(); -1: none is that safe
  double ratio = 0;  // its triangles over the rule's
};

struct Results {
  std::size_t frames = 0, objects = 0, judged = 0;
  double all_finest = 0;                      // triangles per frame, every object in view at level 0
                                              // (the sum over frames times 1 / frames)
  std::vector<std::uint32_t> visible_losses;  // [rule index] among the judged decisions
  int perceptual = 0;                         // index of the main perceptual rule
  Match screen_size, distance;                // the baselines tuned to the perceptual rule's rate
  struct QualityPoint {
    int rule = 0;       // a perceptual sweep entry (quality q)
    Match screen_size;  // the screen-size baseline tuned to its rate
  };
  std::vector<QualityPoint> quality_sweep;  // in the order of the sweep
  // visible_losses[rule] over judged; 0 when nothing was judged.
  double fraction(std::size_t rule) const { return judged > 0 ? visible_losses[rule] / double(judged) : 0.0; }
};

// The results of the frames run so far (sim.frame_index()) and the decisions judged on them.
Results analyse(const Simulation& sim, const std::vector<Judged>& judged);

// The summary `acuity simulate` prints: the rules' triangles, switches and visible losses; with
// judged decisions also the tuned baselines and the perceptual rule's quality sweep.
std::string summary_text(const Simulation& sim, const Results& results);

// Writes into `dir` (created if missing): frames.csv, levels.csv, sweep.csv, judged.csv (when
// decisions were judged), head.csv and gaze.csv (in the formats --head and --gaze read back),
// summary.json and sim.options().images frame pictures frame_NNNN.png (the perceptual rule beside
// the screen-size rule tuned to its visible losses, or at 1 px). Every file is written atomically.
// Returns the paths written, in that order. Throws std::runtime_error naming the file at fault.
std::vector<std::string> write_outputs(const Simulation& sim, const Results& results,
                                       const std::vector<Judged>& judged, const std::string& dir);

// What `acuity simulate` prints after write_outputs: the paths written, a legend of the frame
// pictures, and, unless plot_script is empty, the command that plots the run's CSVs (paths quoted as
// a POSIX shell reads them back; acuity runs no other program itself).
std::string outputs_text(const Results& results, const std::vector<std::string>& written,
                         const std::string& dir, const std::string& plot_script);

// A path as a POSIX shell reads it back: as is when plain, else in single quotes.
std::string shell_quoted(const std::string& path);

}  // namespace acuity::sim
