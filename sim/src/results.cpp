// analyse() and summary_text(): what a run means, computed and formatted (acuity/sim/results.hpp).
#include "acuity/sim/results.hpp"

#include "text.hpp"

namespace acuity::sim {
namespace {

std::uint32_t visible_losses(const RuleRun& r, const std::vector<Judged>& judged, std::size_t objects) {
  std::uint32_t n = 0;
  for (const Judged& j : judged) n += j.scores[r.levels[std::size_t(j.frame) * objects + j.object]] > 1.0f;
  return n;
}

// The cheapest sweep entry of baseline `name` whose visible losses are at most those of rule `to`.
Match tuned(const Simulation& sim, const std::vector<std::uint32_t>& losses, const std::string& name,
            std::size_t to) {
  const std::vector<RuleRun>& rules = sim.rules();
  Match m;
  for (std::size_t i = 0; i < rules.size(); ++i)
    if (rules[i].sweep && rules[i].name == name && losses[i] <= losses[to] &&
        (m.rule < 0 || rules[i].triangles < rules[std::size_t(m.rule)].triangles))
      m.rule = int(i);
  if (m.rule >= 0) m.ratio = rules[std::size_t(m.rule)].triangles / rules[to].triangles;
  return m;
}

}  // namespace

Results analyse(const Simulation& sim, const std::vector<Judged>& judged) {
  const std::vector<RuleRun>& rules = sim.rules();
  Results r;
  r.frames = sim.frame_index();
  r.objects = sim.scene().instances.size();
  r.judged = judged.size();
  r.all_finest = sim.all_finest() * (1.0 / double(r.frames));
  for (const RuleRun& run : rules) r.visible_losses.push_back(visible_losses(run, judged, r.objects));
  const RuleRun* perceptual = &sim.rule("perceptual");
  r.perceptual = int(perceptual - rules.data());
  r.screen_size = tuned(sim, r.visible_losses, "screen-size", std::size_t(r.perceptual));
  r.distance = tuned(sim, r.visible_losses, "distance", std::size_t(r.perceptual));
  for (std::size_t i = 0; i < rules.size(); ++i)
    if (rules[i].sweep && rules[i].name == "perceptual")
      r.quality_sweep.push_back({int(i), tuned(sim, r.visible_losses, "screen-size", i)});
  return r;
}

std::string summary_text(const Simulation& sim, const Results& r) {
  const SimulationOptions& o = sim.options();
  const std::vector<RuleRun>& rules = sim.rules();
  const RuleRun& perceptual = rules[std::size_t(r.perceptual)];
  const double per_frame = 1.0 / double(r.frames);
  std::string out;
  appendf(&out,
          "\n%zu frames at %.0f Hz (%.1f s), two eyes, %zu objects; all in-view objects at their finest: "
          "%.0f triangles per frame\n\n",
          r.frames, o.fps, double(r.frames) / o.fps, r.objects, r.all_finest);
  appendf(&out, "%-12s %16s %14s %14s %10s %14s %18s\n", "rule", "triangles/frame", "of all-finest",
          "of perceptual", "switches", "outside sacc.", r.judged == 0 ? "" : "visible losses");
  for (std::size_t i = 0; i < rules.size(); ++i) {
    const RuleRun& run = rules[i];
    if (run.sweep) continue;
    appendf(&out, "%-12s %16.0f %13.1f%% %13.2fx %10llu %14llu", run.name.c_str(), run.triangles * per_frame,
            100.0 * run.triangles / sim.all_finest(), run.triangles / perceptual.triangles,
            static_cast<unsigned long long>(run.switches),
            static_cast<unsigned long long>(run.switches_outside_saccades));
    if (r.judged > 0)
      appendf(&out, " %10.1f%% (%u/%zu)", 100.0 * r.fraction(i), r.visible_losses[i], r.judged);
    appendf(&out, "\n");
  }
  if (r.judged == 0) return out;
  appendf(&out,
          "\nAt the perceptual rule's rate of visible losses (%.1f%% of %zu decisions judged by rendering "
          "both levels at the exact view):\n",
          100.0 * r.fraction(std::size_t(r.perceptual)), r.judged);
  for (const char* name : {"screen-size", "distance"}) {
    const bool screen_size = std::string(name) == "screen-size";
    const Match& m = screen_size ? r.screen_size : r.distance;
    if (m.rule >= 0) {
      const RuleRun& run = rules[std::size_t(m.rule)];
      appendf(
          &out,
          "  %-12s tuned to %s %.3g: %.0f triangles/frame (%.1f%% visible) = %.2fx the perceptual rule's\n",
          name, screen_size ? "pixel error" : "distance scale", run.parameter, run.triangles * per_frame,
          100.0 * r.fraction(std::size_t(m.rule)), m.ratio);
    } else {
      appendf(&out, "  %-12s no tuning in the sweep is that safe\n", name);
    }
  }
  appendf(&out, "\nAlong the perceptual rule's quality q (invisible when lost contrast <= q x threshold):\n");
  appendf(&out, "  %6s %16s %15s %30s\n", "q", "triangles/frame", "visible losses",
          "screen-size at that rate: ratio");
  for (const Results::QualityPoint& q : r.quality_sweep) {
    const RuleRun& run = rules[std::size_t(q.rule)];
    appendf(&out, "  %6.3g %16.0f %14.1f%%", run.parameter, run.triangles * per_frame,
            100.0 * r.fraction(std::size_t(q.rule)));
    if (q.screen_size.rule >= 0)
      appendf(&out, " %14.3g px: %.2fx\n", rules[std::size_t(q.screen_size.rule)].parameter,
              q.screen_size.ratio);
    else
      appendf(&out, " %30s\n", "none as safe in the sweep");
  }
  return out;
}

}  // namespace acuity::sim
