// Decisions sampled over the conditions (acuity/sim/sampled.hpp).
#include "acuity/sim/sampled.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "exact_view.hpp"
#include "geometry.hpp"
#include "text.hpp"

namespace acuity::sim {
namespace {

void check(const SampleOptions& o) {
  auto fail = [](const char* what) { throw std::runtime_error(std::string("sampled decisions: ") + what); };
  if (o.count < 1 || o.count > 100000) fail("the count must be 1..100000");
  if (!(o.min_diameter_deg > 0 && o.min_diameter_deg <= o.max_diameter_deg && o.max_diameter_deg < 180))
    fail("diameters must satisfy 0 < min <= max < 180 deg");
  if (!(o.max_eccentricity_deg >= 0 && o.max_eccentricity_deg <= 90)) fail("eccentricity must be 0..90 deg");
  if (!(o.moving >= 0 && o.moving <= 1)) fail("the moving fraction must be 0..1");
  if (!(o.min_speed_deg_s > 0 && o.min_speed_deg_s <= o.max_speed_deg_s && o.max_speed_deg_s <= 1000))
    fail("speeds must satisfy 0 < min <= max <= 1000 deg/s");
  if (o.viewport < 1 || !(o.fov_deg > 0 && o.fov_deg < 180))
    fail("the display needs pixels and a field of view below 180 deg");
}

// min (max / min)^u: log-uniform on [min, max] for u uniform on [0, 1).
double log_uniform(double min, double max, double u) { return min * std::pow(max / min, u); }

// The perceptual rule's safety margins the configuration names, each changed alone: removed (the
// gaze tracker's uncertainty, the tables' rounding and interpolation) or added (the largest loss of
// the three nearest views instead of the nearest's, and the area law turned off: every loss read as
// a full-field grating).
struct MarginToggle {
  const char* name;
  void (*change)(SchedulerConfig*);
};
constexpr MarginToggle kMarginToggles[] = {
    {"area law -> off", [](SchedulerConfig* c) { c->area_law = false; }},
    {"gaze uncertainty 1 deg -> 0", [](SchedulerConfig* c) { c->gaze_uncertainty_deg = 0; }},
    {"tables -> exact evaluation", [](SchedulerConfig* c) { c->evaluation = Evaluation::Exact; }},
    {"nearest view -> Max3 of three", [](SchedulerConfig* c) { c->view_blend = ViewBlend::Max3; }},
    {"all but Max3 removed", [](SchedulerConfig* c) {
       c->gaze_uncertainty_deg = 0;
       c->evaluation = Evaluation::Exact;
     }}};

// Every decision's level under configuration c (one frame: objects new to the scheduler take their
// level at once) and the triangles they draw.
std::vector<std::uint8_t> choose(const SceneAssets& scene, const SampledRun& run, const SchedulerConfig& c,
                                 double* triangles) {
  Scheduler s(c);
  for (const Asset& a : scene.assets) s.add_profile(a.profile);
  for (const SampledDecision& d : run.decisions)
    s.set_velocity(s.add_object(d.asset, d.transform), d.velocity);
  s.run_frame(run.frame);
  std::vector<std::uint8_t> levels;
  *triangles = 0;
  for (std::uint32_t i = 0; i < run.decisions.size(); ++i) {
    levels.push_back(s.level(i));
    *triangles += scene.assets[std::size_t(run.decisions[i].asset)].profile.levels[levels.back()].triangles;
  }
  return levels;
}

// The same, one decision at a time on a scheduler of one object, each seen in its own frame.
template <class FrameOf>
std::vector<std::uint8_t> choose_each(const SceneAssets& scene, const SampledRun& run, SchedulerConfig c,
                                      const FrameOf& frame_of, double* triangles) {
  c.max_objects = 1;
  Scheduler s(c);
  for (const Asset& a : scene.assets) s.add_profile(a.profile);
  std::vector<std::uint8_t> levels;
  *triangles = 0;
  for (std::size_t i = 0; i < run.decisions.size(); ++i) {
    const SampledDecision& d = run.decisions[i];
    const ObjectId id = s.add_object(d.asset, d.transform);
    s.set_velocity(id, d.velocity);
    s.run_frame(frame_of(i));
    levels.push_back(s.level(id));
    *triangles += scene.assets[std::size_t(d.asset)].profile.levels[levels.back()].triangles;
    s.remove_object(id);
  }
  return levels;
}

// Two octaves more of the perceptual rule's q (to 4) and of screen-size's pixel error (to 1/128 px)
// than the simulation sweeps: sampled decisions are in the periphery and moving more often.
constexpr int kWider = 8;

}  // namespace

Frame centre_gaze_frame(const SceneAssets& scene, const SampledRun& run, std::size_t i) {
  const SampledDecision& d = run.decisions.at(i);
  const float* s = scene.assets[std::size_t(d.asset)].profile.meta.sphere;
  const ObjectTransform& t = d.transform;
  const glm::dquat q(t.rotation[3], t.rotation[0], t.rotation[1], t.rotation[2]);
  const glm::dvec3 centre =
      glm::dvec3(t.position[0], t.position[1], t.position[2]) + q * glm::dvec3(s[0], s[1], s[2]);
  // The eye at the origin, the gaze along -Z: towards the object across the gaze is centre's x, y.
  glm::dvec3 toward(centre.x, centre.y, 0.0);
  const double across = glm::length(toward);
  toward = across > 0 ? toward / across : glm::dvec3(1, 0, 0);
  const double radius = 0.5 * d.diameter_deg / kDeg;  // [rad]
  const glm::dvec3 gaze = std::cos(radius) * glm::dvec3(0, 0, -1) - std::sin(radius) * toward;
  Frame f = run.frame;
  for (int k = 0; k < 3; ++k) f.gaze[0].direction[k] = float(gaze[k]);
  return f;
}

SampledRun run_sampled(const SceneAssets& scene, const SampleOptions& o, const SceneAssets* own_views) {
  check(o);
  if (scene.assets.empty()) throw std::runtime_error("sampled decisions: the scene has no assets");
  if (own_views) {
    bool same = own_views->assets.size() == scene.assets.size();
    for (std::size_t a = 0; same && a < scene.assets.size(); ++a)
      same = own_views->assets[a].name == scene.assets[a].name &&
             own_views->assets[a].profile.meta.level_count == scene.assets[a].profile.meta.level_count;
    if (!same)
      throw std::runtime_error("sampled decisions: the profiles without cell bounds are of other assets");
  }
  SampledRun run;
  run.options = o;
  Frame& frame = run.frame;
  frame.eye_count = 1;
  frame.dt = 1.0f / 90;
  Eye& eye = frame.eyes[0];
  const float half = 0.5f * o.fov_deg;
  const float fov[4] = {-half, half, half, -half};
  std::copy(fov, fov + 4, eye.fov_deg);
  eye.viewport[0] = eye.viewport[1] = o.viewport;
  Gaze& gaze = frame.gaze[0];
  gaze.valid = true;
  gaze.has_velocity = true;  // tracked and still: the retinal speed is the image's

  // The decisions: every uniform drawn for each, so one's choices never shift the next one's.
  std::mt19937 rng(o.seed * 977u + 3u);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (std::uint32_t i = 0; i < o.count; ++i) {
    double u[10];
    for (double& x : u) x = uniform(rng);
    SampledDecision d;
    d.asset =
        int(std::min<std::size_t>(std::size_t(u[0] * double(scene.assets.size())), scene.assets.size() - 1));
    d.diameter_deg = log_uniform(o.min_diameter_deg, o.max_diameter_deg, u[1]);
    d.eccentricity_deg = o.max_eccentricity_deg * u[2];
    const double azimuth = 2 * kPi * u[3];
    // A uniformly random turn (Shoemake's subgroup algorithm).
    const double a = std::sqrt(1 - u[4]), b = std::sqrt(u[4]);
    const glm::dquat q(b * std::cos(2 * kPi * u[6]), a * std::sin(2 * kPi * u[5]),
                       a * std::cos(2 * kPi * u[5]), b * std::sin(2 * kPi * u[6]));
    d.speed_deg_s = u[7] < o.moving ? log_uniform(o.min_speed_deg_s, o.max_speed_deg_s, u[8]) : 0.0;
    const double heading = 2 * kPi * u[9];
    // The centre at the eccentricity from the gaze (straight ahead), at the distance of the diameter.
    const Profile& p = scene.assets[std::size_t(d.asset)].profile;
    const double e = d.eccentricity_deg / kDeg;
    const glm::dvec3 dir(std::sin(e) * std::cos(azimuth), std::sin(e) * std::sin(azimuth), -std::cos(e));
    const double distance = double(p.meta.sphere[3]) / std::sin(0.5 * d.diameter_deg / kDeg);
    const glm::dvec3 offset = q * glm::dvec3(p.meta.sphere[0], p.meta.sphere[1], p.meta.sphere[2]);
    const glm::dvec3 position = distance * dir - offset;
    for (int k = 0; k < 3; ++k) d.transform.position[k] = position[k];
    d.transform.rotation[0] = float(q.x);
    d.transform.rotation[1] = float(q.y);
    d.transform.rotation[2] = float(q.z);
    d.transform.rotation[3] = float(q.w);
    // Moving across the line of sight at the sampled angular speed, in the sampled heading.
    const glm::dvec3 side =
        glm::normalize(glm::cross(dir, std::abs(dir.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0)));
    const glm::dvec3 across = glm::cross(dir, side);
    const glm::dvec3 v =
        distance * (d.speed_deg_s / kDeg) * (std::cos(heading) * side + std::sin(heading) * across);
    for (int k = 0; k < 3; ++k) d.velocity[k] = float(v[k]);
    run.decisions.push_back(d);
    run.all_finest += p.levels[0].triangles;
  }

  // Every rule chooses once (objects new to a scheduler take their level at once: no hysteresis).
  std::vector<Tuning> tunings = main_tunings();
  const std::size_t main_rules = tunings.size();
  for (const Tuning& t : swept_tunings(kWider)) tunings.push_back(t);
  SchedulerConfig& perceptual = run.perceptual;
  for (const Tuning& t : tunings) {
    SchedulerConfig c;
    c.max_objects = o.count;
    c.max_profiles = std::uint32_t(scene.assets.size());
    c.evaluation = o.evaluation;
    if (t.rule == SelectionRule::Perceptual) c.model = o.model;
    c.hysteresis_margin = 0;
    c.hysteresis_frames = 0;
    tune(&c, t.rule, t.parameter);
    if (run.levels.empty()) perceptual = c;  // the first, q = 1: its thresholds judge
    double triangles = 0;
    run.levels.push_back(choose(scene, run, c, &triangles));
    run.rules.push_back({t.name, run.rules.size() >= main_rules, {0, triangles, t.parameter}});
  }
  for (const MarginToggle& m : kMarginToggles) {
    SchedulerConfig c = perceptual;
    m.change(&c);
    SampledRun::MarginChange change{m.name, {}, 0, 0};
    change.levels = choose(scene, run, c, &change.triangles);
    run.margins.push_back(std::move(change));
  }
  {
    SampledRun::MarginChange change{"eccentricity: nearest -> centre", {}, 0, 0};
    change.levels = choose_each(
        scene, run, perceptual, [&](std::size_t i) { return centre_gaze_frame(scene, run, i); },
        &change.triangles);
    run.margins.push_back(std::move(change));
  }
  if (own_views) {
    SampledRun::MarginChange change{"cell bounds -> each view's own", {}, 0, 0};
    change.levels = choose(*own_views, run, perceptual, &change.triangles);
    run.margins.push_back(std::move(change));
  }

  // Every decision judged at its exact view by the judge's detection model.
  std::vector<ExactView> views;
  for (const SampledDecision& d : run.decisions) {
    const Profile& p = scene.assets[std::size_t(d.asset)].profile;
    views.push_back({d.asset, d.transform, glm::dvec3(d.velocity[0], d.velocity[1], d.velocity[2]),
                     double(p.meta.sphere[3]), &frame});
  }
  const double ppd = double(o.viewport) / (2 * std::tan(0.5 * double(o.fov_deg) / kDeg)) / kDeg;
  const std::vector<ExactScores> scored = judge_exact_views(scene, views, perceptual, ppd);
  for (std::uint32_t i = 0; i < o.count; ++i)
    run.judged.push_back({0, i, scored[i].pixels, scored[i].scores});
  for (std::size_t r = 0; r < run.rules.size(); ++r) {
    std::uint32_t losses = 0;
    for (std::uint32_t i = 0; i < o.count; ++i) losses += run.judged[i].scores[run.levels[r][i]] > 1.0f;
    run.visible.push_back(losses);
    run.rules[r].point.rate = double(losses) / double(o.count);
  }
  for (SampledRun::MarginChange& m : run.margins)
    for (std::uint32_t i = 0; i < o.count; ++i) m.visible += run.judged[i].scores[m.levels[i]] > 1.0f;
  return run;
}

std::string sampled_text(const SceneAssets& scene, const SampledRun& run) {
  const SampleOptions& o = run.options;
  const std::size_t n = run.judged.size();
  std::string out;
  appendf(
      &out,
      "%zu decisions sampled (seed %u): each one of the scene's %zu meshes at a random turn, %.3g-%.3g deg "
      "across (log-uniform),\nits centre %.3g-%.3g deg from the gaze (uniform), %.0f%% of them moving at "
      "%.3g-%.3g deg/s on the retina (log-uniform, any direction);\none eye, %u px over %.3g deg, the gaze "
      "tracked and still; every rule chooses once (no hysteresis) and each decision is\njudged at its exact "
      "view by the detection model. All at their finest: %.0f triangles\n\n",
      n, o.seed, scene.assets.size(), o.min_diameter_deg, o.max_diameter_deg, 0.0, o.max_eccentricity_deg,
      100.0 * o.moving, o.min_speed_deg_s, o.max_speed_deg_s, o.viewport, double(o.fov_deg), run.all_finest);
  appendf(&out, "%-12s %16s %14s %14s %18s\n", "rule", "triangles", "of all-finest", "of perceptual",
          "visible losses");
  const double perceptual = run.rules[0].point.triangles;
  for (std::size_t r = 0; r < run.rules.size(); ++r) {
    const RuleEntry& e = run.rules[r];
    if (e.sweep) continue;
    appendf(&out, "%-12s %16.0f %13.1f%% %13.2fx %10.1f%% (%u/%zu)\n", e.name.c_str(), e.point.triangles,
            100.0 * e.point.triangles / run.all_finest, e.point.triangles / perceptual, 100.0 * e.point.rate,
            run.visible[r], n);
  }
  const double rate = run.rules[0].point.rate;
  appendf(&out,
          "\nAt the perceptual rule's rate of visible losses (%.1f%%; the baselines' sweeps interpolated):\n",
          100.0 * rate);
  const char* of = "the perceptual rule's";
  appendf(
      &out, "  %-12s %s\n", "screen-size",
      match_text(run.rules, tuned(run.rules, "screen-size", rate, perceptual), "pixel error", of, "triangles")
          .c_str());
  appendf(
      &out, "  %-12s %s\n", "distance",
      match_text(run.rules, tuned(run.rules, "distance", rate, perceptual), "distance scale", of, "triangles")
          .c_str());
  const Match at_one = tuned(run.rules, "perceptual", 0.01, 0);
  const double perceptual_at_one = at_one.kind == Match::Kind::Interpolated ? at_one.triangles : 0;
  const Match screen_at_one = tuned(run.rules, "screen-size", 0.01, perceptual_at_one);
  appendf(&out, "At a 1%% rate of visible losses (every sweep interpolated):\n");
  appendf(&out, "  %-12s %s\n", "perceptual", match_text(run.rules, at_one, "q", "", "triangles").c_str());
  appendf(&out, "  %-12s %s\n", "screen-size",
          match_text(run.rules, screen_at_one, "pixel error", "the perceptual rule's at 1%", "triangles")
              .c_str());
  appendf(&out, "  %-12s %s\n", "distance",
          match_text(run.rules, tuned(run.rules, "distance", 0.01, perceptual_at_one), "distance scale",
                     "the perceptual rule's at 1%", "triangles")
              .c_str());
  std::vector<const Profile*> profiles;
  for (const SampledDecision& d : run.decisions)
    profiles.push_back(&scene.assets[std::size_t(d.asset)].profile);
  const Oracle oracle = against_oracle(profiles, run.levels[0], run.judged);
  appendf(
      &out,
      "Against the oracle (per decision, the coarsest level the judge finds invisible):\n"
      "  the perceptual rule draws %.2fx the oracle's triangles; it picks the oracle's level in %.1f%%, a "
      "finer one in %.1f%%, a coarser one in %.1f%%\n",
      oracle.ratio(), 100.0 * oracle.same / double(n), 100.0 * oracle.finer / double(n),
      100.0 * oracle.coarser / double(n));
  const std::size_t losses = n / 100;
  const double least = least_triangles_over(profiles, run.judged, losses);
  if (screen_at_one.kind == Match::Kind::Interpolated && least > 0)
    appendf(&out,
            "  allowing %zu of the %zu decisions (1%%) a visible loss, no rule can draw fewer than %.0f "
            "triangles;\n  screen-size at 1%% draws %.0f, %.2fx that\n",
            losses, n, least, screen_at_one.triangles, screen_at_one.triangles / least);
  appendf(
      &out,
      "\nThe perceptual rule's safety margins, each changed alone over the same judged decisions (losses: "
      "decisions\njudged visible that the rule at q = 1 keeps invisible, and the reverse):\n");
  appendf(&out, "  %-32s %12s %14s %18s %16s\n", "change", "triangles", "of perceptual", "visible losses",
          "losses +new -gone");
  for (const SampledRun::MarginChange& m : run.margins) {
    std::uint32_t added = 0, gone = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const bool before = run.judged[i].scores[run.levels[0][i]] > 1.0f,
                 after = run.judged[i].scores[m.levels[i]] > 1.0f;
      added += after && !before;
      gone += before && !after;
    }
    appendf(&out, "  %-32s %12.0f %13.3fx %10.1f%% (%u/%zu) %11s+%u -%u\n", m.name.c_str(), m.triangles,
            m.triangles / perceptual, 100.0 * m.visible / double(n), m.visible, n, "", added, gone);
  }
  return out;
}

}  // namespace acuity::sim
