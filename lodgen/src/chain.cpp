#include "acuity/lodgen/chain.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "acuity/lodgen/repair.hpp"
#include "acuity/profile.hpp"
#include "cgal_bridge.hpp"

namespace acuity::lodgen {
namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void finish(Chain& c, const ChainProgress& progress, const DeviationOptions& measure) {
  c.diameter = diameter(c.levels[0].mesh);
  DeviationOptions o = measure;
  if (!(o.spacing > 0)) o.spacing = std::max(1e-12, c.diameter / 250);  // relative to the object's size
  for (std::size_t k = 1; k < c.levels.size(); ++k) {
    if (progress) progress("measure", k, c.levels.size() - 1);
    const auto t = std::chrono::steady_clock::now();
    const Deviation d = deviation(c.levels[0].mesh, c.levels[k].mesh, o);
    Level& l = c.levels[k];
    const Level& finer = c.levels[k - 1];
    // Never report a level as closer to level 0 than a finer one.
    l.hausdorff = std::max(c.diameter > 0 ? d.hausdorff / c.diameter : 0.0, finer.hausdorff);
    l.normal_deviation = std::max(d.normal_p99_degrees, finer.normal_deviation);
    l.normal_deviation_max = std::max(d.normal_degrees, finer.normal_deviation_max);
    l.measured_fully = d.complete;
    if (!d.complete)
      c.warnings.push_back("level " + std::to_string(k) + ": the error measurement hit its time cap after " +
                           std::to_string(d.samples) + " samples (errors are lower bounds)");
    l.seconds += seconds_since(t);
  }
}
}  // namespace

Mesh decimate_meshopt_level(const Mesh& level0, std::size_t target, const DecimateOptions& o,
                            MeshoptChainState* state) {
  if (!state->welded) {
    if (target >= level0.triangle_count()) return decimate(level0, target, o);
    Mesh out;
    if (detail::decimate_meshopt_keeping_seams(level0, target, o.lock_border, &out)) return out;
    state->welded = true;
    state->previous_welded = detail::weld_positions(level0);
  }
  state->previous_welded = detail::decimate_welded(state->previous_welded, target, o.lock_border);
  return split_creases(state->previous_welded, o.crease_degrees);
}

Chain build_chain(const Mesh& input, const std::string& where, const ChainOptions& o,
                  const ChainProgress& progress) {
  if (!(o.ratio > 0 && o.ratio < 1)) throw std::invalid_argument("lodgen: ratio must lie in (0, 1)");
  Chain c;
  const MeshReport report = validate(input);
  Mesh welded = input;
  if (!report.clean()) {
    if (!o.repair) throw InputError(where + ": " + report.summary());
    welded = repair(input, where);
    c.warnings.push_back(where + ": repaired " + report.summary());
  }
  // meshopt decimates the split mesh (its seams keep creases in place); the others need it welded
  // and their levels are split at their own creases.
  const Mesh base = split_creases(welded, o.decimate.crease_degrees);
  const std::size_t n0 = base.triangle_count();
  const std::size_t floor_count = std::max<std::size_t>(o.min_triangles, n0 / 100);
  // Targets: level k has ratio^k of level 0's triangles, down to about 1% (or min_triangles). With
  // an error budget the chain is cut after measuring, where the Hausdorff error passes it.
  std::vector<std::size_t> targets = {n0};
  for (double t = double(n0) * o.ratio; std::size_t(std::llround(t)) >= floor_count; t *= o.ratio) {
    if ((o.levels && targets.size() >= o.levels) || targets.size() >= kMaxLevels)
      break;  // what a profile holds
    targets.push_back(std::size_t(std::llround(t)));
  }
  c.levels.push_back({base, n0, 0.0, 0.0});
  MeshoptChainState meshopt_state;
  for (std::size_t k = 1; k < targets.size(); ++k) {
    if (progress) progress("decimate", k, targets.size() - 1);
    const auto t = std::chrono::steady_clock::now();
    Level l;
    l.mesh = o.decimate.backend == Backend::Meshopt
                 ? decimate_meshopt_level(base, targets[k], o.decimate, &meshopt_state)
                 : split_creases(decimate(welded, targets[k], o.decimate), o.decimate.crease_degrees);
    l.target_triangles = targets[k];
    l.seconds = seconds_since(t);
    c.levels.push_back(std::move(l));
  }
  finish(c, progress, o.measure);
  if (o.max_error > 0)  // the error budget: drop the levels past it
    while (c.levels.size() > 1 && c.levels.back().hausdorff > o.max_error) c.levels.pop_back();
  return c;
}

Chain measure_chain(std::vector<Mesh> levels, const ChainProgress& progress,
                    const DeviationOptions& measure) {
  Chain c;
  for (Mesh& m : levels) {
    const std::size_t n = m.triangle_count();
    c.levels.push_back({std::move(m), n, 0.0, 0.0});
  }
  if (c.levels.empty()) throw InputError("no levels");
  finish(c, progress, measure);
  return c;
}

}  // namespace acuity::lodgen
