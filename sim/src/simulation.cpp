#include "acuity/sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geometry.hpp"

namespace acuity::sim {

std::vector<Tuning> swept_tunings(int wider) {
  std::vector<Tuning> out;
  for (int i = -6; i <= 2 + wider; ++i)
    out.push_back({"perceptual", SelectionRule::Perceptual, std::exp2(0.25 * i)});
  for (int i = -20 - wider; i <= 12; ++i)
    out.push_back({"screen-size", SelectionRule::ScreenSize, std::exp2(0.25 * i)});
  for (int i = -8; i <= 20; ++i) out.push_back({"distance", SelectionRule::Distance, std::exp2(0.25 * i)});
  return out;
}

std::vector<Tuning> main_tunings() {
  std::vector<Tuning> out;
  for (const RuleInfo& rule : selection_rules())
    out.push_back({rule.name, rule.rule, rule.rule == SelectionRule::Reddy ? 0.0 : 1.0});
  return out;
}

void tune(SchedulerConfig* c, SelectionRule rule, double parameter) {
  c->rule = rule;
  if (rule == SelectionRule::Perceptual) c->quality = float(parameter);
  if (rule == SelectionRule::ScreenSize) c->pixel_error = float(parameter);
  if (rule == SelectionRule::Distance) c->distance_scale = float(parameter);
}

std::string perceptual_text(const SchedulerConfig& c, const Profile& profile) {
  return std::string("model ") + to_string(c.model) + ", " +
         (Scheduler::table_bytes(profile, c) > 0 ? "tabulated" : "exact") + " thresholds";
}

Simulation::Simulation(const SceneAssets& scene, const SimulationOptions& o) : scene_(scene), options_(o) {
  if (!(o.fps > 0) || !(o.seconds > 0))
    throw std::runtime_error("simulate: seconds and fps must be positive");
  objects_ = scene.instances.size();
  const std::size_t frames = std::size_t(std::llround(o.seconds * o.fps));
  head_ = o.head_file.empty() ? flythrough(scene, o.seconds, o.fps)
                              : head_path_from(read_table(o.head_file), o.fps, frames);
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
    const glm::dquat turn =
        sign > 0 ? h.orientation * glm::inverse(p.orientation) : p.orientation * glm::inverse(h.orientation);
    const double turn_angle =
        2 * std::atan2(glm::length(glm::dvec3(turn.x, turn.y, turn.z)), std::abs(turn.w));
    const glm::dvec3 turn_axis =
        glm::length(glm::dvec3(turn.x, turn.y, turn.z)) > 0
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
      const glm::dvec3 at =
          h.position + h.orientation * glm::dvec3((e ? 0.5 : -0.5) * o.eye_separation, 0, 0);
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
      const glm::dvec3 w =
          glm::length(gaze_axis) > 0 ? glm::normalize(gaze_axis) * gaze_speed : glm::dvec3(0.0);
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
      const glm::dvec3 h =
          to_head(head_[f], world_centre(scene.assets[std::size_t(in.asset)], transform(i, f)));
      const double r = in.radius;
      in_view_[f * objects_ + i] =
          c * h.x + s * h.z < r && -c * h.x + s * h.z < r && c * h.y + s * h.z < r && -c * h.y + s * h.z < r;
      if (in_view_[f * objects_ + i])
        finest_[f] += scene.assets[std::size_t(in.asset)].profile.levels[0].triangles;
    }

  // Rules: the four, the perceptual rule ungated, then sweeps in quarter octaves: the perceptual
  // rule's quality q 0.35..1.4, the baselines' screen-size 1/32..8 px and distance scale 1/4..32.
  // Every rule but "ungated" coarsens after 3 calm frames at a score <= 0.9 (its hysteresis) and in a
  // saccade or after the scheduler's max_coarsen_wait frames; "ungated" takes its own choice at once
  // (a saccade still counts as fixation), showing what that switching policy costs.
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
    if (rule == SelectionRule::Perceptual) c2.model = o.model;
    if (name == "ungated") {
      c2.hysteresis_margin = 0;
      c2.hysteresis_frames = 0;
      c2.max_coarsen_wait = 0;
    }
    tune(&c2, rule, parameter);
    r.scheduler = std::make_unique<Scheduler>(c2);
    for (const Asset& a : scene.assets) r.scheduler->add_profile(a.profile);
    for (const Instance& in : scene.instances) r.scheduler->add_object(in.asset, in.transform);
    r.levels.assign(frames * objects_, 0);
    rules_.push_back(std::move(r));
  };
  for (const Tuning& t : main_tunings()) add(t.name, t.rule, t.parameter, false);
  add("ungated", SelectionRule::Perceptual, 1, false);
  for (const Tuning& t : swept_tunings()) add(t.name, t.rule, t.parameter, true);
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
  struct Moved {
    ObjectTransform transform;
    float velocity[3];
  };
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
      if (in_view(i, f))
        drawn += scene_.assets[std::size_t(scene_.instances[i].asset)].profile.levels[level].triangles;
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

Decision example_decision(const Simulation& sim) {
  Decision d;
  if (sim.frame_count() == 0) return d;
  const std::size_t f = d.frame = sim.frame_count() / 2;
  const std::vector<std::int32_t>& targets = sim.generated().targets;
  if (!targets.empty() && targets[f] >= 0) d.object = targets[f];
  for (std::uint32_t i = 0; i < sim.scene().instances.size() && d.object < 0; ++i)
    if (sim.in_view(i, f)) d.object = i;
  return d;
}

}  // namespace acuity::sim
