// Decimation speed against error: lodgen's back-ends (meshopt on the crease-split mesh, the
// default; OpenMesh; CGAL Garland-Heckbert and Lindstrom-Turk) and plain meshoptimizer (the
// outside reference) on real meshes at 50, 25, 12.5 and 6.25% of the triangles.
// Time is the best of `repeats` runs of what lodgen's chain does per level: for meshopt
// decimate_meshopt_level (the crease-split input decimated keeping its seams; once that is
// rejected, the welded input, the later levels each from the previous welded one; the split itself
// is made once per chain, timed separately and included in the chain table), for the others the
// decimation of the input and the crease split of its result; plain meshoptimizer is timed on the
// input's indices alone, every level from the input. The chain table
// adds, per mesh, level 0's crease split and the four levels against plain meshoptimizer's four. Errors, one estimator for all
// (lodgen::deviation at diameter/250): the symmetric Hausdorff distance to the input in
// bounding-sphere diameters, and the 99th-percentile angle between the result's shading normals
// and the input's crease-split normals (plain meshoptimizer's result gets crease-split normals,
// untimed, as a renderer would compute them).
// Run: build/bench/bench_lodgen [MESH_DIR] [repeats]   (prints Markdown: a summary per back-end, the
// whole chains with a sentence on the meshopt rows that were rejected or continued a welded level,
// then all rows; docs/lodgen.md holds it as a figure, scripts/regenerate_docs.py --only lodgen-bench)
#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "acuity/lodgen/chain.hpp"
#include "acuity/lodgen/decimate.hpp"

using namespace acuity::lodgen;

namespace {
constexpr double kCrease = 45;  // DecimateOptions::crease_degrees' default

Mesh meshopt(const Mesh& in, std::size_t target) {
  Mesh out = in;
  out.indices.resize(in.indices.size());
  float error = 0;
  const std::size_t n =
      meshopt_simplify(out.indices.data(), in.indices.data(), in.indices.size(), in.positions.data(),
                       in.vertex_count(), 12, target * 3, 1.0f, 0, &error);
  out.indices.resize(n);
  return out;
}

// `state`: the meshopt chain's, as build_chain keeps it.
Mesh run(int b, const Mesh& m, const Mesh& shaded, MeshoptChainState* state, std::size_t target) {
  if (b == 4) return meshopt(m, target);
  const Backend backend = Backend(b);
  if (backend == Backend::Meshopt)
    return decimate_meshopt_level(shaded, target, {backend, false, kCrease}, state);
  return split_creases(decimate(m, target, {backend, false, kCrease}), kCrease);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "build/cgal-data/data/meshes";
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  const int order[] = {int(Backend::Meshopt), int(Backend::CgalGarlandHeckbert),
                       int(Backend::CgalLindstromTurk), int(Backend::OpenMesh), 4};
  struct Summary {
    std::vector<double> time, error, normal;
    int at_or_below = 0;
  };
  std::map<std::string, Summary> summary;
  struct ChainRow {
    std::string mesh;
    double split_ms, meshopt_ms, reference_ms;
  };
  std::vector<ChainRow> chains;
  std::string rejected, continued;  // meshopt rows: "mesh kept% (time ratio)", comma-separated
  std::string all_rows =
      "| mesh | triangles | kept | backend | result | time [ms] | Hausdorff [diam] | normal p99 [deg] | time "
      "/ meshopt | error / meshopt |\n|---|---|---|---|---|---|---|---|---|---|\n";
  const double keeps[] = {0.5, 0.25, 0.125, 0.0625};
  std::size_t mesh_count = 0;
  for (const char* name : {"elephant.off", "fandisk.off", "camel.off", "ChineseDragon-10kv.off",
                           "armadillo.off", "bunny00.off"}) {
    const Mesh m = load_mesh(dir + "/" + name);
    ++mesh_count;
    double split_ms = 1e30;
    Mesh shaded;
    for (int r = 0; r < repeats; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      shaded = split_creases(m, kCrease);
      split_ms = std::min(
          split_ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    chains.push_back({name, split_ms, split_ms, 0});
    const double d = diameter(m);
    DeviationOptions measure;
    measure.spacing = d / 250;
    MeshoptChainState chain_state;  // the meshopt chain's
    for (double keep : keeps) {
      const std::size_t target = std::size_t(double(m.triangle_count()) * keep);
      struct Row {
        std::string backend;
        double ms;
        Deviation error;
        std::size_t triangles;
      };
      std::vector<Row> rows;
      const bool was_welded = chain_state.welded;
      for (int b : order) {
        Mesh best;
        double ms = 1e30;
        for (int r = 0; r < repeats; ++r) {
          MeshoptChainState state =
              chain_state;  // each repeat starts from the chain's state (copied untimed)
          const auto t0 = std::chrono::steady_clock::now();
          Mesh out = run(b, m, shaded, &state, target);
          ms = std::min(
              ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
          if (r + 1 == repeats && b == int(Backend::Meshopt)) chain_state = std::move(state);
          best = std::move(out);
        }
        if (b == 4) best = split_creases(best, kCrease);
        rows.push_back({b == 4 ? "meshoptimizer" : to_string(Backend(b)), ms,
                        deviation(shaded, best, measure), best.triangle_count()});
      }
      const Row& ref = rows.back();
      for (const Row& r : rows) {
        const double tr = r.ms / ref.ms, er = r.error.hausdorff / ref.error.hausdorff;
        char line[512];  // a row: names under 100 characters and numbers
        std::snprintf(line, sizeof line,
                      "| %s | %zu | %.2f%% | %s | %zu | %.1f | %.5f | %.1f | %.2f | %.2f |\n", name,
                      m.triangle_count(), 100 * keep, r.backend.c_str(), r.triangles, r.ms,
                      r.error.hausdorff / d, r.error.normal_p99_degrees, tr, er);
        all_rows += line;
        if (r.backend == "meshopt") {
          chains.back().meshopt_ms += r.ms;
          std::string& list = was_welded ? continued : rejected;
          if (was_welded || chain_state.welded) {
            std::snprintf(line, sizeof line, "%s%s %.2f%% (%.2fx)", list.empty() ? "" : ", ", name,
                          100 * keep, tr);
            list += line;
          }
        }
        if (r.backend == "meshoptimizer") chains.back().reference_ms += r.ms;
        Summary& s = summary[r.backend];
        s.time.push_back(tr);
        s.error.push_back(er);
        s.normal.push_back(r.error.normal_p99_degrees / std::max(1e-9, ref.error.normal_p99_degrees));
        s.at_or_below += r.error.hausdorff <= ref.error.hausdorff;
      }
      std::fprintf(stderr, "%s %.2f%% done\n", name, 100 * keep);  // progress
    }
  }
  std::printf("### Summary over %zu meshes × %zu targets (%zu rows)\n\n", mesh_count, std::size(keeps),
              mesh_count * std::size(keeps));
  std::printf(
      "| backend | time / meshoptimizer, median (range) | Hausdorff / meshoptimizer, median | normal p99 / "
      "meshoptimizer, median | rows at or below meshoptimizer's Hausdorff |\n");
  std::printf("|---|---|---|---|---|\n");
  for (int b : order) {
    const std::string label = b == 4 ? "meshoptimizer" : to_string(Backend(b));
    const Summary& s = summary[label];
    std::printf("| %s | %.2fx (%.2f-%.2f) | %.2f | %.2f | %d / %zu |\n", label.c_str(), median(s.time),
                *std::min_element(s.time.begin(), s.time.end()),
                *std::max_element(s.time.begin(), s.time.end()), median(s.error), median(s.normal),
                s.at_or_below, s.time.size());
  }
  std::printf("\n### Whole chains (level 0's split + the %zu levels)\n\n", std::size(keeps));
  std::printf(
      "| mesh | crease split [ms] | meshopt chain: split + 4 levels [ms] | meshoptimizer: 4 levels [ms] | "
      "chain time / meshoptimizer |\n");
  std::printf("|---|---|---|---|---|\n");
  std::vector<double> chain_ratio;
  for (const ChainRow& c : chains) {
    chain_ratio.push_back(c.meshopt_ms / c.reference_ms);
    std::printf("| %s | %.1f | %.1f | %.1f | %.2f |\n", c.mesh.c_str(), c.split_ms, c.meshopt_ms,
                c.reference_ms, chain_ratio.back());
  }
  std::printf("| median | | | | %.2f |\n", median(chain_ratio));
  std::printf(
      "\nDefault meshopt: chains %.2f-%.2fx meshoptimizer's time (median %.2fx). Levels whose seam-keeping "
      "run was rejected (decimated twice): %s. Levels continuing from a rejected level's welded result: "
      "%s.\n",
      *std::min_element(chain_ratio.begin(), chain_ratio.end()),
      *std::max_element(chain_ratio.begin(), chain_ratio.end()), median(chain_ratio),
      rejected.empty() ? "none" : rejected.c_str(), continued.empty() ? "none" : continued.c_str());
  std::printf("\n### All rows\n\n%s", all_rows.c_str());
}
