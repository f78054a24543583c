#include "acuity/sim/generators.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <stdexcept>

#include "acuity/lodgen/mesh.hpp"
#include "geometry.hpp"

namespace acuity::sim {
namespace {

glm::dvec3 slerp_direction(const glm::dvec3& a, const glm::dvec3& b, double s) {
  const double angle = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
  if (angle < 1e-9) return b;
  const double sa = std::sin(angle);
  return glm::normalize(a * (std::sin((1 - s) * angle) / sa) + b * (std::sin(s * angle) / sa));
}

}  // namespace

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
  if (along_z)
    start.z = hi.z + 2.0;
  else {
    start.x = hi.x + 2.0;
    heading = {-1, 0, 0};
  }
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
    m.centre =
        p - m.radius * glm::dvec3(std::cos(m.phase), 0, std::sin(m.phase));  // on its own place at t = 0
    out.push_back(m);
  }
  std::sort(out.begin(), out.end(), [](const Mover& a, const Mover& b) { return a.instance < b.instance; });
  return out;
}

GeneratedGaze generate_gaze(const SceneAssets& scene, const std::vector<HeadPose>& head,
                            const std::vector<Mover>& movers, double fps, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  auto uniform = [&](double a, double b) { return a + (b - a) * unit(rng); };
  std::vector<int> mover_of(scene.instances.size(), -1);
  for (std::size_t i = 0; i < movers.size(); ++i) mover_of[movers[i].instance] = int(i);

  // A target: an object (maybe moving) and an offset from its centre, or a point straight ahead.
  struct Target {
    int object = -1;
    glm::dvec3 offset{0.0};
    glm::dvec3 fixed{0.0};
  };
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
  auto direction = [&](const Target& g, std::size_t f) {
    return glm::normalize(to_head(head[f], world_point(g, f)));
  };
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
    if (*pursuit)
      g.object = moving[std::size_t(unit(rng) * double(moving.size())) % moving.size()];
    else if (!seen.empty())
      g.object = seen[std::size_t(unit(rng) * double(seen.size())) % seen.size()];
    else
      g.fixed = head[f].position + head[f].orientation * glm::dvec3(0, 0, -10);
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
      s.direction =
          slerp_direction(direction(previous, f), direction(current, f), 0.5 - 0.5 * std::cos(kPi * u));
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

std::vector<DemoMesh> demo_meshes(const std::string& cgal_meshes, const std::string& assimp_models,
                                  const std::string& webxr_profiles) {
  namespace fs = std::filesystem;
  const std::string webxr = "npm @webxr-input-profiles/assets";
  std::vector<DemoMesh> out;
  for (const char* name : {"elephant", "camel", "cow", "fandisk"})
    out.push_back(
        {name, (fs::path(cgal_meshes) / (std::string(name) + ".off")).string(), "libcgal-demo", false});
  out.push_back(
      {"wuson", (fs::path(assimp_models) / "OFF" / "Wuson.off").string(), "assimp-testmodels", true});
  out.push_back(
      {"generic-hand", (fs::path(webxr_profiles) / "generic-hand" / "left.glb").string(), webxr, true});
  out.push_back(
      {"google-daydream", (fs::path(webxr_profiles) / "google-daydream" / "none.glb").string(), webxr, true});
  for (const DemoMesh& m : out)
    if (!fs::exists(m.path))
      throw std::runtime_error("demo mesh " + m.name + " not found: " + m.path + " (" + m.package +
                               "; bash scripts/bootstrap.sh deps installs it)");
  return out;
}

// The field: 8 x 8 objects 3 m apart resting on the ground, each scaled to a 1.5 m bounding
// sphere, with a random turn about the vertical.
std::vector<lodgen::LodInstance> demo_field(const std::vector<lodgen::LodObject>& objects, unsigned seed) {
  struct Bounds {
    double centre[3], scale;
  };  // bounding-box centre, scale to a 0.75 m radius
  std::vector<Bounds> bounds;
  for (const lodgen::LodObject& obj : objects) {
    const lodgen::Mesh& m = obj.chain.levels[0].mesh;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (std::size_t v = 0; v < m.vertex_count(); ++v)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], double(m.positions[3 * v + std::size_t(k)]));
        hi[k] = std::max(hi[k], double(m.positions[3 * v + std::size_t(k)]));
      }
    bounds.push_back({{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])},
                      0.75 / (0.5 * lodgen::diameter(m))});
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<lodgen::LodInstance> out;
  for (int i = 0; i < 64; ++i) {
    const Bounds& b = bounds[std::size_t(i) % bounds.size()];
    const double s = b.scale, yaw = unit(rng) * 2 * kPi, c = std::cos(yaw), sn = std::sin(yaw);
    const double target[3] = {(i % 8 - 3.5) * 3.0, 0.75,
                              -(4.0 + (i / 8) * 3.0)};  // where the box centre goes
    lodgen::LodInstance in;
    in.object = int(std::size_t(i) % objects.size());
    in.name = objects[std::size_t(i) % objects.size()].name + "_" + std::to_string(i);
    in.matrix = {s * c, 0, -s * sn, 0, 0, s, 0, 0, s * sn, 0, s * c, 0, 0, 0, 0, 1};
    const double rb[3] = {s * (c * b.centre[0] + sn * b.centre[2]), s * b.centre[1],
                          s * (-sn * b.centre[0] + c * b.centre[2])};
    for (int k = 0; k < 3; ++k) in.matrix[std::size_t(12 + k)] = target[k] - rb[k];
    out.push_back(in);
  }
  return out;
}

}  // namespace acuity::sim
