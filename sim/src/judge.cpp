// Ground truth for the simulation's decisions, and the explanation of one decision.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>

#include <oneapi/tbb/parallel_for.h>

#include "acuity/sim/simulation.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "geometry.hpp"

namespace acuity::sim {

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

  // The exact view from the eyes' midpoint, and the display's pixels across the object there.
  struct Task {
    Judged j;
    ProfileView view;
    int asset;
  };
  std::vector<Task> tasks;
  const SimulationOptions& o = sim.options();
  const double ppd =
      double(o.viewport) / (2 * std::tan(0.5 * double(o.fov_deg) / kDeg)) / kDeg;  // at the centre
  for (std::uint64_t c : candidates) {
    Task t{};
    t.j.frame = std::uint32_t(c / objects);
    t.j.object = std::uint32_t(c % objects);
    const Instance& in = scene.instances[t.j.object];
    t.asset = in.asset;
    const Frame& fr = sim.frame(t.j.frame);
    const glm::dvec3 eye =
        0.5 * (glm::dvec3(fr.eyes[0].position[0], fr.eyes[0].position[1], fr.eyes[0].position[2]) +
               glm::dvec3(fr.eyes[1].position[0], fr.eyes[1].position[1], fr.eyes[1].position[2]));
    const ObjectTransform tr = sim.transform(t.j.object, t.j.frame);
    const glm::dquat q(tr.rotation[3], tr.rotation[0], tr.rotation[1], tr.rotation[2]);
    const glm::dvec3 centre = world_centre(scene.assets[std::size_t(in.asset)], tr);
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
    const double theta = distance > in.radius ? 2 * std::asin(in.radius / distance) * kDeg : 180.0;
    std::uint32_t px = 64;
    while (px < 512 && double(px) < 2 * theta * ppd)
      px *= 2;  // bands up to px / 4 reach the display's Nyquist
    t.j.pixels = px;
    tasks.push_back(t);
  }

  // One measurer per asset and resolution (FFTW plans are made here, serially), then the views in parallel.
  std::map<std::pair<int, std::uint32_t>, std::unique_ptr<spectra::ProfileMeasurer>> measurers;
  std::vector<std::vector<spectra::LevelInput>> inputs(scene.assets.size());
  for (std::size_t a = 0; a < scene.assets.size(); ++a)
    inputs[a] = bake::spectra_levels(scene.assets[a].chain);
  for (const Task& t : tasks) {
    auto& m = measurers[{t.asset, t.j.pixels}];
    if (!m) {
      spectra::ProfileSettings ps;
      ps.render.pixels = t.j.pixels;
      m = std::make_unique<spectra::ProfileMeasurer>(inputs[std::size_t(t.asset)],
                                                     scene.assets[std::size_t(t.asset)].material, ps);
    }
  }
  std::vector<spectra::ViewMeasurement> measured(tasks.size());
  tbb::parallel_for(std::size_t(0), tasks.size(), [&](std::size_t i) {
    measured[i] = measurers.at({tasks[i].asset, tasks[i].j.pixels})->measure(tasks[i].view);
  });

  // Score every level with the perceptual rule's thresholds on a one-view profile of that exact view.
  std::vector<Judged> out;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    Task& t = tasks[i];
    const Asset& a = scene.assets[std::size_t(t.asset)];
    const spectra::ProfileMeasurer& m = *measurers.at({t.asset, t.j.pixels});
    spectra::ProfileData d;
    std::copy(m.sphere(), m.sphere() + 4, d.sphere);
    d.snapshot_pixels = t.j.pixels;
    d.levels.assign(a.profile.levels, a.profile.levels + a.profile.meta.level_count);
    d.views = {t.view};
    d.orientations = spectra::orientation_angles(spectra::AnalysisSettings{});
    d.bands = m.analyzer().bands();
    d.lost = measured[i].lost;
    d.features = measured[i].features;
    const Blob blob = spectra::encode_profile(d);
    Profile p;
    if (open_profile(blob.data(), blob.size, &p) != ProfileStatus::Ok)
      throw std::logic_error("ground-truth profile does not open");
    SchedulerConfig c = sim.rule("perceptual").scheduler->config();
    c.max_objects = 1;
    c.max_profiles = 1;
    c.hysteresis_margin = 0;
    c.hysteresis_frames = 0;
    c.saccade_speed = 0;
    c.keep_scores = true;
    Scheduler s(c);
    s.add_profile(p);
    const ObjectId id = s.add_object(0, sim.transform(t.j.object, t.j.frame));
    const glm::dvec3 v = sim.velocity(t.j.object, t.j.frame);
    const float vf[3] = {float(v.x), float(v.y), float(v.z)};
    s.set_velocity(id, vf);
    s.run_frame(sim.frame(t.j.frame));
    t.j.scores.fill(0);
    const float* scores = s.scores(id);
    for (std::uint32_t k = 0; k < p.meta.level_count; ++k) t.j.scores[k] = scores[k];
    out.push_back(t.j);
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
