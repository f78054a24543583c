// `acuity simulate`'s outputs: CSV files, the summary, frame pictures and plots.
#include <chrono>
#include <cstdio>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "acuity/file.hpp"
#include "frame_image.hpp"
#include "simulation.hpp"

namespace acuity::tools {
namespace fs = std::filesystem;
namespace {

void save(const std::string& path, const std::string& text, std::vector<std::string>* written) {
  std::string error;
  if (!write_file_atomically(path, text.data(), text.size(), &error)) throw std::runtime_error(error);
  written->push_back(path);
}

std::uint32_t visible_losses(const RuleRun& r, const std::vector<Judged>& judged, std::size_t objects) {
  std::uint32_t n = 0;
  for (const Judged& j : judged) n += j.scores[r.levels[std::size_t(j.frame) * objects + j.object]] > 1.0f;
  return n;
}

// The plot script: next to the sources in a build tree, in share/acuity when installed.
std::string plot_script() {
  for (const char* p : {ACUITY_PLOT_SCRIPT_SOURCE, ACUITY_PLOT_SCRIPT_INSTALLED})
    if (fs::exists(p)) return p;
  return {};
}

extern "C" char** environ;

// Runs `program` with `args` (no shell: each argument reaches it as given, quotes and all), its
// standard output discarded. Returns its exit status, or -1 when it cannot be started.
int run_program(const std::string& program, const std::vector<std::string>& args) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(program.c_str()));
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  if (posix_spawn_file_actions_init(&actions) != 0) return -1;
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int started = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (started != 0) return -1;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

std::vector<std::string> report(Simulation& sim, const std::vector<Judged>& judged) {
  const SceneAssets& scene = sim.scene();
  const SimulationOptions& o = sim.options();
  const std::size_t objects = scene.instances.size(), frames = sim.frame_index();
  std::vector<RuleRun>& rules = sim.rules();
  for (RuleRun& r : rules) r.visible_losses = visible_losses(r, judged, objects);
  const RuleRun& perceptual = sim.rule("perceptual");
  const double per_frame = 1.0 / double(frames), finest = sim.all_finest() * per_frame;
  const double n_judged = double(judged.size());
  auto fraction = [&](const RuleRun& r) { return n_judged > 0 ? r.visible_losses / n_judged : 0.0; };

  // A baseline tuned to a rate of visible losses: its cheapest sweep entry at or below that rate.
  struct Match { const RuleRun* run = nullptr; double ratio = 0; };
  auto tuned = [&](const std::string& name, const RuleRun& to) {
    Match m;
    for (const RuleRun& r : rules)
      if (r.sweep && r.name == name && r.visible_losses <= to.visible_losses && (!m.run || r.triangles < m.run->triangles)) m.run = &r;
    if (m.run) m.ratio = m.run->triangles / to.triangles;
    return m;
  };

  std::printf("\n%zu frames at %.0f Hz (%.1f s), two eyes, %zu objects; all in-view objects at their finest: %.0f triangles per frame\n\n",
              frames, o.fps, double(frames) / o.fps, objects, finest);
  std::printf("%-12s %16s %14s %14s %10s %14s %18s\n", "rule", "triangles/frame", "of all-finest", "of perceptual", "switches",
              "outside sacc.", judged.empty() ? "" : "visible losses");
  for (const RuleRun& r : rules) {
    if (r.sweep) continue;
    std::printf("%-12s %16.0f %13.1f%% %13.2fx %10llu %14llu", r.name.c_str(), r.triangles * per_frame, 100.0 * r.triangles / sim.all_finest(),
                r.triangles / perceptual.triangles,
                static_cast<unsigned long long>(r.switches), static_cast<unsigned long long>(r.switches_outside_saccades));
    if (!judged.empty()) std::printf(" %10.1f%% (%u/%zu)", 100.0 * fraction(r), r.visible_losses, judged.size());
    std::printf("\n");
  }
  nlohmann::json summary;
  summary["frames"] = frames;
  summary["objects"] = objects;
  summary["seed"] = o.seed;
  summary["all_finest_triangles_per_frame"] = finest;
  summary["judged_decisions"] = judged.size();
  for (const RuleRun& r : rules)
    if (!r.sweep)
      summary["rules"][r.name] = {{"triangles_per_frame", r.triangles * per_frame}, {"switches", r.switches},
                                  {"switches_outside_saccades", r.switches_outside_saccades}, {"visible_losses", r.visible_losses}};
  if (!judged.empty()) {
    std::printf("\nAt the perceptual rule's rate of visible losses (%.1f%% of %zu decisions judged by rendering both levels at the exact view):\n",
                100.0 * fraction(perceptual), judged.size());
    for (const char* name : {"screen-size", "distance"}) {
      const Match m = tuned(name, perceptual);
      const char* unit = std::string(name) == "screen-size" ? "pixel error" : "distance scale";
      if (m.run) {
        std::printf("  %-12s tuned to %s %.3g: %.0f triangles/frame (%.1f%% visible) = %.2fx the perceptual rule's\n", name, unit,
                    m.run->parameter, m.run->triangles * per_frame, 100.0 * fraction(*m.run), m.ratio);
        summary["tuned"][name] = {{"parameter", m.run->parameter}, {"triangles_per_frame", m.run->triangles * per_frame},
                                  {"visible_losses", m.run->visible_losses}, {"ratio_to_perceptual", m.ratio}};
      } else {
        std::printf("  %-12s no tuning in the sweep is that safe\n", name);
      }
    }
  }
  if (!judged.empty()) {
    std::printf("\nAlong the perceptual rule's quality q (invisible when lost contrast <= q x threshold):\n");
    std::printf("  %6s %16s %15s %30s\n", "q", "triangles/frame", "visible losses", "screen-size at that rate: ratio");
    for (const RuleRun& r : rules) {
      if (!r.sweep || r.name != "perceptual") continue;
      const Match m = tuned("screen-size", r);
      std::printf("  %6.3g %16.0f %14.1f%%", r.parameter, r.triangles * per_frame, 100.0 * fraction(r));
      if (m.run) std::printf(" %14.3g px: %.2fx\n", m.run->parameter, m.ratio);
      else std::printf(" %30s\n", "none as safe in the sweep");
      summary["quality_sweep"].push_back({{"quality", r.parameter}, {"triangles_per_frame", r.triangles * per_frame},
                                         {"visible_losses", r.visible_losses},
                                         {"screen_size_ratio", m.run ? m.ratio : 0.0}});
    }
  }
  if (o.output.empty()) return {};

  fs::create_directories(o.output);
  std::vector<std::string> written;
  const fs::path out(o.output);
  std::ostringstream f;
  f << "frame,seconds,saccade,gaze_confidence,phase,target,all_finest";
  for (const RuleRun& r : rules)
    if (!r.sweep) f << "," << r.name;
  f << "\n";
  const GeneratedGaze& gen = sim.generated();
  for (std::size_t i = 0; i < frames; ++i) {
    f << i << "," << double(i) / o.fps << "," << sim.saccade(i) << "," << sim.gaze()[i].confidence << ","
      << (gen.phases.empty() ? "recorded" : to_string(gen.phases[i])) << "," << (gen.targets.empty() ? -1 : gen.targets[i]) << "," << sim.finest(i);
    for (const RuleRun& r : rules)
      if (!r.sweep) f << "," << r.drawn[i];
    f << "\n";
  }
  save((out / "frames.csv").string(), f.str(), &written);

  std::ostringstream l;
  l << "frame,object,name,in_view";
  for (const RuleRun& r : rules)
    if (!r.sweep) l << "," << r.name;
  l << "\n";
  for (std::size_t i = 0; i < frames; ++i)
    for (std::uint32_t k = 0; k < objects; ++k) {
      l << i << "," << k << "," << scene.instances[k].name << "," << sim.in_view(k, i);
      for (const RuleRun& r : rules)
        if (!r.sweep) l << "," << int(r.levels[i * objects + k]);
      l << "\n";
    }
  save((out / "levels.csv").string(), l.str(), &written);

  std::ostringstream s;
  s << "rule,parameter,sweep,triangles_per_frame,visible_losses,judged\n";
  for (const RuleRun& r : rules)
    s << r.name << "," << r.parameter << "," << r.sweep << "," << r.triangles * per_frame << "," << r.visible_losses << "," << judged.size() << "\n";
  save((out / "sweep.csv").string(), s.str(), &written);

  if (!judged.empty()) {
    std::ostringstream j;
    j << "frame,object,pixels";
    for (std::uint32_t k = 0; k < kMaxLevels; ++k) j << ",score" << k;
    for (const RuleRun& r : rules)
      if (!r.sweep) j << "," << r.name;
    j << "\n";
    for (const Judged& d : judged) {
      j << d.frame << "," << d.object << "," << d.pixels;
      for (float v : d.scores) j << "," << v;
      for (const RuleRun& r : rules)
        if (!r.sweep) j << "," << int(r.levels[std::size_t(d.frame) * objects + d.object]);
      j << "\n";
    }
    save((out / "judged.csv").string(), j.str(), &written);
  }

  // The tracks, in the formats --head and --gaze read back.
  std::ostringstream h, g;
  h.precision(17);
  g.precision(17);
  h << "t,x,y,z,qx,qy,qz,qw\n";
  g << "t,x,y,z,confidence\n";
  for (std::size_t i = 0; i < frames; ++i) {
    const HeadPose& p = sim.head()[i];
    const GazeSample& z = sim.gaze()[i];
    const double t = double(i) / o.fps;
    h << t << "," << p.position.x << "," << p.position.y << "," << p.position.z << "," << p.orientation.x << "," << p.orientation.y
      << "," << p.orientation.z << "," << p.orientation.w << "\n";
    g << t << "," << z.direction.x << "," << z.direction.y << "," << z.direction.z << "," << z.confidence << "\n";
  }
  save((out / "head.csv").string(), h.str(), &written);
  save((out / "gaze.csv").string(), g.str(), &written);
  save((out / "summary.json").string(), summary.dump(2) + "\n", &written);

  // Frames: the perceptual rule beside the screen-size rule tuned to the same visible losses (or at 1 px).
  const Match ss = tuned("screen-size", perceptual);
  const RuleRun& right = ss.run ? *ss.run : sim.rule("screen-size");
  for (std::uint32_t k = 0; k < o.images && frames > 0; ++k) {
    const std::size_t i = frames * (2 * k + 1) / (2 * o.images);
    RgbImage im;
    im.height = 480;
    im.width = 2 * im.height + 8;
    im.pixels.assign(std::size_t(im.width) * std::size_t(im.height) * 3, 255);
    draw_levels(sim, i, &perceptual.levels[i * objects], &im, 0);
    draw_levels(sim, i, &right.levels[i * objects], &im, im.height + 8);
    char name[64];
    std::snprintf(name, sizeof name, "frame_%04zu.png", i);
    write_png((out / name).string(), im);
    written.push_back((out / name).string());
  }

  if (o.plots) {
    const std::string script = plot_script();
    const std::string python = "/usr/bin/python3";
    if (script.empty() || !fs::exists(python)) {
      std::printf("\nplots skipped: %s not found\n", script.empty() ? "plot_simulation.py" : python.c_str());
    } else {
      if (run_program(python, {script, o.output}) == 0) {
        for (const char* p : {"triangles.png", "sweep.png"}) written.push_back((out / p).string());
      } else {
        std::printf("\nplots skipped: %s %s '%s' failed (is python3-matplotlib installed?)\n", python.c_str(), script.c_str(),
                    o.output.c_str());
      }
    }
  }
  std::printf("\nwritten to %s:\n", o.output.c_str());
  for (const std::string& p : written) std::printf("  %s\n", p.c_str());
  std::printf("(frames: perceptual left, %s right; level 0 blue, 1 cyan, 2 green, 3 yellow, 4 orange; ring = gaze)\n",
              ss.run ? "screen-size tuned to the same visible losses" : "screen-size at 1 px");
  return written;
}

}  // namespace acuity::tools

namespace acuity::tools {

RunResult run_simulation(const SceneAssets& scene, const SimulationOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  Simulation sim(scene, options);
  sim.run();
  const auto t1 = std::chrono::steady_clock::now();
  std::vector<Judged> judged;
  if (options.validate > 0) judged = judge_decisions(sim, options.validate, options.seed);
  const auto t2 = std::chrono::steady_clock::now();
  std::printf("\nsimulated %zu frames x %zu rule settings in %.1f s; judged %zu decisions by render-and-analyze in %.1f s\n",
              sim.frame_count(), sim.rules().size(), std::chrono::duration<double>(t1 - t0).count(), judged.size(),
              std::chrono::duration<double>(t2 - t1).count());
  RunResult result;
  result.written = report(sim, judged);
  if (sim.frame_count() > 0) {
    const std::size_t f = result.example_frame = sim.frame_count() / 2;
    const std::vector<std::int32_t>& targets = sim.generated().targets;
    if (!targets.empty() && targets[f] >= 0) result.example_object = targets[f];
    for (std::uint32_t i = 0; i < scene.instances.size() && result.example_object < 0; ++i)
      if (sim.in_view(i, f)) result.example_object = i;
  }
  return result;
}

}  // namespace acuity::tools
