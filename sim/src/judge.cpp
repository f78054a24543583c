// Ground truth: the exact-view check of decisions (a run's, or sampled ones), and the explanation of
// one decision.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>

#include <oneapi/tbb/parallel_for.h>

#include "acuity/sim/detection.hpp"
#include "acuity/sim/simulation.hpp"
#include "acuity/spectra/render.hpp"
#include "exact_view.hpp"
#include "geometry.hpp"

namespace acuity::sim {

namespace {

// The exact view of one decision: the snapshot's direction and up in object space, its pixels, and
// where it lies in the visual field of the frame's eyes.
struct Task {
  ProfileView view;
  std::uint32_t pixels = 0;
  Placement placement;
};

glm::dvec3 vec(const double* p) { return {p[0], p[1], p[2]}; }
glm::dvec3 vec(const float* p) { return {p[0], p[1], p[2]}; }
glm::dquat rotation(const float* q) { return glm::dquat(q[3], q[0], q[1], q[2]); }

Task exact_task(const SceneAssets& scene, const ExactView& v, const SchedulerConfig& c, double ppd) {
  Task t;
  const Frame& fr = *v.frame;
  const std::uint32_t eyes = std::clamp<std::uint32_t>(fr.eye_count, 1, 2);
  glm::dvec3 eye(0.0), eye_velocity(0.0);
  for (std::uint32_t e = 0; e < eyes; ++e) {
    eye += vec(fr.eyes[e].position) / double(eyes);
    eye_velocity += glm::dvec3(vec(fr.eyes[e].velocity)) / double(eyes);
  }
  const ObjectTransform& tr = v.transform;
  const glm::dquat q = rotation(tr.rotation);
  const glm::dvec3 centre = world_centre(scene.assets[std::size_t(v.asset)], tr);
  const glm::dquat head = rotation(fr.eyes[0].orientation);
  // The snapshot's frame in the world: direction (object to eye), up (the head's, made
  // perpendicular) and right = -direction x up, as the renderer's; in object space for the render.
  const glm::dvec3 dir = glm::normalize(eye - centre);
  glm::dvec3 up = head * glm::dvec3(0, 1, 0);
  up -= dir * glm::dot(up, dir);
  if (glm::length(up) < 1e-6) up = std::abs(dir.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  up = glm::normalize(up - dir * glm::dot(up, dir));
  const glm::dvec3 od = glm::inverse(q) * dir, ou = glm::inverse(q) * up;
  for (int k = 0; k < 3; ++k) {
    t.view.direction[k] = float(od[k]);
    t.view.up[k] = float(ou[k]);
  }
  const double distance = glm::length(eye - centre);
  const double theta = distance > v.radius ? 2 * std::asin(v.radius / distance) * kDeg : 180.0;
  t.pixels = 64;
  while (t.pixels < 512 && double(t.pixels) < 2 * theta * ppd)
    t.pixels *= 2;  // bands up to px / 4 reach the display's Nyquist

  Placement& p = t.placement;
  p.centre = centre - eye;
  p.radius = v.radius;
  p.up = up;
  p.right = glm::normalize(glm::cross(-dir, up));
  p.head_up = head * glm::dvec3(0, 1, 0);
  // The gazes the scheduler would take (valid, confident, finite); a saccade counts as fixation.
  glm::dvec3 gaze_velocity(0.0);
  bool tracked = false;
  for (std::uint32_t e = 0; e < eyes; ++e) {
    const Gaze& g = fr.gaze[e];
    const glm::dvec3 gd = vec(g.direction);
    const double gl = glm::length(gd);
    if (!g.valid || g.confidence < c.min_gaze_confidence || !std::isfinite(gl) || gl < 0.5) continue;
    const glm::dquat er = rotation(fr.eyes[e].orientation);
    p.gazes.push_back(er * (gd / gl));
    const glm::dvec3 gw = vec(g.angular_velocity);
    if (e == 0 && g.has_velocity && std::isfinite(glm::length(gw)) &&
        !(c.saccade_speed > 0 && glm::length(gw) > double(c.saccade_speed))) {
      tracked = true;  // d(gaze)/dt in the world [deg/s]: eye in head, carried by the head, and the head's
      gaze_velocity = er * glm::cross(gw, gd / gl) + glm::cross(vec(fr.eyes[0].angular_velocity), p.gazes[0]);
    }
  }
  // Without a gaze, the scheduler's assumption: anywhere within its no-gaze disc about the view centre.
  p.view_centre = head * glm::dvec3(0, 0, -1);
  p.no_gaze_radius_deg = double(c.no_gaze_radius_deg);
  // The image's motion [deg/s] at the object's centre, and its slip on the retina by the scheduler's
  // own rule (object_retinal_slip).
  const glm::dvec3 u = -dir, rel = v.velocity - eye_velocity;
  const glm::vec3 world(kDeg * (rel - glm::dot(rel, u) * u) / std::max(distance, 1e-9));
  const glm::vec3 turn(kDeg * glm::cross(vec(fr.eyes[0].angular_velocity), u));
  const glm::vec3 gaze(gaze_velocity);
  glm::vec3 slip_f;
  object_retinal_slip(&world.x, &turn.x, tracked ? &gaze.x : nullptr, c.params, &slip_f.x);
  const glm::dvec3 slip(slip_f);
  p.retinal_velocity = {glm::dot(slip, p.right), glm::dot(slip, p.up)};
  return t;
}

// The exact views' tasks, one detector per resolution and the chains' render inputs (FFTW plans are
// made here, serially); then each view rendered and scored in parallel (score(i, render)).
struct ExactJudge {
  const SceneAssets& scene;
  const std::vector<ExactView>& views;
  std::vector<Task> tasks;
  std::map<std::uint32_t, std::unique_ptr<Detector>> detectors;
  std::vector<std::vector<spectra::LevelInput>> inputs;
  std::vector<std::array<float, 4>> spheres;

  ExactJudge(const SceneAssets& s, const std::vector<ExactView>& v, const SchedulerConfig& perceptual,
             double ppd)
      : scene(s), views(v), inputs(s.assets.size()), spheres(s.assets.size()) {
    for (const ExactView& view : views) tasks.push_back(exact_task(scene, view, perceptual, ppd));
    DetectionSettings settings;
    settings.white_luminance = perceptual.params.luminance;
    settings.nyquist_cpd = 0.5 * ppd;
    settings.params = perceptual.params;
    for (std::size_t i = 0; i < views.size(); ++i) {
      auto& d = detectors[tasks[i].pixels];
      if (!d) d = std::make_unique<Detector>(tasks[i].pixels, settings);
      const std::size_t a = std::size_t(views[i].asset);
      if (!inputs[a].empty()) continue;
      inputs[a] = bake::spectra_levels(scene.assets[a].chain);
      spectra::bounding_sphere(inputs[a][0].mesh, spheres[a].data());  // every level framed by level 0's
    }
  }
  // Calls each(i, render, score) for every view in parallel: render(mesh) draws a mesh of the view's
  // asset at the view, score(image) is the detection model's score of it against level 0's.
  template <class F>
  void run(F&& each) const {
    tbb::parallel_for(std::size_t(0), tasks.size(), [&](std::size_t i) {
      const std::size_t a = std::size_t(views[i].asset);
      spectra::RenderSettings rs;
      rs.pixels = tasks[i].pixels;
      std::copy(spheres[a].begin(), spheres[a].end(), rs.sphere);
      const spectra::Material& material = scene.assets[a].material;
      const Detector& d = *detectors.at(tasks[i].pixels);
      const auto render = [&](const spectra::MeshView& mesh) {
        return spectra::render_snapshot(mesh, material, tasks[i].view, rs);
      };
      const auto reference = d.prepare(render(inputs[a][0].mesh), tasks[i].placement);
      each(i, render, [&](const spectra::Image& image) { return float(d.detect(image, *reference).score); });
    });
  }
};

}  // namespace

std::vector<ExactScores> judge_exact_views(const SceneAssets& scene, const std::vector<ExactView>& views,
                                           const SchedulerConfig& perceptual, double ppd) {
  const ExactJudge judge(scene, views, perceptual, ppd);
  std::vector<ExactScores> out(views.size());
  judge.run([&](std::size_t i, const auto& render, const auto& score) {
    const std::vector<spectra::LevelInput>& levels = judge.inputs[std::size_t(views[i].asset)];
    out[i].pixels = judge.tasks[i].pixels;
    for (std::size_t k = 1; k < levels.size() && k < kMaxLevels; ++k)
      out[i].scores[k] = score(render(levels[k].mesh));
  });
  return out;
}

std::vector<float> judge_exact_triangles(const SceneAssets& scene, const std::vector<ExactView>& views,
                                         const std::vector<std::vector<std::uint32_t>>& indices,
                                         const SchedulerConfig& perceptual, double ppd) {
  const ExactJudge judge(scene, views, perceptual, ppd);
  std::vector<float> out(views.size());
  judge.run([&](std::size_t i, const auto& render, const auto& score) {
    spectra::MeshView mesh = judge.inputs[std::size_t(views[i].asset)][0].mesh;
    mesh.indices = indices[i].data();
    mesh.index_count = indices[i].size();
    out[i] = score(render(mesh));
  });
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
