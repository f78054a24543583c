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

// One entry of a rule's tuning sweep: its rate of visible losses (a fraction of the judged
// decisions), triangles per frame and tuning (quality q, pixel error, distance scale).
struct SweepPoint {
  double rate = 0, triangles = 0, parameter = 0;
};

// A rule's sweep at a given rate of visible losses. Triangles as a function of the rate is the
// sweep's frontier: at each rate, its cheapest entry at or below that rate (this favours the swept
// rule). Between the two frontier entries that bracket the rate, log triangles and log tuning are
// interpolated linearly in the rate. Below every entry's rate the safest frontier entry is a lower
// bound (a safer tuning needs at least its triangles); above every rate the cheapest entry an upper
// bound.
struct Match {
  enum class Kind { None, Interpolated, AtLeast, AtMost };
  Kind kind = Kind::None;  // None: no valid entry, or the rate is not a number
  int rule = -1;           // the frontier entry at or below the rate (the cheapest that safe); -1: none
  int riskier = -1;  // the frontier entry above the rate it is interpolated towards (AtLeast: the bound)
  double triangles = 0, parameter = 0;  // at the rate (bounds: the bounding entry's)
  double ratio = 0;                     // triangles over the compared rule's (set by analyse)
};
// rule and riskier index `sweep`. Entries whose rate or triangles are not finite, or whose triangles
// are not positive, are ignored.
Match at_equal_loss(const std::vector<SweepPoint>& sweep, double rate);

// A rule at one tuning as the comparisons read it: its name, whether it is a sweep entry, and its
// rate of visible losses, triangles and tuning.
struct RuleEntry {
  std::string name;
  bool sweep = false;
  SweepPoint point;
};
// at_equal_loss over the sweep entries named `name`; the Match's indices index `entries`, its ratio
// is its triangles over `triangles` (none when that is 0).
Match tuned(const std::vector<RuleEntry>& entries, const std::string& name, double rate, double triangles);
// A Match in words: "<triangles> <unit> = <ratio>x <of> (<tuning> ...)", naming the sweep entries
// it lies between (their tuning and rate).
std::string match_text(const std::vector<RuleEntry>& entries, const Match& m, const char* tuning,
                       const char* of, const char* unit);

// A rule against the oracle over judged decisions: per decision, the oracle's level is the
// coarsest the exact-view check finds invisible (score <= 1; level 0 loses nothing).
struct Oracle {
  double rule_triangles = 0, oracle_triangles = 0;  // summed over the decisions added
  std::uint32_t same = 0, finer = 0, coarser = 0;   // decisions by the rule's level against the oracle's
  void add(int level, int oracle, double level_triangles, double oracle_level_triangles);
  double ratio() const;  // rule_triangles / oracle_triangles; NaN when that is 0
};
// A rule's `levels` on judged decisions against the oracle's, decision i of an object with profile
// `profiles[i]` (same-sized vectors).
Oracle against_oracle(const std::vector<const Profile*>& profiles, const std::vector<std::uint8_t>& levels,
                      const std::vector<Judged>& judged);
// The coarsest of the first `levels` levels (at most kMaxLevels) whose score is <= 1; 0 when none is.
int oracle_level(const Judged& judged, std::uint32_t levels);

// The least triangles any rule can draw over decisions when at most `losses` of them may be visible:
// per decision, `invisible` is its cheapest level scoring <= 1 and `any` its cheapest level; the sum
// of `invisible` less the `losses` largest savings any - invisible. Same-sized vectors.
double least_triangles(const std::vector<double>& invisible, const std::vector<double>& any,
                       std::size_t losses);
// The same over judged decisions, decision i of an object with profile `profiles[i]`.
double least_triangles_over(const std::vector<const Profile*>& profiles, const std::vector<Judged>& judged,
                            std::size_t losses);

struct Results {
  std::size_t frames = 0, objects = 0, judged = 0;
  double all_finest = 0;                      // triangles per frame, every object in view at level 0
                                              // (the sum over frames times 1 / frames)
  std::vector<std::uint32_t> visible_losses;  // [rule index] among the judged decisions
  int perceptual = 0;                         // index of the main perceptual rule
  Match screen_size, distance;                // the baselines' sweeps at the perceptual rule's rate
  Oracle oracle;                              // the perceptual rule against the oracle
  Oracle ungated;                             // the "ungated" rule against the oracle
  struct QualityPoint {
    int rule = 0;       // a perceptual sweep entry (quality q)
    Match screen_size;  // the screen-size sweep at its rate
    Oracle oracle;      // it against the oracle
  };
  std::vector<QualityPoint> quality_sweep;  // in the order of the sweep
  // At a 1% rate of visible losses: the perceptual, screen-size and distance sweeps (ratios over
  // the perceptual sweep's triangles there).
  Match one_percent_perceptual, one_percent_screen_size, one_percent_distance;
  // Over the judged decisions, with 1% of them (rounded down) allowed to be visible losses: the least
  // triangles any rule can draw (least_triangles), and screen-size's at 1% (its sweep interpolated as
  // above; 0 unless interpolated or exactly at 1%).
  std::size_t one_percent_losses = 0;
  double least_at_one_percent = 0, screen_size_judged_at_one_percent = 0;
  // The instances of SimulationOptions::third_party's assets.
  struct Group {
    std::size_t objects = 0, judged = 0;
    double all_finest = 0;                      // triangles per frame (sum over frames / frames)
    std::vector<double> triangles;              // [rule] per frame
    std::vector<std::uint32_t> visible_losses;  // [rule] among its judged decisions
    Oracle oracle;                              // the perceptual rule against the oracle on them
  } third_party;
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
