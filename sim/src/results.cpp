// analyse() and summary_text(): what a run means, computed and formatted (acuity/sim/results.hpp).
#include "acuity/sim/results.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "text.hpp"

namespace acuity::sim {
namespace {

std::uint32_t visible_losses(const RuleRun& r, const std::vector<Judged>& judged, std::size_t objects) {
  std::uint32_t n = 0;
  for (const Judged& j : judged) n += j.scores[r.levels[std::size_t(j.frame) * objects + j.object]] > 1.0f;
  return n;
}

// Every rule run of the simulation as the comparisons read it (indices as sim.rules()).
std::vector<RuleEntry> rule_entries(const Simulation& sim, const Results& r) {
  std::vector<RuleEntry> entries;
  for (std::size_t i = 0; i < sim.rules().size(); ++i) {
    const RuleRun& run = sim.rules()[i];
    entries.push_back(
        {run.name, run.sweep, {r.fraction(i), run.triangles / double(r.frames), run.parameter}});
  }
  return entries;
}

// Triangles over the judged decisions of the levels `run` chose.
double judged_triangles(const Simulation& sim, const RuleRun& run, const std::vector<Judged>& judged) {
  const SceneAssets& scene = sim.scene();
  double sum = 0;
  for (const Judged& j : judged) {
    const Profile& p = scene.assets[std::size_t(scene.instances[j.object].asset)].profile;
    sum += p.levels[run.levels[std::size_t(j.frame) * scene.instances.size() + j.object]].triangles;
  }
  return sum;
}

// A Match's triangles over the judged decisions: its entries' there, interpolated as the Match
// interpolates per frame (log triangles, by the same fraction); 0 unless interpolated or exact, or
// when an entry draws no triangles (no logarithm).
double judged_triangles(const Simulation& sim, const Match& m, const std::vector<Judged>& judged) {
  if (m.kind != Match::Kind::Interpolated) return 0;
  const RuleRun& a = sim.rules()[std::size_t(m.rule)];
  const double at_a = judged_triangles(sim, a, judged);
  if (m.riskier < 0) return at_a;
  const RuleRun& b = sim.rules()[std::size_t(m.riskier)];
  const double at_b = judged_triangles(sim, b, judged);
  if (!(at_a > 0 && at_b > 0 && a.triangles > 0 && b.triangles > 0 && m.triangles > 0)) return 0;
  const double frames = double(sim.frame_index());
  const double span = std::log(b.triangles / a.triangles);
  const double t = span != 0 ? std::log(m.triangles * frames / a.triangles) / span : 0.0;
  return at_a * std::exp(t * std::log(at_b / at_a));
}

// Each judged decision's profile (its object's asset's).
std::vector<const Profile*> judged_profiles(const Simulation& sim, const std::vector<Judged>& judged) {
  const SceneAssets& scene = sim.scene();
  std::vector<const Profile*> profiles;
  for (const Judged& j : judged)
    profiles.push_back(&scene.assets[std::size_t(scene.instances[j.object].asset)].profile);
  return profiles;
}

// The rule's level at each judged decision.
std::vector<std::uint8_t> judged_levels(const Simulation& sim, const RuleRun& run,
                                        const std::vector<Judged>& judged) {
  std::vector<std::uint8_t> levels;
  for (const Judged& j : judged)
    levels.push_back(run.levels[std::size_t(j.frame) * sim.scene().instances.size() + j.object]);
  return levels;
}

// Every rule on the instances of options().third_party's assets.
Results::Group third_party(const Simulation& sim, const std::vector<Judged>& judged, std::size_t frames) {
  const SceneAssets& scene = sim.scene();
  const std::vector<std::string>& names = sim.options().third_party;
  const std::size_t objects = scene.instances.size();
  std::vector<const Profile*> in_group(objects, nullptr);  // the instance's profile, when in the group
  Results::Group g;
  for (std::size_t i = 0; i < objects; ++i) {
    const Asset& a = scene.assets[std::size_t(scene.instances[i].asset)];
    if (std::find(names.begin(), names.end(), a.name) != names.end()) in_group[i] = &a.profile;
    g.objects += in_group[i] != nullptr;
  }
  const double per_frame = frames > 0 ? 1.0 / double(frames) : 0.0;
  for (std::size_t f = 0; f < frames; ++f)
    for (std::size_t i = 0; i < objects; ++i)
      if (in_group[i] && sim.in_view(std::uint32_t(i), f))
        g.all_finest += in_group[i]->levels[0].triangles * per_frame;
  for (const RuleRun& run : sim.rules()) {
    double drawn = 0;
    for (std::size_t f = 0; f < frames; ++f)
      for (std::size_t i = 0; i < objects; ++i)
        if (in_group[i] && sim.in_view(std::uint32_t(i), f))
          drawn += in_group[i]->levels[run.levels[f * objects + i]].triangles;
    g.triangles.push_back(drawn * per_frame);
    std::uint32_t losses = 0;
    for (const Judged& j : judged)
      losses += in_group[j.object] && j.scores[run.levels[std::size_t(j.frame) * objects + j.object]] > 1.0f;
    g.visible_losses.push_back(losses);
  }
  std::vector<const Profile*> profiles;
  std::vector<Judged> mine;
  std::vector<std::uint8_t> levels;
  const RuleRun& perceptual = sim.rule("perceptual");
  for (const Judged& j : judged)
    if (in_group[j.object]) {
      profiles.push_back(in_group[j.object]);
      mine.push_back(j);
      levels.push_back(perceptual.levels[std::size_t(j.frame) * objects + j.object]);
    }
  g.judged = mine.size();
  g.oracle = against_oracle(profiles, levels, mine);
  return g;
}

}  // namespace

Match tuned(const std::vector<RuleEntry>& entries, const std::string& name, double rate, double triangles) {
  std::vector<int> index;
  std::vector<SweepPoint> points;
  for (std::size_t i = 0; i < entries.size(); ++i)
    if (entries[i].sweep && entries[i].name == name) {
      index.push_back(int(i));
      points.push_back(entries[i].point);
    }
  Match m = at_equal_loss(points, rate);
  if (m.rule >= 0) m.rule = index[std::size_t(m.rule)];
  if (m.riskier >= 0) m.riskier = index[std::size_t(m.riskier)];
  if (m.kind != Match::Kind::None && triangles > 0) m.ratio = m.triangles / triangles;
  return m;
}

std::string match_text(const std::vector<RuleEntry>& entries, const Match& m, const char* tuning,
                       const char* of, const char* unit) {
  if (m.kind == Match::Kind::None) return "no tuning in the sweep";
  const bool at_least = m.kind == Match::Kind::AtLeast, at_most = m.kind == Match::Kind::AtMost;
  const char* bound = at_least ? "at least " : at_most ? "at most " : "";
  std::string out;
  appendf(&out, "%s%.0f %s", bound, m.triangles, unit);
  if (m.ratio > 0) appendf(&out, " = %s%.2fx %s", bound, m.ratio, of);
  auto entry = [&](int i) {  // "0.0312 at 0.5%"
    std::string e;
    const SweepPoint& p = entries[std::size_t(i)].point;
    appendf(&e, "%.3g at %.1f%%", p.parameter, 100.0 * p.rate);
    return e;
  };
  if (at_least)
    appendf(&out, " (no tuning is that safe; the safest: %s %s visible)", tuning, entry(m.riskier).c_str());
  else if (at_most)
    appendf(&out, " (every tuning is safer; the cheapest: %s %s visible)", tuning, entry(m.rule).c_str());
  else if (m.riskier < 0)
    appendf(&out, " (%s %s visible)", tuning, entry(m.rule).c_str());
  else
    appendf(&out, " (%s ~%.3g, between %s and %s visible)", tuning, m.parameter, entry(m.rule).c_str(),
            entry(m.riskier).c_str());
  return out;
}

Match at_equal_loss(const std::vector<SweepPoint>& sweep, double rate) {
  Match m;
  if (!std::isfinite(rate)) return m;
  std::vector<int> order;
  for (std::size_t i = 0; i < sweep.size(); ++i)
    if (std::isfinite(sweep[i].rate) && std::isfinite(sweep[i].triangles) && sweep[i].triangles > 0)
      order.push_back(int(i));
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const SweepPoint &x = sweep[std::size_t(a)], &y = sweep[std::size_t(b)];
    return x.rate < y.rate || (x.rate == y.rate && x.triangles < y.triangles);
  });
  std::vector<int> frontier;  // rates strictly increasing, triangles strictly decreasing
  for (int i : order)
    if (frontier.empty() || sweep[std::size_t(i)].triangles < sweep[std::size_t(frontier.back())].triangles)
      frontier.push_back(i);
  if (frontier.empty()) return m;
  const SweepPoint& safest = sweep[std::size_t(frontier.front())];
  if (rate < safest.rate) {
    m.kind = Match::Kind::AtLeast;
    m.riskier = frontier.front();
    m.triangles = safest.triangles;
    m.parameter = safest.parameter;
    return m;
  }
  std::size_t k = 0;
  while (k + 1 < frontier.size() && sweep[std::size_t(frontier[k + 1])].rate <= rate) ++k;
  m.rule = frontier[k];
  const SweepPoint& a = sweep[std::size_t(m.rule)];
  m.kind = Match::Kind::Interpolated;
  m.triangles = a.triangles;
  m.parameter = a.parameter;
  if (rate == a.rate) return m;
  if (k + 1 == frontier.size()) {
    m.kind = Match::Kind::AtMost;
    return m;
  }
  m.riskier = frontier[k + 1];
  const SweepPoint& b = sweep[std::size_t(m.riskier)];
  const double t = (rate - a.rate) / (b.rate - a.rate);  // b.rate > rate > a.rate
  m.triangles = std::exp(std::log(a.triangles) + t * (std::log(b.triangles) - std::log(a.triangles)));
  m.parameter = a.parameter > 0 && b.parameter > 0
                    ? std::exp(std::log(a.parameter) + t * (std::log(b.parameter) - std::log(a.parameter)))
                    : a.parameter + t * (b.parameter - a.parameter);
  return m;
}

void Oracle::add(int level, int oracle, double level_triangles, double oracle_level_triangles) {
  rule_triangles += level_triangles;
  oracle_triangles += oracle_level_triangles;
  same += level == oracle;
  finer += level < oracle;
  coarser += level > oracle;
}

double Oracle::ratio() const {
  return oracle_triangles > 0 ? rule_triangles / oracle_triangles : std::numeric_limits<double>::quiet_NaN();
}

double least_triangles(const std::vector<double>& invisible, const std::vector<double>& any,
                       std::size_t losses) {
  double sum = 0;
  std::vector<double> savings;
  for (std::size_t i = 0; i < invisible.size(); ++i) {
    sum += invisible[i];
    savings.push_back(std::max(0.0, invisible[i] - any[i]));
  }
  losses = std::min(losses, savings.size());
  std::partial_sort(savings.begin(), savings.begin() + std::ptrdiff_t(losses), savings.end(),
                    std::greater<>());
  for (std::size_t i = 0; i < losses; ++i) sum -= savings[i];
  return sum;
}

double least_triangles_over(const std::vector<const Profile*>& profiles, const std::vector<Judged>& judged,
                            std::size_t losses) {
  std::vector<double> invisible, any;
  for (std::size_t i = 0; i < judged.size(); ++i) {
    const Profile& p = *profiles[i];
    double cheapest = p.levels[0].triangles, cheapest_invisible = cheapest;  // level 0 loses nothing
    for (std::uint32_t k = 1; k < std::min<std::uint32_t>(p.meta.level_count, kMaxLevels); ++k) {
      cheapest = std::min(cheapest, double(p.levels[k].triangles));
      if (judged[i].scores[k] <= 1.0f)
        cheapest_invisible = std::min(cheapest_invisible, double(p.levels[k].triangles));
    }
    invisible.push_back(cheapest_invisible);
    any.push_back(cheapest);
  }
  return least_triangles(invisible, any, losses);
}

Oracle against_oracle(const std::vector<const Profile*>& profiles, const std::vector<std::uint8_t>& levels,
                      const std::vector<Judged>& judged) {
  Oracle o;
  for (std::size_t i = 0; i < judged.size(); ++i) {
    const Profile& p = *profiles[i];
    const int best = oracle_level(judged[i], p.meta.level_count);
    o.add(levels[i], best, p.levels[levels[i]].triangles, p.levels[best].triangles);
  }
  return o;
}

int oracle_level(const Judged& judged, std::uint32_t levels) {
  int best = 0;
  for (std::uint32_t k = 1; k < std::min<std::uint32_t>(levels, kMaxLevels); ++k)
    if (judged.scores[k] <= 1.0f) best = int(k);
  return best;
}

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
  const double per_frame = 1.0 / double(r.frames);
  const double rate = r.fraction(std::size_t(r.perceptual));
  const std::vector<RuleEntry> entries = rule_entries(sim, r);
  r.screen_size = tuned(entries, "screen-size", rate, perceptual->triangles * per_frame);
  r.distance = tuned(entries, "distance", rate, perceptual->triangles * per_frame);
  const std::vector<const Profile*> profiles = judged_profiles(sim, judged);
  r.oracle = against_oracle(profiles, judged_levels(sim, *perceptual, judged), judged);
  r.ungated = against_oracle(profiles, judged_levels(sim, sim.rule("ungated"), judged), judged);
  for (std::size_t i = 0; i < rules.size(); ++i)
    if (rules[i].sweep && rules[i].name == "perceptual")
      r.quality_sweep.push_back({int(i),
                                 tuned(entries, "screen-size", r.fraction(i), rules[i].triangles * per_frame),
                                 against_oracle(profiles, judged_levels(sim, rules[i], judged), judged)});
  r.one_percent_perceptual = tuned(entries, "perceptual", 0.01, 0);
  const double at_one =
      r.one_percent_perceptual.kind == Match::Kind::Interpolated ? r.one_percent_perceptual.triangles : 0;
  r.one_percent_screen_size = tuned(entries, "screen-size", 0.01, at_one);
  r.one_percent_distance = tuned(entries, "distance", 0.01, at_one);
  r.one_percent_losses = judged.size() / 100;
  r.least_at_one_percent = least_triangles_over(profiles, judged, r.one_percent_losses);
  r.screen_size_judged_at_one_percent = judged_triangles(sim, r.one_percent_screen_size, judged);
  r.third_party = third_party(sim, judged, r.frames);
  return r;
}

namespace {

// The same in a table cell: "0.0312 px: 1.45x", "~0.041 px: 1.30x", "< 0.0312 px: >= 1.45x".
std::string match_cell(const Match& m, const char* unit) {
  std::string out;
  if (m.kind == Match::Kind::None) return "none";
  const char* at = m.kind == Match::Kind::AtLeast  ? "< "
                   : m.kind == Match::Kind::AtMost ? "> "
                   : m.riskier >= 0                ? "~"
                                                   : "";
  const char* bound = m.kind == Match::Kind::AtLeast ? ">= " : m.kind == Match::Kind::AtMost ? "<= " : "";
  appendf(&out, "%s%.3g%s: %s%.2fx", at, m.parameter, unit, bound, m.ratio);
  return out;
}

}  // namespace

std::string summary_text(const Simulation& sim, const Results& r) {
  const SimulationOptions& o = sim.options();
  const std::vector<RuleRun>& rules = sim.rules();
  const RuleRun& perceptual = rules[std::size_t(r.perceptual)];
  const double per_frame = 1.0 / double(r.frames);
  const std::vector<RuleEntry> entries = rule_entries(sim, r);
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
  const SchedulerConfig& gated = perceptual.scheduler->config();
  appendf(&out,
          "(ungated: the perceptual rule switching at once; every other rule coarsens after %u calm frames "
          "at a score <= %.2g, in a saccade or after %u frames)\n",
          gated.hysteresis_frames, 1.0 - double(gated.hysteresis_margin), gated.max_coarsen_wait);
  const Results::Group& g = r.third_party;
  if (g.objects > 0) {
    appendf(&out, "\nThird-party assets (");
    for (std::size_t i = 0; i < o.third_party.size(); ++i)
      appendf(&out, "%s%s", i ? ", " : "", o.third_party[i].c_str());
    appendf(&out, "): %zu of the %zu objects", g.objects, r.objects);
    if (r.judged > 0) appendf(&out, ", %zu of the %zu judged decisions", g.judged, r.judged);
    appendf(&out, ";\nall of them in view at their finest: %.0f triangles per frame\n", g.all_finest);
    appendf(&out, "%-12s %16s %14s %18s\n", "rule", "triangles/frame", "of all-finest",
            g.judged > 0 ? "visible losses" : "");
    for (std::size_t i = 0; i < rules.size(); ++i) {
      if (rules[i].sweep) continue;
      appendf(&out, "%-12s %16.0f %13.1f%%", rules[i].name.c_str(), g.triangles[i],
              g.all_finest > 0 ? 100.0 * g.triangles[i] / g.all_finest : 0.0);
      if (g.judged > 0)
        appendf(&out, " %17.1f%% (%u/%zu)", 100.0 * g.visible_losses[i] / double(g.judged),
                g.visible_losses[i], g.judged);
      appendf(&out, "\n");
    }
    if (g.judged > 0) {
      const Oracle& o3 = g.oracle;
      appendf(
          &out,
          "over its %zu judged decisions the perceptual rule draws %.0f triangles, the oracle (the coarsest "
          "level the judge\nfinds invisible) %.0f: %.2fx; it picks the oracle's level in %u, a finer one in "
          "%u, a coarser one in %u\n",
          g.judged, o3.rule_triangles, o3.oracle_triangles, o3.ratio(), o3.same, o3.finer, o3.coarser);
    }
  }
  if (r.judged == 0) return out;
  appendf(
      &out,
      "\nAt the perceptual rule's rate of visible losses (%.1f%% of %zu decisions judged at the exact view "
      "by the detection model; the baselines' sweeps interpolated):\n",
      100.0 * r.fraction(std::size_t(r.perceptual)), r.judged);
  appendf(
      &out, "  %-12s %s\n", "screen-size",
      match_text(entries, r.screen_size, "pixel error", "the perceptual rule's", "triangles/frame").c_str());
  appendf(
      &out, "  %-12s %s\n", "distance",
      match_text(entries, r.distance, "distance scale", "the perceptual rule's", "triangles/frame").c_str());
  appendf(&out, "At a 1%% rate of visible losses (every sweep interpolated):\n");
  appendf(&out, "  %-12s %s\n", "perceptual",
          match_text(entries, r.one_percent_perceptual, "q", "", "triangles/frame").c_str());
  appendf(&out, "  %-12s %s\n", "screen-size",
          match_text(entries, r.one_percent_screen_size, "pixel error", "the perceptual rule's at 1%",
                     "triangles/frame")
              .c_str());
  appendf(&out, "  %-12s %s\n", "distance",
          match_text(entries, r.one_percent_distance, "distance scale", "the perceptual rule's at 1%",
                     "triangles/frame")
              .c_str());
  const Oracle& oracle = r.oracle;
  const double n = double(oracle.same + oracle.finer + oracle.coarser);
  appendf(&out,
          "Against the oracle (per judged decision, the coarsest level the judge finds invisible):\n"
          "  the perceptual rule draws %.2fx the oracle's triangles over the judged decisions; it picks the "
          "oracle's level in %.1f%%, a finer one in %.1f%%, a coarser one in %.1f%%\n",
          oracle.ratio(), 100.0 * oracle.same / n, 100.0 * oracle.finer / n, 100.0 * oracle.coarser / n);
  const Oracle& ungated = r.ungated;
  appendf(&out,
          "  switching at once (ungated), its choices draw %.2fx: the oracle's level in %.1f%%, a finer one "
          "in %.1f%%, a coarser one in %.1f%%; the rest is the cost of waiting to coarsen\n",
          ungated.ratio(), 100.0 * ungated.same / n, 100.0 * ungated.finer / n, 100.0 * ungated.coarser / n);
  if (r.screen_size_judged_at_one_percent > 0 && r.least_at_one_percent > 0)
    appendf(
        &out,
        "  allowing %zu of the %zu decisions (1%%) a visible loss, no rule can draw fewer than %.0f "
        "triangles "
        "over them\n"
        "  (the oracle, at the coarsest level where that saves most); screen-size at 1%% draws %.0f, %.2fx "
        "that:\n"
        "  no rule as safe saves more over screen-size on this field\n",
        r.one_percent_losses, r.judged, r.least_at_one_percent, r.screen_size_judged_at_one_percent,
        r.screen_size_judged_at_one_percent / r.least_at_one_percent);
  appendf(&out, "\nAlong the perceptual rule's quality q (invisible when lost contrast <= q x threshold):\n");
  appendf(&out, "  %6s %16s %15s %10s %32s\n", "q", "triangles/frame", "visible losses", "of oracle",
          "screen-size at that rate: ratio");
  for (const Results::QualityPoint& q : r.quality_sweep) {
    const RuleRun& run = rules[std::size_t(q.rule)];
    appendf(&out, "  %6.3g %16.0f %14.1f%% %9.2fx %32s\n", run.parameter, run.triangles * per_frame,
            100.0 * r.fraction(std::size_t(q.rule)), q.oracle.ratio(),
            match_cell(q.screen_size, " px").c_str());
  }
  return out;
}

}  // namespace acuity::sim
