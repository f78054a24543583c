#include "simulation.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include <oneapi/tbb/parallel_for.h>

#include "acuity/spectra/profile_writer.hpp"

namespace acuity::tools {
namespace {

constexpr double kPi = 3.14159265358979323846, kDeg = 180.0 / kPi;

glm::dvec3 to_head(const HeadPose& h, const glm::dvec3& world_point) {
  return glm::inverse(h.orientation) * (world_point - h.position);
}

double angle_deg(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * kDeg;
}

glm::dvec3 slerp_direction(const glm::dvec3& a, const glm::dvec3& b, double s) {
  const double angle = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
  if (angle < 1e-9) return b;
  const double sa = std::sin(angle);
  return glm::normalize(a * (std::sin((1 - s) * angle) / sa) + b * (std::sin(s * angle) / sa));
}

glm::dvec3 world_centre(const Asset& a, const ObjectTransform& t) {
  const glm::dquat q(t.rotation[3], t.rotation[0], t.rotation[1], t.rotation[2]);
  const glm::dvec3 c(a.profile.meta.sphere[0], a.profile.meta.sphere[1], a.profile.meta.sphere[2]);
  return glm::dvec3(t.position[0], t.position[1], t.position[2]) + q * (double(t.scale) * c);
}

}  // namespace

const char* to_string(GazePhase p) {
  switch (p) {
    case GazePhase::Fixation: return "fixation";
    case GazePhase::Saccade: return "saccade";
    case GazePhase::Pursuit: return "pursuit";
    case GazePhase::Blink: return "blink";
    case GazePhase::Recorded: return "recorded";
  }
  return "?";
}

glm::dvec3 Mover::position(double t) const {
  const double a = phase + speed / radius * t;
  return centre + radius * glm::dvec3(std::cos(a), 0, std::sin(a));
}

std::vector<HeadPose> flythrough(const SceneAssets& scene, double seconds, double fps) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const Instance& in : scene.instances)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], in.transform.position[k] - in.radius);
      hi[k] = std::max(hi[k], in.transform.position[k] + in.radius);
    }
  const bool along_z = hi.z - lo.z >= hi.x - lo.x;
  const glm::dvec3 centre = 0.5 * (lo + hi);
  // Start 2 m before the +z (or +x) end, walk towards the other end over the run, at most 1.4 m/s.
  const double length = (along_z ? hi.z - lo.z : hi.x - lo.x) + 2.0;
  const double speed = std::min(1.4, length / std::max(seconds, 1e-3));
  glm::dvec3 start(centre.x, lo.y + 1.6, centre.z), heading(0, 0, -1);
  if (along_z) start.z = hi.z + 2.0;
  else { start.x = hi.x + 2.0; heading = {-1, 0, 0}; }
  const double base_yaw = std::atan2(-heading.x, -heading.z);
  std::vector<HeadPose> out(std::size_t(std::llround(seconds * fps)));
  for (std::size_t f = 0; f < out.size(); ++f) {
    const double t = double(f) / fps;
    const double yaw = base_yaw + 10.0 / kDeg * std::sin(0.3 * t);
    out[f].position = start + heading * (speed * t);
    out[f].orientation = glm::angleAxis(yaw, glm::dvec3(0, 1, 0));
  }
  return out;
}

std::vector<Mover> choose_movers(const SceneAssets& scene, std::uint32_t count, unsigned seed) {
  std::vector<std::uint32_t> order(scene.instances.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937 rng(seed * 7919u + 17u);
  std::shuffle(order.begin(), order.end(), rng);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Mover> out;
  for (std::uint32_t i = 0; i < std::min<std::size_t>(count, order.size()); ++i) {
    const Instance& in = scene.instances[order[i]];
    Mover m;
    m.instance = order[i];
    m.radius = std::max(0.5, in.radius);
    m.speed = 1.0;
    m.phase = unit(rng) * 2 * kPi;
    const glm::dvec3 p(in.transform.position[0], in.transform.position[1], in.transform.position[2]);
    m.centre = p - m.radius * glm::dvec3(std::cos(m.phase), 0, std::sin(m.phase));  // on its own place at t = 0
    out.push_back(m);
  }
  std::sort(out.begin(), out.end(), [](const Mover& a, const Mover& b) { return a.instance < b.instance; });
  return out;
}

GeneratedGaze generate_gaze(const SceneAssets& scene, const std::vector<HeadPose>& head, const std::vector<Mover>& movers,
                            double fps, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  auto uniform = [&](double a, double b) { return a + (b - a) * unit(rng); };
  std::vector<int> mover_of(scene.instances.size(), -1);
  for (std::size_t i = 0; i < movers.size(); ++i) mover_of[movers[i].instance] = int(i);

  // A target: an object (maybe moving) and an offset from its centre, or a point straight ahead.
  struct Target { int object = -1; glm::dvec3 offset{0.0}; glm::dvec3 fixed{0.0}; };
  auto world_point = [&](const Target& g, std::size_t f) {
    if (g.object < 0) return g.fixed;
    const Instance& in = scene.instances[std::size_t(g.object)];
    ObjectTransform t = in.transform;
    if (mover_of[std::size_t(g.object)] >= 0) {
      const glm::dvec3 p = movers[std::size_t(mover_of[std::size_t(g.object)])].position(double(f) / fps);
      for (int k = 0; k < 3; ++k) t.position[k] = p[k];
    }
    return world_centre(scene.assets[std::size_t(in.asset)], t) + g.offset;
  };
  auto direction = [&](const Target& g, std::size_t f) { return glm::normalize(to_head(head[f], world_point(g, f))); };
  auto choose = [&](std::size_t f, bool* pursuit) {
    std::vector<int> seen, moving;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
      Target g;
      g.object = int(i);
      const glm::dvec3 h = to_head(head[f], world_point(g, f));
      if (glm::length(h) > 1.5 && angle_deg(h, {0, 0, -1}) < 30) {
        seen.push_back(int(i));
        if (mover_of[i] >= 0) moving.push_back(int(i));
      }
    }
    Target g;
    *pursuit = !moving.empty() && unit(rng) < 0.35;
    if (*pursuit) g.object = moving[std::size_t(unit(rng) * double(moving.size())) % moving.size()];
    else if (!seen.empty()) g.object = seen[std::size_t(unit(rng) * double(seen.size())) % seen.size()];
    else g.fixed = head[f].position + head[f].orientation * glm::dvec3(0, 0, -10);
    if (g.object >= 0) {
      const double r = 0.3 * scene.instances[std::size_t(g.object)].radius;
      g.offset = r * glm::dvec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    }
    return g;
  };

  GeneratedGaze out;
  const std::size_t frames = head.size();
  out.samples.resize(frames);
  out.phases.resize(frames);
  out.targets.resize(frames);
  bool pursuit = false;
  Target current = choose(0, &pursuit), previous = current;
  GazePhase phase = pursuit ? GazePhase::Pursuit : GazePhase::Fixation;
  double phase_end = pursuit ? uniform(0.6, 1.5) : uniform(0.2, 0.45), saccade_start = 0, saccade_length = 0;
  double next_blink = uniform(2, 6), blink_end = -1;
  glm::dvec3 last = direction(current, 0);
  for (std::size_t f = 0; f < frames; ++f) {
    const double t = double(f) / fps;
    if (phase != GazePhase::Saccade && t >= next_blink) {
      blink_end = t + 0.15;
      next_blink = t + uniform(2, 6);
    }
    if (phase == GazePhase::Saccade && t >= saccade_start + saccade_length) {
      phase = pursuit ? GazePhase::Pursuit : GazePhase::Fixation;
      phase_end = t + (pursuit ? uniform(0.6, 1.5) : uniform(0.2, 0.45));
    } else if (phase != GazePhase::Saccade && t >= phase_end) {
      previous = current;
      current = choose(f, &pursuit);
      const double amplitude = angle_deg(direction(previous, f), direction(current, f));
      saccade_start = t;
      saccade_length = 0.021 + 0.0022 * amplitude;  // main sequence (Carpenter 1988)
      phase = GazePhase::Saccade;
    }
    GazeSample& s = out.samples[f];
    if (phase == GazePhase::Saccade) {
      const double u = std::clamp((t - saccade_start) / saccade_length, 0.0, 1.0);
      s.direction = slerp_direction(direction(previous, f), direction(current, f), 0.5 - 0.5 * std::cos(kPi * u));
    } else {
      s.direction = direction(current, f);
    }
    const bool blink = t < blink_end;
    if (blink) s.direction = last;  // the tracker holds its last sample
    s.confidence = blink ? 0.0f : 1.0f;
    last = s.direction;
    out.phases[f] = blink ? GazePhase::Blink : phase;
    out.targets[f] = current.object;
  }
  return out;
}

// ---- the simulation ----

Simulation::Simulation(const SceneAssets& scene, const SimulationOptions& o) : scene_(scene), options_(o) {
  if (!(o.fps > 0) || !(o.seconds > 0)) throw std::runtime_error("simulate: seconds and fps must be positive");
  objects_ = scene.instances.size();
  const std::size_t frames = std::size_t(std::llround(o.seconds * o.fps));
  head_ = o.head_file.empty() ? flythrough(scene, o.seconds, o.fps) : head_path_from(read_table(o.head_file), o.fps, frames);
  movers_ = choose_movers(scene, o.movers, o.seed);
  mover_of_.assign(objects_, -1);
  for (std::size_t i = 0; i < movers_.size(); ++i) mover_of_[movers_[i].instance] = int(i);
  if (o.gaze_file.empty()) {
    generated_ = generate_gaze(scene, head_, movers_, o.fps, o.seed);
    gaze_ = generated_.samples;
  } else {
    gaze_ = gaze_trace_from(read_table(o.gaze_file), o.fps, frames);
  }

  // Frames: two eyes along the head's x axis, velocities by differences between frames.
  const float tan_half = float(std::tan(0.5 * double(o.fov_deg) / kDeg));
  frames_.resize(frames);
  saccade_.assign(frames, 0);
  for (std::size_t f = 0; f < frames; ++f) {
    const HeadPose& h = head_[f];
    const HeadPose& p = head_[f ? f - 1 : std::min<std::size_t>(1, frames - 1)];
    const double sign = f ? 1.0 : -1.0;  // frame 0 differences forwards
    const glm::dvec3 v = sign * (h.position - p.position) * o.fps;
    const glm::dquat turn = sign > 0 ? h.orientation * glm::inverse(p.orientation) : p.orientation * glm::inverse(h.orientation);
    const double turn_angle = 2 * std::atan2(glm::length(glm::dvec3(turn.x, turn.y, turn.z)), std::abs(turn.w));
    const glm::dvec3 turn_axis = glm::length(glm::dvec3(turn.x, turn.y, turn.z)) > 0
                                     ? glm::normalize(glm::dvec3(turn.x, turn.y, turn.z)) * (turn.w < 0 ? -1.0 : 1.0)
                                     : glm::dvec3(0.0);
    const glm::dvec3 omega = turn_axis * (turn_angle * kDeg * o.fps);
    Frame& fr = frames_[f];
    fr.eye_count = 2;
    fr.dt = float(1.0 / o.fps);
    const GazeSample& g = gaze_[f];
    const GazeSample& gp = gaze_[f ? f - 1 : f];
    const glm::dvec3 gaze_axis = glm::cross(gp.direction, g.direction);
    const double gaze_speed = angle_deg(gp.direction, g.direction) * o.fps;
    const bool tracked = g.confidence > 0 && gp.confidence > 0;
    saccade_[f] = tracked && gaze_speed > double(o.saccade_speed);
    for (int e = 0; e < 2; ++e) {
      Eye& eye = fr.eyes[e];
      const glm::dvec3 at = h.position + h.orientation * glm::dvec3((e ? 0.5 : -0.5) * o.eye_separation, 0, 0);
      for (int k = 0; k < 3; ++k) {
        eye.position[k] = at[k];
        eye.velocity[k] = float(v[k]);
        eye.angular_velocity[k] = float(omega[k]);
      }
      eye.orientation[0] = float(h.orientation.x);
      eye.orientation[1] = float(h.orientation.y);
      eye.orientation[2] = float(h.orientation.z);
      eye.orientation[3] = float(h.orientation.w);
      eye.fov_deg[0] = -0.5f * o.fov_deg;
      eye.fov_deg[1] = 0.5f * o.fov_deg;
      eye.fov_deg[2] = 0.5f * o.fov_deg;
      eye.fov_deg[3] = -0.5f * o.fov_deg;
      eye.viewport[0] = eye.viewport[1] = o.viewport;
      Gaze& gz = fr.gaze[e];
      gz.valid = g.confidence > 0;
      gz.confidence = g.confidence;
      for (int k = 0; k < 3; ++k) gz.direction[k] = float(g.direction[k]);
      gz.has_velocity = tracked;
      const glm::dvec3 w = glm::length(gaze_axis) > 0 ? glm::normalize(gaze_axis) * gaze_speed : glm::dvec3(0.0);
      for (int k = 0; k < 3; ++k) gz.angular_velocity[k] = float(w[k]);
    }
  }

  // Objects in view (bounding sphere against the head's frustum), for counting what is drawn.
  in_view_.assign(frames * objects_, 0);
  finest_.assign(frames, 0.0);
  const double c = 1.0 / std::sqrt(1.0 + double(tan_half) * tan_half), s = double(tan_half) * c;
  for (std::size_t f = 0; f < frames; ++f)
    for (std::uint32_t i = 0; i < objects_; ++i) {
      const Instance& in = scene.instances[i];
      const glm::dvec3 h = to_head(head_[f], world_centre(scene.assets[std::size_t(in.asset)], transform(i, f)));
      const double r = in.radius;
      in_view_[f * objects_ + i] = c * h.x + s * h.z < r && -c * h.x + s * h.z < r && c * h.y + s * h.z < r && -c * h.y + s * h.z < r;
      if (in_view_[f * objects_ + i]) finest_[f] += scene.assets[std::size_t(in.asset)].profile.levels[0].triangles;
    }

  // Rules: the four, then sweeps in quarter octaves: the perceptual rule's quality q 0.35..1.4, the
  // baselines' screen-size 1/32..8 px and distance scale 1/4..32.
  auto add = [&](const std::string& name, SelectionRule rule, double parameter, bool sweep) {
    RuleRun r;
    r.name = name;
    r.parameter = parameter;
    r.sweep = sweep;
    SchedulerConfig c2;
    c2.max_objects = std::uint32_t(objects_);
    c2.max_profiles = std::uint32_t(scene.assets.size());
    c2.rule = rule;
    c2.hysteresis_margin = 0.1f;
    c2.hysteresis_frames = 3;
    c2.saccade_speed = o.saccade_speed;
    c2.evaluation = o.evaluation;
    if (rule == SelectionRule::Perceptual) c2.quality = float(parameter);
    if (rule == SelectionRule::ScreenSize) c2.pixel_error = float(parameter);
    if (rule == SelectionRule::Distance) c2.distance_scale = float(parameter);
    r.scheduler = std::make_unique<Scheduler>(c2);
    for (const Asset& a : scene.assets) r.scheduler->add_profile(a.profile);
    for (const Instance& in : scene.instances) r.scheduler->add_object(in.asset, in.transform);
    r.levels.assign(frames * objects_, 0);
    rules_.push_back(std::move(r));
  };
  add("perceptual", SelectionRule::Perceptual, 1, false);
  add("reddy", SelectionRule::Reddy, 0, false);
  add("distance", SelectionRule::Distance, 1, false);
  add("screen-size", SelectionRule::ScreenSize, 1, false);
  for (int i = -6; i <= 2; ++i) add("perceptual", SelectionRule::Perceptual, std::exp2(0.25 * i), true);
  for (int i = -20; i <= 12; ++i) add("screen-size", SelectionRule::ScreenSize, std::exp2(0.25 * i), true);
  for (int i = -8; i <= 20; ++i) add("distance", SelectionRule::Distance, std::exp2(0.25 * i), true);
}

Simulation::~Simulation() = default;

const RuleRun& Simulation::rule(const std::string& name) const {
  for (const RuleRun& r : rules_)
    if (r.name == name && !r.sweep) return r;
  throw std::runtime_error("no rule " + name);
}

ObjectTransform Simulation::transform(std::uint32_t object, std::size_t frame) const {
  ObjectTransform t = scene_.instances[object].transform;
  if (mover_of_[object] >= 0) {
    const glm::dvec3 p = movers_[std::size_t(mover_of_[object])].position(double(frame) / options_.fps);
    for (int k = 0; k < 3; ++k) t.position[k] = p[k];
  }
  return t;
}

glm::dvec3 Simulation::velocity(std::uint32_t object, std::size_t frame) const {
  if (mover_of_[object] < 0) return glm::dvec3(0.0);
  const Mover& m = movers_[std::size_t(mover_of_[object])];
  const double t = double(frame) / options_.fps, dt = 1.0 / options_.fps;
  return (m.position(t + dt) - m.position(t)) / dt;
}

bool Simulation::step() {
  if (next_ >= frames_.size()) return false;
  const std::size_t f = next_++;
  struct Moved { ObjectTransform transform; float velocity[3]; };
  std::vector<Moved> moved(movers_.size());
  for (std::size_t k = 0; k < movers_.size(); ++k) {
    const glm::dvec3 v = velocity(movers_[k].instance, f);
    moved[k] = {transform(movers_[k].instance, f), {float(v.x), float(v.y), float(v.z)}};
  }
  for (RuleRun& r : rules_) {
    for (std::size_t k = 0; k < movers_.size(); ++k) {
      r.scheduler->set_transform(movers_[k].instance, moved[k].transform);
      r.scheduler->set_velocity(movers_[k].instance, moved[k].velocity);
    }
    r.scheduler->run_frame(frames_[f]);
    double drawn = 0;
    for (std::uint32_t i = 0; i < objects_; ++i) {
      const std::uint8_t level = r.scheduler->level(i);
      r.levels[f * objects_ + i] = level;
      if (in_view(i, f)) drawn += scene_.assets[std::size_t(scene_.instances[i].asset)].profile.levels[level].triangles;
    }
    r.drawn.push_back(drawn);
    r.triangles += drawn;
    r.switches += r.scheduler->stats().changed;
    if (!saccade_[f]) r.switches_outside_saccades += r.scheduler->stats().changed;
  }
  return true;
}

double Simulation::all_finest() const {
  double sum = 0;
  for (std::size_t f = 0; f < next_; ++f) sum += finest_[f];
  return sum;
}

void Simulation::run() {
  while (step()) {}
}

// ---- ground truth ----

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
  struct Task { Judged j; ProfileView view; int asset; };
  std::vector<Task> tasks;
  const SimulationOptions& o = sim.options();
  const double ppd = double(o.viewport) / (2 * std::tan(0.5 * double(o.fov_deg) / kDeg)) / kDeg;  // at the centre
  for (std::uint64_t c : candidates) {
    Task t{};
    t.j.frame = std::uint32_t(c / objects);
    t.j.object = std::uint32_t(c % objects);
    const Instance& in = scene.instances[t.j.object];
    t.asset = in.asset;
    const Frame& fr = sim.frame(t.j.frame);
    const glm::dvec3 eye = 0.5 * (glm::dvec3(fr.eyes[0].position[0], fr.eyes[0].position[1], fr.eyes[0].position[2]) +
                                  glm::dvec3(fr.eyes[1].position[0], fr.eyes[1].position[1], fr.eyes[1].position[2]));
    const ObjectTransform tr = sim.transform(t.j.object, t.j.frame);
    const glm::dquat q(tr.rotation[3], tr.rotation[0], tr.rotation[1], tr.rotation[2]);
    const glm::dvec3 centre = world_centre(scene.assets[std::size_t(in.asset)], tr);
    const glm::dvec3 d = glm::inverse(q) * (eye - centre);
    const glm::dquat head(fr.eyes[0].orientation[3], fr.eyes[0].orientation[0], fr.eyes[0].orientation[1], fr.eyes[0].orientation[2]);
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
    while (px < 512 && double(px) < 2 * theta * ppd) px *= 2;  // bands up to px / 4 reach the display's Nyquist
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
      m = std::make_unique<spectra::ProfileMeasurer>(inputs[std::size_t(t.asset)], scene.assets[std::size_t(t.asset)].material, ps);
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
    if (open_profile(blob.data(), blob.size, &p) != ProfileStatus::Ok) throw std::logic_error("ground-truth profile does not open");
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

}  // namespace acuity::tools

namespace acuity::tools {

std::string explain_text(const Simulation& sim, std::uint32_t object) {
  const std::size_t f = sim.frame_index() - 1;
  const Instance& in = sim.scene().instances[object];
  const Asset& a = sim.scene().assets[std::size_t(in.asset)];
  const Scheduler& s = *sim.rule("perceptual").scheduler;
  ObjectExplain e{};
  if (!s.explain(object, &e)) throw std::runtime_error("explain: object " + std::to_string(object) + " is not scheduled");
  const Profile& p = a.profile;
  char line[256];
  std::string out;
  auto add = [&](const char* fmt, auto... args) {
    std::snprintf(line, sizeof line, fmt, args...);
    out += line;
  };
  add("object %u '%s' (%s, %u levels) in frame %zu at %.3f s%s\n", object, in.name.c_str(), a.name.c_str(), p.meta.level_count, f,
      double(f) / sim.options().fps, sim.saccade(f) ? " (during a saccade)" : "");
  add("  distance %.2f m, angular diameter %.2f deg, eccentricity %.2f deg from the gaze%s\n", double(e.distance_m),
      double(e.angular_diameter_deg), double(e.eccentricity_deg), sim.gaze()[f].confidence > 0 ? "" : " (no gaze: blink)");
  add("  image velocity %.2f deg/s, retinal velocity %.2f deg/s; profile view %u\n", double(e.image_velocity_deg_s),
      double(e.retinal_velocity_deg_s), e.view);
  add("  %-6s %10s %9s %12s %14s %12s %12s\n", "level", "triangles", "score", "limit band", "at", "orientation", "threshold");
  for (std::uint32_t k = 0; k < e.level_count; ++k) {
    const LevelExplain& l = e.levels[k];
    if (k == 0) {
      add("  %-6u %10u %9s %12s %14s %12s %12s\n", k, p.levels[k].triangles, "0", "-", "-", "-", "-");
      continue;
    }
    add("  %-6u %10u %9.3f %7.1f cpod %9.2f cpd %8.1f deg %12.4g%s\n", k, p.levels[k].triangles, double(l.score),
        double(p.bands[l.band]), double(l.frequency_cpd), double(p.orientations[l.orientation]), double(l.threshold),
        l.score <= 1 ? "  invisible" : "  visible");
  }
  add("  chosen: level %u (perceptual: the coarsest with score <= 1, after hysteresis and saccade gating)\n", s.level(object));
  add("  other rules this frame:");
  for (const char* name : {"reddy", "distance", "screen-size"}) add(" %s %u", name, sim.rule(name).scheduler->level(object));
  add("\n");
  return out;
}

}  // namespace acuity::tools
