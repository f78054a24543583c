#pragma once
// acuity/sim/large_object.hpp — the demo's large object (issue 48 item 4): one of the demo's meshes
// drawn large, spanning the gaze, as a cluster hierarchy (lodgen --clusters, its per-group loss
// profiled and cached), for the frames of a run: the object rule's triangles per frame (one level for
// the whole object, the run's perceptual configuration) against the cluster cut's (Scheduler::select_cut
// with memory, the same configuration), and both judged at some frames by the judge's detection model
// against the finest mesh (acuity/sim/detection.hpp; the cut rendered as its triangles).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "acuity/sim/simulation.hpp"

namespace acuity::sim {

struct LargeObjectOptions {
  std::string asset = "camel";  // the scene asset drawn large (its chain's level 0 is the finest mesh)
  std::vector<double> spans_deg = {40, 20};  // the angles its bounding sphere subtends at the head, one
                                             // run each [deg]
  double distance = 2;                       // from the head to the sphere's centre [m]
  std::uint32_t judged = 10;                 // frames judged, spread evenly over the run
  std::string profiles;        // folder where the hierarchy's profile is cached (<asset>-clusters.acuity)
  std::uint32_t pixels = 256;  // snapshot pixels of that profile's level-0 snapshots, as the scene's
                               // profiles take them (the demo's and simulate's --res)
};

struct LargeObjectRun {
  std::string asset;
  std::uint64_t finest = 0;  // triangles of the finest mesh
  std::uint32_t clusters = 0, groups = 0, bands = 0;
  std::size_t frames = 0;
  struct Judged {
    std::uint32_t frame = 0;
    std::uint64_t object_triangles = 0, cut_triangles = 0;
    float object_score = 0, cut_score = 0;  // the judge's: <= 1 invisible
  };
  struct Span {
    double deg = 0;
    double object_rule = 0, cut = 0;  // triangles per frame, mean over the frames
    std::vector<Judged> judged;
  };
  std::vector<Span> spans;  // as LargeObjectOptions::spans_deg
};

// The object: still, in front of a still head whose eyes look down -Z, its sphere centred on that
// axis; the gaze each frame is the run's (its directions in the head, its confidence, its measured
// velocity: fixations, saccades, pursuit and blinks over +-40 degrees), the head itself held still.
// The hierarchy is built from the asset's level 0 (deterministic); its profile (level 0 at
// options.pixels and what each group loses, 12 directions per group, the bake's other defaults) is
// read from `profiles` when it measured this hierarchy at those pixels, else made and written there.
// `progress` receives a line when the profile is made.
// Throws std::runtime_error naming a missing asset, io::Error when the cache cannot be written.
LargeObjectRun run_large_object(const Simulation& sim, const LargeObjectOptions& options,
                                const std::function<void(const std::string&)>& progress = {});

// The index of `asset` among the scene's assets. Throws std::runtime_error "<what>: the scene has no
// asset 'NAME' (it has A, B, ...)" when none has that name: run_large_object's check, which a
// command may make before the run.
std::size_t large_object_asset(const SceneAssets& scene, const std::string& asset, const std::string& what);

// The block the demo prints.
std::string large_object_text(const LargeObjectRun& run, const LargeObjectOptions& options);

}  // namespace acuity::sim
