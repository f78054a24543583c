// Ground truth: the exact-view check of decisions (a run's, or sampled ones), and the explanation of
// one decision.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>

#include <oneapi/tbb/parallel_for.h>

#include "acuity/sim/simulation.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "exact_view.hpp"
#include "geometry.hpp"

namespace acuity::sim {

std::vector<ExactScores> judge_exact_views(const SceneAssets& scene, const std::vector<ExactView>& views,
                                           const SchedulerConfig& perceptual, double ppd) {
  // The exact view's direction and up in object space, and the snapshot's pixels.
  struct Task {
    ProfileView view;
    std::uint32_t pixels;
  };
  std::vector<Task> tasks;
  for (const ExactView& v : views) {
    Task t{};
    const Frame& fr = *v.frame;
    glm::dvec3 eye(0.0);
    for (std::uint32_t e = 0; e < fr.eye_count; ++e)
      eye += glm::dvec3(fr.eyes[e].position[0], fr.eyes[e].position[1], fr.eyes[e].position[2]) /
             double(fr.eye_count);
    const ObjectTransform& tr = v.transform;
    const glm::dquat q(tr.rotation[3], tr.rotation[0], tr.rotation[1], tr.rotation[2]);
    const glm::dvec3 centre = world_centre(scene.assets[std::size_t(v.asset)], tr);
    const glm::dvec3 d = glm::inverse(q) * (eye - centre);
    const glm::dquat head(fr.eyes[0].orientation[3], fr.eyes[0].orientation[0], fr.eyes[0].orientation[1],
                          fr.eyes[0].orientation[2]);
    glm::dvec3 up = glm::inverse(q) * (head * glm::dvec3(0, 1, 0));
    const glm::dvec3 dir = glm::normalize(d);
    up -= dir * glm::dot(up, dir);
    if (glm::length(up) < 1e-6) {
      t.view = spectra::make_view(float(dir.x), float(dir.y), float(dir.z));
    } else {
      up = glm::normalize(up);
      for (int k = 0; k < 3; ++k) {
        t.view.direction[k] = float(dir[k]);
        t.view.up[k] = float(up[k]);
      }
    }
    const double distance = glm::length(eye - centre);
    const double theta = distance > v.radius ? 2 * std::asin(v.radius / distance) * kDeg : 180.0;
    t.pixels = 64;
    while (t.pixels < 512 && double(t.pixels) < 2 * theta * ppd)
      t.pixels *= 2;  // bands up to px / 4 reach the display's Nyquist
    tasks.push_back(t);
  }

  // One measurer per asset and resolution (FFTW plans are made here, serially), then the views in parallel.
  std::map<std::pair<int, std::uint32_t>, std::unique_ptr<spectra::ProfileMeasurer>> measurers;
  std::vector<std::vector<spectra::LevelInput>> inputs(scene.assets.size());
  for (std::size_t i = 0; i < views.size(); ++i) {
    const int a = views[i].asset;
    auto& m = measurers[{a, tasks[i].pixels}];
    if (m) continue;
    if (inputs[std::size_t(a)].empty())
      inputs[std::size_t(a)] = bake::spectra_levels(scene.assets[std::size_t(a)].chain);
    spectra::ProfileSettings ps;
    ps.render.pixels = tasks[i].pixels;
    m = std::make_unique<spectra::ProfileMeasurer>(inputs[std::size_t(a)],
                                                   scene.assets[std::size_t(a)].material, ps);
  }
  std::vector<spectra::ViewMeasurement> measured(tasks.size());
  tbb::parallel_for(std::size_t(0), tasks.size(), [&](std::size_t i) {
    measured[i] = measurers.at({views[i].asset, tasks[i].pixels})->measure(tasks[i].view);
  });

  // Score every level with the perceptual rule's thresholds on a one-view profile of that exact view.
  std::vector<ExactScores> out;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const ExactView& v = views[i];
    const Asset& a = scene.assets[std::size_t(v.asset)];
    const spectra::ProfileMeasurer& m = *measurers.at({v.asset, tasks[i].pixels});
    spectra::ProfileData d;
    std::copy(m.sphere(), m.sphere() + 4, d.sphere);
    d.snapshot_pixels = tasks[i].pixels;
    d.levels.assign(a.profile.levels, a.profile.levels + a.profile.meta.level_count);
    d.views = {tasks[i].view};
    d.orientations = spectra::orientation_angles(spectra::AnalysisSettings{});
    d.bands = m.analyzer().bands();
    d.lost = measured[i].lost;
    d.features = measured[i].features;
    const Blob blob = spectra::encode_profile(d);
    Profile p;
    if (open_profile(blob.data(), blob.size, &p) != ProfileStatus::Ok)
      throw std::logic_error("ground-truth profile does not open");
    SchedulerConfig c = perceptual;
    c.max_objects = 1;
    c.max_profiles = 1;
    c.hysteresis_margin = 0;
    c.hysteresis_frames = 0;
    c.saccade_speed = 0;
    c.keep_scores = true;
    Scheduler s(c);
    s.add_profile(p);
    const ObjectId id = s.add_object(0, v.transform);
    const float vf[3] = {float(v.velocity.x), float(v.velocity.y), float(v.velocity.z)};
    s.set_velocity(id, vf);
    s.run_frame(*v.frame);
    ExactScores e;
    e.pixels = tasks[i].pixels;
    const float* scores = s.scores(id);
    for (std::uint32_t k = 0; k < p.meta.level_count; ++k) e.scores[k] = scores[k];
    out.push_back(e);
  }
  return out;
}

std::vector<Judged> judge_decisions(const Simulation& sim, std::uint32_t count, unsigned seed) {
  const SceneAssets& scene = sim.scene();
  const std::size_t objects = scene.instances.size(), frames = sim.frame_index();
  std::vector<std::uint64_t> candidates;
  for (std::size_t f = 0; f < frames; ++f)
    for (std::uint32_t i = 0; i < objects; ++i)
      if (sim.in_view(i, f)) candidates.push_back(f * objects + i);
  std::mt19937 rng(seed * 31u + 5u);
  std::shuffle(candidates.begin(), candidates.end(), rng);
  candidates.resize(std::min<std::size_t>(count, candidates.size()));
  std::sort(candidates.begin(), candidates.end());

  // Each decision at the exact view of its frame, at the display's pixels per degree (its centre's).
  const SimulationOptions& o = sim.options();
  const double ppd = double(o.viewport) / (2 * std::tan(0.5 * double(o.fov_deg) / kDeg)) / kDeg;
  std::vector<ExactView> views;
  std::vector<Judged> out;
  for (std::uint64_t c : candidates) {
    Judged j{};
    j.frame = std::uint32_t(c / objects);
    j.object = std::uint32_t(c % objects);
    const Instance& in = scene.instances[j.object];
    views.push_back({in.asset, sim.transform(j.object, j.frame), sim.velocity(j.object, j.frame), in.radius,
                     &sim.frame(j.frame)});
    out.push_back(j);
  }
  const std::vector<ExactScores> scored =
      judge_exact_views(scene, views, sim.rule("perceptual").scheduler->config(), ppd);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].pixels = scored[i].pixels;
    out[i].scores = scored[i].scores;
  }
  return out;
}

std::string explain_text(const Simulation& sim, std::uint32_t object) {
  const std::size_t f = sim.frame_index() - 1;
  const Instance& in = sim.scene().instances[object];
  const Asset& a = sim.scene().assets[std::size_t(in.asset)];
  const Scheduler& s = *sim.rule("perceptual").scheduler;
  ObjectExplain e{};
  if (!s.explain(object, &e))
    throw std::runtime_error("explain: object " + std::to_string(object) + " is not scheduled");
  const Profile& p = a.profile;
  char line[256];
  std::string out;
  auto add = [&](const char* fmt, auto... args) {
    std::snprintf(line, sizeof line, fmt, args...);
    out += line;
  };
  add("object %u '%s' (%s, %u levels) in frame %zu at %.3f s%s\n", object, in.name.c_str(), a.name.c_str(),
      p.meta.level_count, f, double(f) / sim.options().fps, sim.saccade(f) ? " (during a saccade)" : "");
  add("  distance %.2f m, angular diameter %.2f deg, eccentricity %.2f deg from the gaze%s\n",
      double(e.distance_m), double(e.angular_diameter_deg), double(e.eccentricity_deg),
      sim.gaze()[f].confidence > 0 ? "" : " (no gaze: blink)");
  add("  image velocity %.2f deg/s, retinal velocity %.2f deg/s; profile view %u\n",
      double(e.image_velocity_deg_s), double(e.retinal_velocity_deg_s), e.view);
  add("  %-6s %10s %9s %12s %14s %12s %12s\n", "level", "triangles", "score", "limit band", "at",
      "orientation", "threshold");
  for (std::uint32_t k = 0; k < e.level_count; ++k) {
    const LevelExplain& l = e.levels[k];
    if (k == 0) {
      add("  %-6u %10u %9s %12s %14s %12s %12s\n", k, p.levels[k].triangles, "0", "-", "-", "-", "-");
      continue;
    }
    add("  %-6u %10u %9.3f %7.1f cpod %9.2f cpd %8.1f deg %12.4g%s\n", k, p.levels[k].triangles,
        double(l.score), double(p.bands[l.band]), double(l.frequency_cpd),
        double(p.orientations[l.orientation]), double(l.threshold),
        l.score <= 1 ? "  invisible" : "  visible");
  }
  add("  chosen: level %u (perceptual: the coarsest with score <= 1, after hysteresis and saccade gating)\n",
      s.level(object));
  add("  other rules this frame:");
  for (const char* name : {"reddy", "distance", "screen-size", "ungated"})
    add(" %s %u", name, sim.rule(name).scheduler->level(object));
  add("\n");
  return out;
}

std::string explain_frame(const SceneAssets& scene, SimulationOptions options, std::size_t frame,
                          const std::string& object) {
  std::uint32_t index = 0;
  while (index < scene.instances.size() && scene.instances[index].name != object) ++index;
  if (index == scene.instances.size()) {
    try {
      index = std::uint32_t(std::stoul(object));
    } catch (...) { index = std::uint32_t(scene.instances.size()); }
    if (index >= scene.instances.size())
      throw std::runtime_error("explain: no object '" + object + "' (a node name or an index below " +
                               std::to_string(scene.instances.size()) + ")");
  }
  options.validate = 0;
  Simulation sim(scene, options);
  if (frame >= sim.frame_count())
    throw std::runtime_error("explain: frame " + std::to_string(frame) + " is past the run's " +
                             std::to_string(sim.frame_count()) + " frames");
  while (sim.frame_index() <= frame) sim.step();
  return explain_text(sim, index);
}

}  // namespace acuity::sim
