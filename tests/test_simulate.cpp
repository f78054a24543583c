// acuity simulate / explain: the table reader and its errors, the resampled tracks, the gaze
// generator against the main sequence and its own phases, scene instancing through glTF, the
// ground truth, the frame pictures, and that a fixed seed reproduces every output byte.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "acuity/bake/scene.hpp"
#include "acuity/file.hpp"
#include "acuity/lodgen/gltf.hpp"
#include "acuity/sim/frame_image.hpp"
#include "acuity/sim/results.hpp"
#include "acuity/sim/sampled.hpp"
#include "acuity/transform.hpp"
#include "mesh_fixture.hpp"

namespace fs = std::filesystem;
using namespace acuity;
using namespace acuity::sim;
using namespace acuity::bake;  // the scene bake (load_scene_assets)

namespace {

constexpr double kPi = 3.14159265358979323846;

fs::path scratch(const std::string& name) {
  const fs::path p =
      fs::temp_directory_path() / ("acuity_test_simulate_" + std::to_string(::getpid())) / name;
  fs::create_directories(p.parent_path());
  return p;
}

// Removes the scratch directory after the last test.
struct ScratchCleanup : ::testing::Environment {
  void TearDown() override { fs::remove_all(scratch("x").parent_path()); }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) { return e.what(); }
  return "no error";
}

lodgen::Mesh sphere_mesh(int subdivisions) {
  const acuity::testing::TestMesh t = acuity::testing::icosphere(subdivisions, 1.0f);
  lodgen::Mesh m;
  m.positions = t.positions;
  m.normals = t.normals;
  m.indices = t.indices;
  return m;
}

// A 3 x 3 field of sphere chains (icospheres 3, 2, 1 subdivisions) 4 m apart, radius 0.5 m, written
// once as an instanced glTF; profiles at 64 px cached beside it.
const SceneAssets& small_scene() {
  static std::unique_ptr<SceneAssets> scene = [] {
    lodgen::LodObject obj;
    obj.name = "ball";
    const double errors[] = {0, 0.004, 0.02};
    for (int s : {3, 2, 1}) obj.chain.levels.push_back({sphere_mesh(s), 0, errors[3 - s], 0});
    std::vector<lodgen::LodInstance> field;
    for (int i = 0; i < 9; ++i) {
      lodgen::LodInstance in;
      in.name = "ball_" + std::to_string(i);
      in.matrix = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, (i % 3 - 1) * 4.0, 0.5, -(3.0 + (i / 3) * 4.0),
                   1};
      field.push_back(in);
    }
    const fs::path path = scratch("field.glb");
    lodgen::write_lod_gltf(path.string(), {obj}, {}, {}, field);
    AssetOptions o;
    o.profiles = scratch("profiles").string();
    o.profile_pixels = 64;
    o.quiet = true;
    return load_scene_assets(path.string(), o);
  }();
  return *scene;
}

// small_scene()'s assets profiled without cell bounds (each view's own measurement).
const SceneAssets& small_scene_own_views() {
  static std::unique_ptr<SceneAssets> scene = [] {
    small_scene();  // writes the field
    AssetOptions o;
    o.profiles = scratch("profiles-own-views").string();
    o.profile_pixels = 64;
    o.bound_cells = false;
    o.quiet = true;
    return load_scene_assets(scratch("field.glb").string(), o);
  }();
  return *scene;
}

// The sanitizer run (ACUITY_QUICK_TESTS) judges fewer decisions: the judge's rendering is most of
// these tests' time there, and the same code runs either way.
bool quick() { return std::getenv("ACUITY_QUICK_TESTS") != nullptr; }
std::uint32_t judged_count() { return quick() ? 8 : 20; }

SimulationOptions small_options(const std::string& output) {
  SimulationOptions o;
  o.seconds = 3;
  o.movers = 2;
  o.validate = quick() ? 4 : 12;  // the sanitizer run judges fewer
  o.images = 1;
  o.output = output.empty() ? std::string() : scratch(output).string();
  return o;
}

}  // namespace

// A cached profile is reused only when measured with the snapshots asked for: small_scene()'s
// 64-pixel profiles, asked for at 32 pixels, are measured again (and written over the cache), then
// read back from it at 32.
TEST(SceneAssets, CachedProfilesAreMeasuredAgainAtOtherSnapshotPixels) {
  const SceneAssets& at64 = small_scene();
  const fs::path cache = scratch("profiles-32");
  fs::create_directories(cache);
  for (const auto& f : fs::directory_iterator(scratch("profiles")))
    fs::copy_file(f.path(), cache / f.path().filename());
  AssetOptions o;
  o.profiles = cache.string();
  o.profile_pixels = 32;
  o.quiet = true;
  const std::unique_ptr<SceneAssets> at32 = load_scene_assets(scratch("field.glb").string(), o);
  const std::unique_ptr<SceneAssets> again = load_scene_assets(scratch("field.glb").string(), o);
  ASSERT_EQ(at32->assets.size(), at64.assets.size());
  ASSERT_EQ(again->assets.size(), at64.assets.size());
  for (std::size_t i = 0; i < at64.assets.size(); ++i) {
    EXPECT_EQ(at64.assets[i].profile.meta.snapshot_pixels, 64u);
    EXPECT_EQ(at32->assets[i].profile.meta.snapshot_pixels, 32u) << at32->assets[i].name;
    EXPECT_EQ(io::read_file((cache / (at32->assets[i].name + ".acuity")).string()).size,
              at32->assets[i].blob.size);
    EXPECT_EQ(again->assets[i].blob.size, at32->assets[i].blob.size);
    EXPECT_EQ(
        std::memcmp(again->assets[i].blob.data(), at32->assets[i].blob.data(), at32->assets[i].blob.size), 0);
  }
}

TEST(Table, ReadsCsvAndJsonByColumnName) {
  write(scratch("t.csv"), "# comment\nt, x ,y\n0,1,2\n0.5,-3e-1,4\n");
  const Table c = read_table(scratch("t.csv").string());
  ASSERT_EQ(c.columns.size(), 3u);
  EXPECT_EQ(c.column("x", true), 1);
  EXPECT_EQ(c.column("confidence", false), -1);
  EXPECT_DOUBLE_EQ(c.rows[1][1], -0.3);
  write(scratch("t.json"), R"([{"t": 0, "x": 1}, {"t": 1, "x": 2.5}])");
  const Table j = read_table(scratch("t.json").string());
  EXPECT_DOUBLE_EQ(j.rows[1][std::size_t(j.column("x", true))], 2.5);
}

TEST(Table, BadInputNamesFileLineAndColumn) {
  const std::string p = scratch("bad.csv").string();
  write(p, "t,x\n0,1\n1,abc\n");
  EXPECT_NE(error_of([&] { read_table(p); }).find("bad.csv:3: column 'x': 'abc'"), std::string::npos)
      << error_of([&] { read_table(p); });
  write(p, "t,x\n0,1,2\n");
  EXPECT_NE(error_of([&] { read_table(p); }).find("bad.csv:2: 3 fields, the header has 2"),
            std::string::npos);
  write(p, "t,x\n0,nan\n");
  EXPECT_NE(error_of([&] { read_table(p); }).find("not a finite number"), std::string::npos);
  write(p, "");
  EXPECT_NE(error_of([&] { read_table(p); }).find("no header"), std::string::npos);
  const std::string j = scratch("bad.json").string();
  write(j, R"({"t": 0})");
  EXPECT_NE(error_of([&] { read_table(j); }).find("expected an array"), std::string::npos);
  write(j, R"([{"t": 0, "x": 1}, {"t": 1, "y": 1}])");
  EXPECT_NE(error_of([&] { read_table(j); }).find("row 1: has no 'x'"), std::string::npos);
  write(j, R"([{"t": 0, "x": "1"}])");
  EXPECT_NE(error_of([&] { read_table(j); }).find("row 0: 'x' is not a finite number"), std::string::npos);
  write(j, "[{\"t\": 0,");
  EXPECT_NE(error_of([&] { read_table(j); }).find("not valid JSON"), std::string::npos);
  EXPECT_NE(error_of([&] { read_table(scratch("missing.csv").string()); }).find("missing.csv: No such file"),
            std::string::npos);
  // Tracks: missing columns, time not increasing, zero quaternion.
  write(p, "t,x,y,z\n0,0,0,-1\n");
  EXPECT_NE(error_of([&] { head_path_from(read_table(p), 60, 10); }).find("no column 'qx'"),
            std::string::npos);
  write(p, "t,x,y,z\n0,0,0,-1\n0,0,0,-1\n");
  EXPECT_NE(error_of([&] { gaze_trace_from(read_table(p), 60, 10); }).find("does not increase"),
            std::string::npos);
  write(p, "t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,0\n");
  EXPECT_NE(error_of([&] { head_path_from(read_table(p), 60, 10); }).find("quaternion is zero"),
            std::string::npos);
}

TEST(Tracks, ResampleLinearlyAndHoldBlinks) {
  const std::string p = scratch("head.csv").string();
  const double s = std::sin(kPi / 4), c = std::cos(kPi / 4);  // 0 -> 90 deg about +y over 1 s
  write(p, "t,x,y,z,qx,qy,qz,qw\n0,0,1.6,0,0,0,0,1\n1,2,1.6,0,0," + std::to_string(s) + ",0," +
               std::to_string(c) + "\n");
  const std::vector<HeadPose> head = head_path_from(read_table(p), 4, 6);
  ASSERT_EQ(head.size(), 6u);
  EXPECT_NEAR(head[2].position.x, 1.0, 1e-12);  // t = 0.5 s: halfway
  const glm::dvec3 fwd = head[2].orientation * glm::dvec3(0, 0, -1);
  EXPECT_NEAR(std::atan2(-fwd.x, -fwd.z), kPi / 4, 1e-6);  // slerp: 45 deg
  EXPECT_NEAR(head[5].position.x, 2.0, 1e-12);             // held past the end
  const std::string g = scratch("gaze.csv").string();
  write(g, "t,x,y,z,confidence\n0,0,0,-1,1\n0.5,0,0,-2,0\n1,1,0,-1,1\n1.5,0,0,0,1\n");
  const std::vector<GazeSample> gaze = gaze_trace_from(read_table(g), 4, 7);
  EXPECT_FLOAT_EQ(gaze[0].confidence, 1.0f);
  EXPECT_FLOAT_EQ(gaze[1].confidence, 0.0f);  // between a tracked and a lost sample: lost
  EXPECT_FLOAT_EQ(gaze[3].confidence, 0.0f);
  EXPECT_NEAR(glm::length(gaze[3].direction), 1.0, 1e-12);
  EXPECT_FLOAT_EQ(gaze[6].confidence, 0.0f);  // a zero direction is no gaze
}

TEST(GazeGenerator, FollowsMainSequencePursuesAndBlinks) {
  const SceneAssets& scene = small_scene();
  const double fps = 1000;  // fine sampling to time the phases
  const std::vector<HeadPose> head = flythrough(scene, 12, fps);
  const std::vector<Mover> movers = choose_movers(scene, 3, 4);
  const GeneratedGaze g = generate_gaze(scene, head, movers, fps, 4);
  ASSERT_EQ(g.samples.size(), head.size());
  int saccades = 0, blinks = 0, pursuit_frames = 0;
  for (std::size_t f = 0; f < g.phases.size();) {
    std::size_t e = f;
    while (e < g.phases.size() && g.phases[e] == g.phases[f]) ++e;
    const double ms = double(e - f) * 1000 / fps;
    if (g.phases[f] == GazePhase::Saccade && f > 0 && e < g.phases.size()) {
      const double amplitude =
          std::acos(std::clamp(glm::dot(g.samples[f - 1].direction, g.samples[e].direction), -1.0, 1.0)) *
          180 / kPi;
      EXPECT_NEAR(ms, 21 + 2.2 * amplitude, 3.0)
          << "saccade of " << amplitude << " deg";  // head motion moves the ends slightly
      ++saccades;
    }
    if (g.phases[f] == GazePhase::Blink && e < g.phases.size()) {
      EXPECT_NEAR(ms, 150, 2);
      for (std::size_t i = f; i < e; ++i) EXPECT_EQ(g.samples[i].confidence, 0.0f);
      ++blinks;
    }
    if (g.phases[f] == GazePhase::Fixation && e < g.phases.size() &&
        (f == 0 || g.phases[f - 1] == GazePhase::Saccade) && g.phases[e] == GazePhase::Saccade) {
      EXPECT_TRUE(ms >= 199 && ms <= 451) << ms;
    }
    f = e;
  }
  for (std::size_t f = 0; f < g.phases.size(); ++f) {
    if (g.phases[f] != GazePhase::Pursuit) continue;
    ++pursuit_frames;  // the gaze stays on the moving object: within its angular radius
    const auto it = std::find_if(movers.begin(), movers.end(),
                                 [&](const Mover& m) { return int(m.instance) == g.targets[f]; });
    ASSERT_NE(it, movers.end());
    const glm::dvec3 h =
        glm::inverse(head[f].orientation) * (it->position(double(f) / fps) - head[f].position);
    const double angle =
        std::acos(std::clamp(glm::dot(glm::normalize(h), g.samples[f].direction), -1.0, 1.0));
    EXPECT_LE(angle, std::asin(std::min(1.0, scene.instances[it->instance].radius / glm::length(h))));
  }
  EXPECT_GT(saccades, 10);
  EXPECT_GE(blinks, 1);
  EXPECT_GT(pursuit_frames, 0);
}

TEST(Scene, InstancesShareMeshesAndKeepTheirPlacement) {
  const SceneAssets& scene = small_scene();
  ASSERT_EQ(scene.assets.size(), 1u);
  ASSERT_EQ(scene.instances.size(), 9u);
  EXPECT_EQ(scene.scene.meshes.size(), 3u);  // one chain, shared by nine instances
  EXPECT_EQ(scene.assets[0].chain.levels.size(), 3u);
  EXPECT_NEAR(scene.assets[0].chain.levels[2].hausdorff, 0.02, 1e-4);  // through MSFT_screencoverage
  EXPECT_EQ(scene.instances[4].name, "ball_4");
  EXPECT_DOUBLE_EQ(scene.instances[4].transform.position[2], -7.0);
  EXPECT_FLOAT_EQ(scene.instances[4].transform.scale, 0.5f);
  EXPECT_NEAR(scene.instances[4].radius, 0.5, 1e-6);
  // A rotated, scaled and mirrored matrix decomposes to a unit quaternion and the largest scale.
  const double c = std::cos(0.3), s = std::sin(0.3);
  const ObjectTransform t = acuity::transform_from_matrix(
      std::array<double, 16>{2 * c, 0, -2 * s, 0, 0, 3, 0, 0, 2 * s, 0, 2 * c, 0, 1, 2, 3, 1}.data());
  EXPECT_FLOAT_EQ(t.scale, 3.0f);
  EXPECT_NEAR(t.rotation[1], std::sin(0.15), 1e-6);
  EXPECT_NEAR(t.rotation[3], std::cos(0.15), 1e-6);
}

// A run as `acuity simulate` makes it: every frame, the judged decisions, the results, the files.
void run_simulation(const SceneAssets& scene, const SimulationOptions& o) {
  Simulation sim(scene, o);
  sim.run();
  std::vector<Judged> judged;
  if (o.validate > 0) judged = judge_decisions(sim, o.validate, o.seed);
  write_outputs(sim, analyse(sim, judged), judged, o.output);
}

TEST(Simulate, FixedSeedReproducesEveryOutputByte) {
  const SceneAssets& scene = small_scene();
  run_simulation(scene, small_options("run_a"));
  run_simulation(scene, small_options("run_b"));
  SimulationOptions other = small_options("run_c");
  other.seed = 2;
  run_simulation(scene, other);
  for (const char* f : {"frames.csv", "levels.csv", "sweep.csv", "judged.csv", "gaze.csv", "head.csv",
                        "summary.json", "frame_0090.png"}) {
    const std::string a = slurp(scratch("run_a") / f);
    ASSERT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, slurp(scratch("run_b") / f)) << f;
  }
  EXPECT_NE(slurp(scratch("run_a") / "gaze.csv"), slurp(scratch("run_c") / "gaze.csv"));
  // Outputs are ordinary readable files (written through a private temporary).
  EXPECT_EQ(fs::status(scratch("run_a") / "frame_0090.png").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read | fs::perms::others_read);
  // The written tracks read back as --head and --gaze give the same levels.
  SimulationOptions replay = small_options("run_d");
  replay.head_file = (scratch("run_a") / "head.csv").string();
  replay.gaze_file = (scratch("run_a") / "gaze.csv").string();
  run_simulation(scene, replay);
  EXPECT_EQ(slurp(scratch("run_a") / "levels.csv"), slurp(scratch("run_d") / "levels.csv"));
}

TEST(Simulate, RulesAndGroundTruthAgreeWhereTheyMust) {
  const SceneAssets& scene = small_scene();
  Simulation sim(scene, small_options(""));
  sim.run();
  const std::vector<Judged> judged = judge_decisions(sim, judged_count(), 1);
  ASSERT_EQ(judged.size(), judged_count());
  for (const Judged& j : judged) {
    EXPECT_TRUE(sim.in_view(j.object, j.frame));
    EXPECT_EQ(j.scores[0], 0.0f);                        // the finest level loses nothing
    EXPECT_LE(j.scores[1], j.scores[2] * 1.5f + 0.05f);  // coarser loses more (up to view noise)
    EXPECT_TRUE(j.pixels >= 64 && j.pixels <= 512);
  }
  // Every frame: the screen-size sweep is monotone in its pixel error (a looser tolerance never finer).
  const RuleRun* previous = nullptr;
  for (const RuleRun& r : sim.rules()) {
    if (!r.sweep || r.name != "screen-size") continue;
    if (previous) { EXPECT_GE(previous->triangles, r.triangles); }
    previous = &r;
  }
  // explain: the chosen level is invisible by its own score, and the text names it.
  for (std::uint32_t i = 0; i < scene.instances.size(); ++i) {
    const std::string text = explain_text(sim, i);
    const int level = sim.rule("perceptual").scheduler->level(i);
    EXPECT_NE(text.find("chosen: level " + std::to_string(level)), std::string::npos) << text;
    ObjectExplain e{};
    ASSERT_TRUE(sim.rule("perceptual").scheduler->explain(i, &e));
    EXPECT_LE(e.levels[level].score, 1.0f) << text;
  }
}

TEST(Simulate, AnalyseCountsLossesAndTunesBaselinesAsDefined) {
  const SceneAssets& scene = small_scene();
  Simulation sim(scene, small_options(""));
  sim.run();
  const std::vector<Judged> judged = judge_decisions(sim, judged_count(), 1);
  const std::vector<RuleRun>& rules = sim.rules();
  const std::size_t objects = scene.instances.size();
  const Results r = analyse(sim, judged);
  EXPECT_EQ(r.frames, sim.frame_count());
  EXPECT_EQ(r.judged, judged.size());
  ASSERT_EQ(r.visible_losses.size(), rules.size());
  EXPECT_EQ(&rules[std::size_t(r.perceptual)], &sim.rule("perceptual"));
  // Losses, counted here decision by decision: the level a rule chose scores above 1.
  for (std::size_t i = 0; i < rules.size(); ++i) {
    std::uint32_t losses = 0;
    for (const Judged& j : judged)
      if (j.scores[rules[i].levels[std::size_t(j.frame) * objects + j.object]] > 1.0f) ++losses;
    EXPECT_EQ(r.visible_losses[i], losses) << rules[i].name << " " << rules[i].parameter;
  }
  // The baselines at a rate: the entry they start from is at most as lossy and none as safe is
  // cheaper; the interpolated triangles lie between it and the riskier entry; ratio over the rule's.
  const double frames = double(r.frames);
  auto check = [&](const Match& m, const std::string& name, std::size_t to) {
    for (std::size_t i = 0; i < rules.size(); ++i) {
      if (!rules[i].sweep || rules[i].name != name || r.visible_losses[i] > r.visible_losses[to]) continue;
      ASSERT_GE(m.rule, 0) << name;
      EXPECT_LE(rules[std::size_t(m.rule)].triangles, rules[i].triangles) << name;
    }
    if (m.rule < 0) {
      EXPECT_EQ(m.kind, Match::Kind::AtLeast);
      ASSERT_GE(m.riskier, 0);
      EXPECT_GT(r.visible_losses[std::size_t(m.riskier)], r.visible_losses[to]);
      return;
    }
    EXPECT_TRUE(rules[std::size_t(m.rule)].sweep && rules[std::size_t(m.rule)].name == name);
    EXPECT_LE(r.visible_losses[std::size_t(m.rule)], r.visible_losses[to]);
    EXPECT_LE(m.triangles, rules[std::size_t(m.rule)].triangles / frames * (1 + 1e-12));
    if (m.riskier >= 0) {
      EXPECT_GT(r.visible_losses[std::size_t(m.riskier)], r.visible_losses[to]);
      EXPECT_GE(m.triangles, rules[std::size_t(m.riskier)].triangles / frames * (1 - 1e-12));
    }
    EXPECT_DOUBLE_EQ(m.ratio, m.triangles / (rules[to].triangles / frames));
  };
  check(r.screen_size, "screen-size", std::size_t(r.perceptual));
  check(r.distance, "distance", std::size_t(r.perceptual));
  ASSERT_EQ(r.quality_sweep.size(), 9u);  // q = 2^(i/4), i = -6..2
  for (const Results::QualityPoint& q : r.quality_sweep)
    check(q.screen_size, "screen-size", std::size_t(q.rule));
  // The oracle, recounted here: per decision the coarsest level scoring at most 1.
  double chosen = 0, best = 0;
  std::uint32_t same = 0;
  for (const Judged& j : judged) {
    const Profile& p = scene.assets[std::size_t(scene.instances[j.object].asset)].profile;
    int o = 0;
    for (std::uint32_t k = 0; k < p.meta.level_count; ++k)
      if (j.scores[k] <= 1.0f) o = int(k);
    const int level = sim.rule("perceptual").levels[std::size_t(j.frame) * objects + j.object];
    chosen += p.levels[level].triangles;
    best += p.levels[o].triangles;
    same += level == o;
  }
  EXPECT_DOUBLE_EQ(r.oracle.ratio(), chosen / best);
  EXPECT_EQ(r.oracle.same, same);
  EXPECT_EQ(r.oracle.same + r.oracle.finer + r.oracle.coarser, judged.size());
  // The ungated rule against the oracle, recounted.
  const RuleRun& ungated = sim.rule("ungated");
  double ungated_chosen = 0;
  for (const Judged& j : judged) {
    const Profile& p = scene.assets[std::size_t(scene.instances[j.object].asset)].profile;
    ungated_chosen += p.levels[ungated.levels[std::size_t(j.frame) * objects + j.object]].triangles;
  }
  EXPECT_DOUBLE_EQ(r.ungated.ratio(), ungated_chosen / best);
  // 8 or 20 decisions allow no loss at 1%: the least any rule draws is the cheapest invisible level of each
  // (here the oracle's: the chains' triangles fall with the level).
  EXPECT_EQ(r.one_percent_losses, 0u);
  EXPECT_DOUBLE_EQ(r.least_at_one_percent, best);
  // Screen-size at 1% over the judged decisions lies between its bracketing entries' there.
  if (r.one_percent_screen_size.kind == Match::Kind::Interpolated) {
    auto over_judged = [&](int rule) {
      double sum = 0;
      for (const Judged& j : judged) {
        const Profile& p = scene.assets[std::size_t(scene.instances[j.object].asset)].profile;
        sum += p.levels[rules[std::size_t(rule)].levels[std::size_t(j.frame) * objects + j.object]].triangles;
      }
      return sum;
    };
    const double safe = over_judged(r.one_percent_screen_size.rule);
    const double risky =
        r.one_percent_screen_size.riskier >= 0 ? over_judged(r.one_percent_screen_size.riskier) : safe;
    EXPECT_LE(r.screen_size_judged_at_one_percent, std::max(safe, risky) * (1 + 1e-12));
    EXPECT_GE(r.screen_size_judged_at_one_percent, std::min(safe, risky) * (1 - 1e-12));
  }
  // No third-party assets named: the group is empty and the summary has no such table.
  EXPECT_EQ(r.third_party.objects, 0u);
  EXPECT_EQ(summary_text(sim, r).find("Third-party"), std::string::npos);
  // The summary names every main rule with its losses out of the judged decisions.
  const std::string text = summary_text(sim, r);
  for (const char* name : {"perceptual", "reddy", "distance", "screen-size", "ungated"}) {
    const std::size_t i = std::size_t(&sim.rule(name) - rules.data());
    EXPECT_NE(
        text.find("(" + std::to_string(r.visible_losses[i]) + "/" + std::to_string(judged_count()) + ")"),
        std::string::npos)
        << name << "\n"
        << text;
  }
  // With nothing judged, no rate is claimed.
  const Results none = analyse(sim, {});
  EXPECT_EQ(none.fraction(std::size_t(none.perceptual)), 0.0);
  EXPECT_EQ(summary_text(sim, none).find("visible"), std::string::npos);
}

// Walking backwards away from the field for 3 s (to 600 m), then standing: objects coarsen. The
// ungated rule (the perceptual rule switching at once) is never finer than the perceptual rule; each
// time the perceptual rule coarsens an object, after calm frames and a saccade, the ungated rule was
// coarser the frame before; and it switches at least as often.
TEST(Simulate, UngatedRuleCoarsensAtOnceWhereThePerceptualRuleWaits) {
  const SceneAssets& scene = small_scene();
  std::string head = "t,x,y,z,qx,qy,qz,qw\n";
  for (int i = 0; i <= 60; ++i)
    head += std::to_string(0.1 * i) + ",0,1.6," + std::to_string(20.0 * std::min(i, 30)) + ",0,0,0,1\n";
  write(scratch("retreat.csv"), head);
  SimulationOptions o = small_options("");
  o.seconds = 6;
  o.movers = 0;
  o.head_file = scratch("retreat.csv").string();
  o.validate = 0;
  Simulation sim(scene, o);
  sim.run();
  const RuleRun &gated = sim.rule("perceptual"), &ungated = sim.rule("ungated");
  const std::size_t objects = scene.instances.size();
  std::size_t coarsened = 0, coarser = 0;
  for (std::size_t f = 0; f < sim.frame_count(); ++f)
    for (std::size_t i = 0; i < objects; ++i) {
      const std::size_t at = f * objects + i;
      ASSERT_GE(ungated.levels[at], gated.levels[at]) << "frame " << f << " object " << i;
      coarser += ungated.levels[at] > gated.levels[at];
      if (f > 0 && gated.levels[at] > gated.levels[at - objects]) {
        ++coarsened;
        EXPECT_GT(ungated.levels[at - objects], gated.levels[at - objects])
            << "frame " << f << " object " << i;
      }
    }
  ASSERT_GT(coarsened, 0u);  // the walk exercises coarsening
  EXPECT_GT(coarser, coarsened);
  EXPECT_LT(ungated.triangles, gated.triangles);
  EXPECT_GE(ungated.switches, gated.switches);
}

// SimulationOptions::model: the perceptual rule, ungated and the quality sweep take it; Reddy and
// the baselines keep their own choices, level for level; perceptual_text (what the commands print)
// and summary.json name it, with the evaluation the scheduler really used (stela-csf has no tables).
TEST(Simulate, ModelReachesThePerceptualRulesOnly) {
  const SceneAssets& scene = small_scene();
  SimulationOptions o = small_options("");
  o.seconds = 1;
  o.validate = 0;
  Simulation base(scene, o);
  base.run();
  o.model = ThresholdModel::StelaCsf;
  o.output = scratch("stela-model").string();
  o.images = 0;
  Simulation stela(scene, o);
  stela.run();
  for (std::size_t r = 0; r < stela.rules().size(); ++r) {
    const RuleRun &a = base.rules()[r], &b = stela.rules()[r];
    const bool perceptual = b.scheduler->config().rule == SelectionRule::Perceptual;
    EXPECT_EQ(b.scheduler->config().model, perceptual ? ThresholdModel::StelaCsf : ThresholdModel::Default)
        << b.name;
    if (!perceptual) {
      EXPECT_EQ(a.levels, b.levels) << b.name;
      continue;
    }
    ObjectExplain ea{}, eb{};  // the last frame's thresholds of object 0: the model's own
    ASSERT_TRUE(a.scheduler->explain(0, &ea) && b.scheduler->explain(0, &eb)) << b.name;
    ASSERT_GT(eb.level_count, 1u);
    EXPECT_NE(ea.levels[1].threshold, eb.levels[1].threshold) << b.name;
  }
  const Profile& profile = scene.assets[0].profile;
  EXPECT_EQ(perceptual_text(stela.rule("perceptual").scheduler->config(), profile),
            "model stela-csf, exact thresholds");
  EXPECT_EQ(perceptual_text(base.rule("perceptual").scheduler->config(), profile),
            "model default, tabulated thresholds");
  write_outputs(stela, analyse(stela, {}), {}, o.output);
  const std::string json = slurp(fs::path(o.output) / "summary.json");
  EXPECT_NE(json.find("\"model\": \"stela-csf\""), std::string::npos) << json;
}

TEST(Simulate, ThirdPartyAssetsAreReportedApart) {
  const SceneAssets& scene = small_scene();
  SimulationOptions o = small_options("");
  o.third_party = {"ball"};  // every instance: the group's figures are the whole run's
  Simulation sim(scene, o);
  sim.run();
  const std::vector<Judged> judged = judge_decisions(sim, judged_count(), 1);
  const Results r = analyse(sim, judged);
  const Results::Group& g = r.third_party;
  EXPECT_EQ(g.objects, scene.instances.size());
  EXPECT_EQ(g.judged, judged.size());
  EXPECT_NEAR(g.all_finest, r.all_finest, 1e-9 * r.all_finest);
  ASSERT_EQ(g.triangles.size(), sim.rules().size());
  for (std::size_t i = 0; i < sim.rules().size(); ++i) {
    EXPECT_NEAR(g.triangles[i], sim.rules()[i].triangles / double(r.frames), 1e-9 * r.all_finest);
    EXPECT_EQ(g.visible_losses[i], r.visible_losses[i]);
  }
  // The oracle beside them: the whole run's when the group is every instance.
  EXPECT_EQ(g.oracle.same, r.oracle.same);
  EXPECT_EQ(g.oracle.finer, r.oracle.finer);
  EXPECT_EQ(g.oracle.coarser, r.oracle.coarser);
  EXPECT_DOUBLE_EQ(g.oracle.rule_triangles, r.oracle.rule_triangles);
  EXPECT_DOUBLE_EQ(g.oracle.oracle_triangles, r.oracle.oracle_triangles);
  const std::string judged_text = std::to_string(judged_count());
  EXPECT_NE(summary_text(sim, r).find("Third-party assets (ball): 9 of the 9 objects, " + judged_text +
                                      " of the " + judged_text + " judged"),
            std::string::npos)
      << summary_text(sim, r);
}

// at_equal_loss on sweeps whose answer is known: triangles 1000 at rate 0 and 250 at rate 0.02
// (tuning 1/32 and 1/8) give 500 and 1/16 at 0.01 (log-linear halfway).
TEST(EqualLoss, InterpolatesTheFrontierBetweenTheEntriesThatBracketTheRate) {
  const std::vector<SweepPoint> sweep = {
      {0.02, 250, 0.125},
      {0.005, 2000, 0.01},  // riskier and dearer than entry 2: off the frontier
      {0.0, 1000, 0.03125},
      {0.03, 900, 0.2}};  // dearer than a safer entry: off the frontier
  Match m = at_equal_loss(sweep, 0.01);
  EXPECT_EQ(m.kind, Match::Kind::Interpolated);
  EXPECT_EQ(m.rule, 2);
  EXPECT_EQ(m.riskier, 0);
  EXPECT_NEAR(m.triangles, 500.0, 1e-9);
  EXPECT_NEAR(m.parameter, 0.0625, 1e-12);
  // A quarter of the way: 1000 * (1/4)^(1/4).
  EXPECT_NEAR(at_equal_loss(sweep, 0.005).triangles, 1000.0 * std::pow(0.25, 0.25), 1e-9);
  // At an entry's rate: that entry, exactly, and the cheaper of two at the same rate.
  std::vector<SweepPoint> tied = sweep;
  tied.push_back({0.02, 300, 0.1});
  m = at_equal_loss(tied, 0.02);
  EXPECT_EQ(m.kind, Match::Kind::Interpolated);
  EXPECT_EQ(m.rule, 0);
  EXPECT_EQ(m.riskier, -1);
  EXPECT_DOUBLE_EQ(m.triangles, 250.0);
  m = at_equal_loss(sweep, 0.0);
  EXPECT_EQ(m.rule, 2);
  EXPECT_DOUBLE_EQ(m.triangles, 1000.0);
  // Safer than every entry: the safest is a lower bound; riskier than all: the cheapest an upper one.
  const std::vector<SweepPoint> risky = {{0.04, 800, 0.5}, {0.01, 1200, 0.25}, {0.1, 300, 1}};
  m = at_equal_loss(risky, 0.0);
  EXPECT_EQ(m.kind, Match::Kind::AtLeast);
  EXPECT_EQ(m.rule, -1);
  EXPECT_EQ(m.riskier, 1);
  EXPECT_DOUBLE_EQ(m.triangles, 1200.0);
  EXPECT_DOUBLE_EQ(m.parameter, 0.25);
  m = at_equal_loss(risky, 0.5);
  EXPECT_EQ(m.kind, Match::Kind::AtMost);
  EXPECT_EQ(m.rule, 2);
  EXPECT_DOUBLE_EQ(m.triangles, 300.0);
}

TEST(EqualLoss, DegenerateSweepsAndRatesGiveNoneOrSkipTheBadEntries) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(at_equal_loss({}, 0.01).kind, Match::Kind::None);
  EXPECT_EQ(at_equal_loss({{0, 100, 1}}, nan).kind, Match::Kind::None);
  EXPECT_EQ(at_equal_loss({{0, 100, 1}}, inf).kind, Match::Kind::None);
  EXPECT_EQ(at_equal_loss({{nan, 100, 1}, {0, 0, 1}, {0, -5, 1}, {0, inf, 1}, {0, nan, 1}}, 0.0).kind,
            Match::Kind::None);
  // Bad entries are skipped, the rest still answer; a NaN tuning gives a NaN tuning, not a crash.
  const Match m = at_equal_loss({{nan, 1, 1}, {0, 400, 2}, {0.1, 100, 8}, {0.05, nan, 4}}, 0.05);
  EXPECT_EQ(m.kind, Match::Kind::Interpolated);
  EXPECT_NEAR(m.triangles, 200.0, 1e-9);
  EXPECT_NEAR(m.parameter, 4.0, 1e-12);
  // A single entry: exact at its rate, bounds on either side.
  EXPECT_EQ(at_equal_loss({{0.01, 100, 1}}, 0.01).kind, Match::Kind::Interpolated);
  EXPECT_EQ(at_equal_loss({{0.01, 100, 1}}, 0.0).kind, Match::Kind::AtLeast);
  EXPECT_EQ(at_equal_loss({{0.01, 100, 1}}, 0.02).kind, Match::Kind::AtMost);
}

// The oracle on constructed decisions: scores 0, 0.5, 1, 1.5, 0.8 make level 4 the coarsest
// invisible of five levels, level 2 of three; NaN is never invisible.
TEST(Oracle, CoarsestInvisibleLevelAndTriangleRatio) {
  Judged j{};
  j.scores = {};
  const float s[] = {0, 0.5f, 1.0f, 1.5f, 0.8f};
  std::copy(std::begin(s), std::end(s), j.scores.begin());
  EXPECT_EQ(oracle_level(j, 5), 4);
  EXPECT_EQ(oracle_level(j, 3), 2);
  EXPECT_EQ(oracle_level(j, 1), 0);
  EXPECT_EQ(oracle_level(j, 1000), int(kMaxLevels) - 1);  // levels past kMaxLevels do not exist; score 0
  j.scores[1] = j.scores[2] = std::numeric_limits<float>::quiet_NaN();
  j.scores[4] = 2;
  EXPECT_EQ(oracle_level(j, 5), 0);
  // Three decisions over levels of 1000, 500, 250, 125 triangles: finer (1 for 2), the same (2),
  // coarser (3 for 1): 875 against 1000.
  Oracle o;
  EXPECT_TRUE(std::isnan(o.ratio()));
  o.add(1, 2, 500, 250);
  o.add(2, 2, 250, 250);
  o.add(3, 1, 125, 500);
  EXPECT_DOUBLE_EQ(o.ratio(), 0.875);
  EXPECT_EQ(o.same, 1u);
  EXPECT_EQ(o.finer, 1u);
  EXPECT_EQ(o.coarser, 1u);
}

// The least triangles with losses allowed, on constructed decisions: cheapest invisible 100, 50, 30
// and cheapest at all 10, 40, 30 save 90, 10, 0 by losing; one loss allowed takes the 90.
TEST(Oracle, LeastTrianglesSpendsTheAllowedLossesWhereTheySaveMost) {
  const std::vector<double> invisible = {100, 50, 30}, any = {10, 40, 30};
  EXPECT_DOUBLE_EQ(least_triangles(invisible, any, 0), 180);
  EXPECT_DOUBLE_EQ(least_triangles(invisible, any, 1), 90);
  EXPECT_DOUBLE_EQ(least_triangles(invisible, any, 2), 80);
  EXPECT_DOUBLE_EQ(least_triangles(invisible, any, 99), 80);  // more losses than decisions
  EXPECT_DOUBLE_EQ(least_triangles({}, {}, 1), 0);
}

// Sampled decisions: each where its sample puts it (diameter, eccentricity, retinal speed across the
// line of sight, computed back from the pose), judged like the simulation's decisions, and every
// rule's losses and triangles counted from its levels; the sweeps monotone in their tuning.
TEST(Sampled, DecisionsStandWhereSampledAndEveryRuleIsCountedFromItsLevels) {
  const SceneAssets& scene = small_scene();
  SampleOptions o;
  o.count = 16;            // at seed 1 both still and moving ones (6 drew no moving one), in every build
  o.max_diameter_deg = 3;  // snapshots of at most 128 px: a quick judge
  o.moving = 0.5;
  const SampledRun run = run_sampled(scene, o, &small_scene_own_views());
  ASSERT_EQ(run.decisions.size(), o.count);
  ASSERT_EQ(run.judged.size(), o.count);
  std::uint32_t moving = 0;
  for (std::uint32_t i = 0; i < o.count; ++i) {
    const SampledDecision& d = run.decisions[i];
    const Profile& p = scene.assets[std::size_t(d.asset)].profile;
    EXPECT_TRUE(d.diameter_deg >= 1 && d.diameter_deg <= 3) << d.diameter_deg;
    EXPECT_TRUE(d.eccentricity_deg >= 0 && d.eccentricity_deg <= 40) << d.eccentricity_deg;
    // The sphere's centre from the pose: its diameter and angle from the gaze (0, 0, -1).
    const double len = std::sqrt(double(d.transform.rotation[0]) * d.transform.rotation[0] +
                                 double(d.transform.rotation[1]) * d.transform.rotation[1] +
                                 double(d.transform.rotation[2]) * d.transform.rotation[2] +
                                 double(d.transform.rotation[3]) * d.transform.rotation[3]);
    EXPECT_NEAR(len, 1.0, 1e-6);
    const double x = d.transform.rotation[0], y = d.transform.rotation[1], z = d.transform.rotation[2],
                 w = d.transform.rotation[3];
    const double c[3] = {p.meta.sphere[0], p.meta.sphere[1], p.meta.sphere[2]};
    // q c q*, written out.
    const double t[3] = {2 * (y * c[2] - z * c[1]), 2 * (z * c[0] - x * c[2]), 2 * (x * c[1] - y * c[0])};
    const double centre[3] = {d.transform.position[0] + c[0] + w * t[0] + (y * t[2] - z * t[1]),
                              d.transform.position[1] + c[1] + w * t[1] + (z * t[0] - x * t[2]),
                              d.transform.position[2] + c[2] + w * t[2] + (x * t[1] - y * t[0])};
    const double dist = std::sqrt(centre[0] * centre[0] + centre[1] * centre[1] + centre[2] * centre[2]);
    EXPECT_NEAR(2 * std::asin(p.meta.sphere[3] / dist) * 180 / kPi, d.diameter_deg, 1e-6 * d.diameter_deg);
    EXPECT_NEAR(std::acos(-centre[2] / dist) * 180 / kPi, d.eccentricity_deg, 1e-5);
    // The velocity across the line of sight, at the sampled angular speed.
    const double along =
        (d.velocity[0] * centre[0] + d.velocity[1] * centre[1] + d.velocity[2] * centre[2]) / dist;
    const double speed =
        std::sqrt(double(d.velocity[0]) * d.velocity[0] + double(d.velocity[1]) * d.velocity[1] +
                  double(d.velocity[2]) * d.velocity[2]);
    EXPECT_NEAR(along, 0.0, 1e-5 * (1 + speed));
    EXPECT_NEAR(speed / dist * 180 / kPi, d.speed_deg_s, 1e-5 * (1 + d.speed_deg_s));
    moving += d.speed_deg_s > 0;
    if (d.speed_deg_s > 0) { EXPECT_TRUE(d.speed_deg_s >= 1 && d.speed_deg_s <= 30) << d.speed_deg_s; }
    EXPECT_EQ(run.judged[i].object, i);
    EXPECT_EQ(run.judged[i].scores[0], 0.0f);  // the finest level loses nothing
    EXPECT_TRUE(run.judged[i].pixels >= 64 && run.judged[i].pixels <= 128) << run.judged[i].pixels;
  }
  EXPECT_GT(moving, 0u);
  EXPECT_LT(moving, o.count);
  // Every rule's rate and triangles from its levels; the main perceptual rule is its q = 1 sweep entry.
  const SweepPoint* previous_q = nullptr;
  const SweepPoint* previous_px = nullptr;
  for (std::size_t r = 0; r < run.rules.size(); ++r) {
    double triangles = 0;
    std::uint32_t losses = 0;
    for (std::uint32_t i = 0; i < o.count; ++i) {
      const std::uint8_t level = run.levels[r][i];
      triangles += scene.assets[std::size_t(run.decisions[i].asset)].profile.levels[level].triangles;
      losses += run.judged[i].scores[level] > 1.0f;
    }
    const RuleEntry& e = run.rules[r];
    EXPECT_DOUBLE_EQ(e.point.triangles, triangles) << e.name;
    EXPECT_EQ(run.visible[r], losses) << e.name;
    EXPECT_DOUBLE_EQ(e.point.rate, double(losses) / o.count) << e.name;
    if (e.sweep && e.name == "perceptual") {
      if (e.point.parameter == 1.0) { EXPECT_EQ(run.levels[r], run.levels[0]); }
      if (previous_q) { EXPECT_LE(e.point.triangles, previous_q->triangles); }  // a larger q never finer
      previous_q = &e.point;
    }
    if (e.sweep && e.name == "screen-size") {
      if (previous_px) { EXPECT_LE(e.point.triangles, previous_px->triangles); }
      previous_px = &e.point;
    }
  }
  EXPECT_EQ(run.rules[0].name, "perceptual");
  EXPECT_FALSE(run.rules[0].sweep);
  // Each margin change counted from its levels; removing a margin never makes a decision finer, and
  // adding one (Max3) never makes one coarser; the tables never decide coarser than exact. (The area
  // law off goes either way: a moving object's rows read the pooled loss with the law; so may other
  // profiles, whose views are chosen anew.)
  ASSERT_EQ(run.margins.size(), 7u);
  EXPECT_EQ(run.margins[5].name, "eccentricity: nearest -> centre");
  EXPECT_EQ(run.margins[6].name, "cell bounds -> each view's own");
  for (const SampledRun::MarginChange& m : run.margins) {
    double triangles = 0;
    std::uint32_t losses = 0;
    for (std::uint32_t i = 0; i < o.count; ++i) {
      const std::uint8_t level = m.levels[i];
      triangles += scene.assets[std::size_t(run.decisions[i].asset)].profile.levels[level].triangles;
      losses += run.judged[i].scores[level] > 1.0f;
      if (m.name.find("area law") != std::string::npos || m.name.find("cell bounds") != std::string::npos) {
        continue;
      } else if (m.name.find("-> Max3") != std::string::npos) {  // added (not "all but Max3 removed")
        EXPECT_LE(level, run.levels[0][i]) << m.name << " decision " << i;
      } else {
        EXPECT_GE(level, run.levels[0][i]) << m.name << " decision " << i;
      }
    }
    EXPECT_DOUBLE_EQ(m.triangles, triangles) << m.name;
    EXPECT_EQ(m.visible, losses) << m.name;
  }
  // The eccentricity margin's frames: the gaze turned away by the object's angular radius, so the
  // rule's eccentricity (the sphere's nearest point, less the gaze's uncertainty) is what the
  // centre's was less the uncertainty, where in the sampled frame it is the nearest point's.
  for (std::uint32_t i = 0; i < o.count; ++i) {
    const SampledDecision& d = run.decisions[i];
    SchedulerConfig c = run.perceptual;
    c.max_objects = 1;
    Scheduler s(c);
    for (const Asset& a : scene.assets) s.add_profile(a.profile);
    const ObjectId id = s.add_object(d.asset, d.transform);
    const float room = c.gaze_uncertainty_deg;
    ObjectExplain at_centre, sampled;
    s.run_frame(centre_gaze_frame(scene, run, i));
    ASSERT_TRUE(s.explain(id, &at_centre));
    s.run_frame(run.frame);
    ASSERT_TRUE(s.explain(id, &sampled));
    EXPECT_NEAR(at_centre.eccentricity_deg, std::max(0.0, d.eccentricity_deg - room), 1e-3) << i;
    EXPECT_NEAR(sampled.eccentricity_deg, std::max(0.0, d.eccentricity_deg - 0.5 * d.diameter_deg - room),
                1e-3)
        << i;
    EXPECT_EQ(at_centre.view, sampled.view) << i;  // the same view of the object
    EXPECT_FLOAT_EQ(at_centre.angular_diameter_deg, sampled.angular_diameter_deg) << i;
  }
  const SceneAssets other;  // no assets: not the scene's
  EXPECT_NE(error_of([&] { run_sampled(scene, o, &other); }).find("other assets"), std::string::npos);
  const std::string text = sampled_text(scene, run);
  EXPECT_NE(text.find("safety margins"), std::string::npos) << text;
  EXPECT_NE(text.find(std::to_string(o.count) + " decisions sampled"), std::string::npos) << text;
  EXPECT_NE(text.find("Against the oracle"), std::string::npos) << text;
  // Bad options are named.
  SampleOptions bad = o;
  bad.count = 0;
  EXPECT_NE(error_of([&] { run_sampled(scene, bad); }).find("count"), std::string::npos);
  bad = o;
  bad.min_diameter_deg = 5;  // above the maximum
  EXPECT_NE(error_of([&] { run_sampled(scene, bad); }).find("diameters"), std::string::npos);
  bad = o;
  bad.moving = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(error_of([&] { run_sampled(scene, bad); }).find("moving"), std::string::npos);
}

TEST(FrameImage, ObjectsTakeTheirLevelColourAndTheGazeIsMarked) {
  const SceneAssets& scene = small_scene();
  SimulationOptions o = small_options("");
  o.movers = 0;
  Simulation sim(scene, o);
  sim.step();
  auto count = [&](const std::uint8_t* levels, int channel_high, int channel_low) {
    RgbImage im;
    im.width = im.height = 200;
    im.pixels.assign(200 * 200 * 3, 0);
    draw_levels(sim, 0, levels, &im, 0);
    int n = 0, white = 0;
    for (int y = 0; y < 180; ++y)  // above the swatches
      for (int x = 0; x < 200; ++x) {
        const std::uint8_t* p = &im.pixels[std::size_t(y * 200 + x) * 3];
        n += p[channel_high] > 2 * p[channel_low] + 20;
        white += p[0] == 255 && p[1] == 255 && p[2] == 255;
      }
    return std::pair{n, white};
  };
  const std::vector<std::uint8_t> finest(9, 0), coarse(9, 2);
  const auto blue = count(finest.data(), 2, 0), green_as_blue = count(coarse.data(), 2, 0),
             green = count(coarse.data(), 1, 0);
  EXPECT_GT(blue.first, 200);  // level 0: blue objects
  EXPECT_LT(green_as_blue.first, 20);
  EXPECT_GT(green.first, 200);  // level 2: green
  EXPECT_GT(blue.second, 20);   // the gaze ring
}

TEST(Outputs, ShellQuotingReadsBackAsTheSamePath) {
  EXPECT_EQ(shell_quoted("build/demo/simulate"), "build/demo/simulate");  // plain: as is
  EXPECT_EQ(shell_quoted("my runs/a"), "'my runs/a'");
  EXPECT_EQ(shell_quoted("it's"), "'it'\\''s'");  // a quote closes, is escaped, reopens
  EXPECT_EQ(shell_quoted(""), "''");
  EXPECT_EQ(shell_quoted("$(rm -rf x);`y`"), "'$(rm -rf x);`y`'");
}

TEST(Outputs, TextListsTheFilesAndThePlotCommandOnlyWhenAsked) {
  Results r;
  const std::vector<std::string> written = {"out dir/frames.csv", "out dir/summary.json"};
  const std::string with = outputs_text(r, written, "out dir", "/usr/share/acuity/plot_simulation.py");
  EXPECT_NE(with.find("\nwritten to out dir:\n  out dir/frames.csv\n  out dir/summary.json\n"),
            std::string::npos);
  EXPECT_NE(with.find("screen-size at 1 px"), std::string::npos);  // no tuned baseline in r
  EXPECT_NE(with.find("python3 /usr/share/acuity/plot_simulation.py 'out dir'\n"), std::string::npos) << with;
  const std::string without = outputs_text(r, written, "out dir", "");
  EXPECT_EQ(without.find("python3"), std::string::npos);
  r.screen_size.rule = 2;
  EXPECT_NE(outputs_text(r, {}, "o", "").find("screen-size tuned to the same visible losses"),
            std::string::npos);
}
