// write_outputs(): the files a simulation run leaves (acuity/sim/results.hpp).
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "acuity/file.hpp"
#include "acuity/sim/frame_image.hpp"
#include "acuity/sim/results.hpp"

namespace acuity::sim {
namespace {

namespace fs = std::filesystem;

void save(const std::string& path, const std::string& text, std::vector<std::string>* written) {
  io::write_file_atomically(path, text);
  written->push_back(path);
}

// Per frame: time, saccade, gaze, the generator's phase and target, triangles of each main rule.
std::string frames_csv(const Simulation& sim, const Results& r) {
  std::ostringstream f;
  f << "frame,seconds,saccade,gaze_confidence,phase,target,all_finest";
  for (const RuleRun& run : sim.rules())
    if (!run.sweep) f << "," << run.name;
  f << "\n";
  const GeneratedGaze& gen = sim.generated();
  for (std::size_t i = 0; i < r.frames; ++i) {
    f << i << "," << double(i) / sim.options().fps << "," << sim.saccade(i) << "," << sim.gaze()[i].confidence
      << "," << (gen.phases.empty() ? "recorded" : to_string(gen.phases[i])) << ","
      << (gen.targets.empty() ? -1 : gen.targets[i]) << "," << sim.finest(i);
    for (const RuleRun& run : sim.rules())
      if (!run.sweep) f << "," << run.drawn[i];
    f << "\n";
  }
  return f.str();
}

// Per frame and object: in view, the level of each main rule.
std::string levels_csv(const Simulation& sim, const Results& r) {
  std::ostringstream l;
  l << "frame,object,name,in_view";
  for (const RuleRun& run : sim.rules())
    if (!run.sweep) l << "," << run.name;
  l << "\n";
  for (std::size_t i = 0; i < r.frames; ++i)
    for (std::uint32_t k = 0; k < r.objects; ++k) {
      l << i << "," << k << "," << sim.scene().instances[k].name << "," << sim.in_view(k, i);
      for (const RuleRun& run : sim.rules())
        if (!run.sweep) l << "," << int(run.levels[i * r.objects + k]);
      l << "\n";
    }
  return l.str();
}

// Per rule setting: its triangles and visible losses.
std::string sweep_csv(const Simulation& sim, const Results& r) {
  std::ostringstream s;
  s << "rule,parameter,sweep,triangles_per_frame,visible_losses,judged\n";
  const std::vector<RuleRun>& rules = sim.rules();
  for (std::size_t i = 0; i < rules.size(); ++i)
    s << rules[i].name << "," << rules[i].parameter << "," << rules[i].sweep << ","
      << rules[i].triangles * (1.0 / double(r.frames)) << "," << r.visible_losses[i] << "," << r.judged
      << "\n";
  return s.str();
}

// Per judged decision: every level's score and each main rule's level.
std::string judged_csv(const Simulation& sim, const Results& r, const std::vector<Judged>& judged) {
  std::ostringstream j;
  j << "frame,object,pixels";
  for (std::uint32_t k = 0; k < kMaxLevels; ++k) j << ",score" << k;
  for (const RuleRun& run : sim.rules())
    if (!run.sweep) j << "," << run.name;
  j << "\n";
  for (const Judged& d : judged) {
    j << d.frame << "," << d.object << "," << d.pixels;
    for (float v : d.scores) j << "," << v;
    for (const RuleRun& run : sim.rules())
      if (!run.sweep) j << "," << int(run.levels[std::size_t(d.frame) * r.objects + d.object]);
    j << "\n";
  }
  return j.str();
}

// The results as JSON: the main rules, the tuned baselines and the quality sweep (when judged).
std::string summary_json(const Simulation& sim, const Results& r) {
  const std::vector<RuleRun>& rules = sim.rules();
  const double per_frame = 1.0 / double(r.frames);
  nlohmann::json summary;
  summary["frames"] = r.frames;
  summary["objects"] = r.objects;
  summary["seed"] = sim.options().seed;
  summary["model"] = to_string(sim.options().model);  // the perceptual rule's
  summary["evaluation"] = to_string(sim.options().evaluation);
  summary["all_finest_triangles_per_frame"] = r.all_finest;
  summary["judged_decisions"] = r.judged;
  for (std::size_t i = 0; i < rules.size(); ++i)
    if (!rules[i].sweep)
      summary["rules"][rules[i].name] = {{"triangles_per_frame", rules[i].triangles * per_frame},
                                         {"switches", rules[i].switches},
                                         {"switches_outside_saccades", rules[i].switches_outside_saccades},
                                         {"visible_losses", r.visible_losses[i]}};
  if (r.judged == 0) return summary.dump(2) + "\n";
  auto match = [&](const Match& m) {
    const char* kinds[] = {"none", "interpolated", "at_least", "at_most"};
    return nlohmann::json{{"kind", kinds[int(m.kind)]},
                          {"parameter", m.parameter},
                          {"triangles_per_frame", m.triangles},
                          {"ratio", m.ratio}};
  };
  summary["equal_loss"]["screen-size"] = match(r.screen_size);
  summary["equal_loss"]["distance"] = match(r.distance);
  for (const char* name : {"perceptual", "screen-size", "distance"})
    summary["one_percent"][name] = match(name[0] == 'p'   ? r.one_percent_perceptual
                                         : name[0] == 's' ? r.one_percent_screen_size
                                                          : r.one_percent_distance);
  summary["oracle"] = {{"ratio", r.oracle.ratio()},
                       {"same", r.oracle.same},
                       {"finer", r.oracle.finer},
                       {"coarser", r.oracle.coarser}};
  summary["oracle_ungated"] = {{"ratio", r.ungated.ratio()},
                               {"same", r.ungated.same},
                               {"finer", r.ungated.finer},
                               {"coarser", r.ungated.coarser}};
  summary["one_percent_bound"] = {{"losses_allowed", r.one_percent_losses},
                                  {"least_triangles", r.least_at_one_percent},
                                  {"screen_size_triangles", r.screen_size_judged_at_one_percent}};
  for (const Results::QualityPoint& q : r.quality_sweep) {
    const RuleRun& run = rules[std::size_t(q.rule)];
    summary["quality_sweep"].push_back({{"quality", run.parameter},
                                        {"triangles_per_frame", run.triangles * per_frame},
                                        {"visible_losses", r.visible_losses[std::size_t(q.rule)]},
                                        {"oracle_ratio", q.oracle.ratio()},
                                        {"screen_size", match(q.screen_size)}});
  }
  const Results::Group& g = r.third_party;
  summary["third_party"] = {{"objects", g.objects},
                            {"judged_decisions", g.judged},
                            {"all_finest_triangles_per_frame", g.all_finest},
                            {"oracle",
                             {{"ratio", g.oracle.ratio()},
                              {"same", g.oracle.same},
                              {"finer", g.oracle.finer},
                              {"coarser", g.oracle.coarser}}}};
  for (std::size_t i = 0; i < rules.size(); ++i)
    if (!rules[i].sweep)
      summary["third_party"]["rules"][rules[i].name] = {{"triangles_per_frame", g.triangles[i]},
                                                        {"visible_losses", g.visible_losses[i]}};
  return summary.dump(2) + "\n";
}

}  // namespace

std::vector<std::string> write_outputs(const Simulation& sim, const Results& r,
                                       const std::vector<Judged>& judged, const std::string& dir) {
  fs::create_directories(dir);
  std::vector<std::string> written;
  const fs::path out(dir);
  save((out / "frames.csv").string(), frames_csv(sim, r), &written);
  save((out / "levels.csv").string(), levels_csv(sim, r), &written);
  save((out / "sweep.csv").string(), sweep_csv(sim, r), &written);
  if (!judged.empty()) save((out / "judged.csv").string(), judged_csv(sim, r, judged), &written);
  save((out / "head.csv").string(), head_path_csv(sim.head(), sim.options().fps, r.frames), &written);
  save((out / "gaze.csv").string(), gaze_trace_csv(sim.gaze(), sim.options().fps, r.frames), &written);
  save((out / "summary.json").string(), summary_json(sim, r), &written);

  // Frames: the perceptual rule beside the screen-size rule tuned to the same visible losses (or at 1 px).
  const RuleRun& left = sim.rules()[std::size_t(r.perceptual)];
  const RuleRun& right =
      r.screen_size.rule >= 0 ? sim.rules()[std::size_t(r.screen_size.rule)] : sim.rule("screen-size");
  const std::uint32_t images = sim.options().images;
  for (std::uint32_t k = 0; k < images && r.frames > 0; ++k) {
    const std::size_t i = r.frames * (2 * k + 1) / (2 * images);
    RgbImage im;
    im.height = 480;
    im.width = 2 * im.height + 8;
    im.pixels.assign(std::size_t(im.width) * std::size_t(im.height) * 3, 255);
    draw_levels(sim, i, &left.levels[i * r.objects], &im, 0);
    draw_levels(sim, i, &right.levels[i * r.objects], &im, im.height + 8);
    char name[64];
    std::snprintf(name, sizeof name, "frame_%04zu.png", i);
    write_png((out / name).string(), im);
    written.push_back((out / name).string());
  }
  return written;
}

}  // namespace acuity::sim

namespace acuity::sim {

std::string shell_quoted(const std::string& path) {
  if (!path.empty() &&
      path.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_./+-") ==
          std::string::npos)
    return path;
  std::string out = "'";
  for (char c : path) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string outputs_text(const Results& results, const std::vector<std::string>& written,
                         const std::string& dir, const std::string& plot_script) {
  std::string out = "\nwritten to " + dir + ":\n";
  for (const std::string& p : written) out += "  " + p + "\n";
  out += std::string("(frames: perceptual left, ") +
         (results.screen_size.rule >= 0 ? "screen-size tuned to the same visible losses"
                                        : "screen-size at 1 px") +
         " right; level 0 blue, 1 cyan, 2 green, 3 yellow, 4 orange; ring = gaze)\n";
  if (!plot_script.empty())
    out += "plots (triangles.png, sweep.png; needs python3-matplotlib):\n  python3 " +
           shell_quoted(plot_script) + " " + shell_quoted(dir) + "\n";
  return out;
}

}  // namespace acuity::sim
