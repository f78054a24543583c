// Decimation speed against error: OpenMesh, CGAL (Garland-Heckbert, Lindstrom-Turk) and
// meshoptimizer (the outside reference) on real meshes at 50, 25, 12.5 and 6.25% of the triangles.
// Time is the best of `repeats` runs of the decimation alone; error is the symmetric Hausdorff
// distance to the input (lodgen::hausdorff, one estimator for all) in bounding-sphere diameters.
// Run: build/bench/bench_lodgen [MESH_DIR] [repeats]   (prints a Markdown table)
#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "acuity/lodgen/decimate.hpp"

using namespace acuity::lodgen;

namespace {
Mesh meshopt(const Mesh& in, std::size_t target) {
  Mesh out = in;
  out.indices.resize(in.indices.size());
  float error = 0;
  const std::size_t n = meshopt_simplify(out.indices.data(), in.indices.data(), in.indices.size(), in.positions.data(),
                                         in.vertex_count(), 12, target * 3, 1.0f, 0, &error);
  out.indices.resize(n);
  return out;
}
}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "build/cgal-data/data/meshes";
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  std::printf("| mesh | triangles | kept | backend | result | time [ms] | Hausdorff [diam] | time / meshopt | error / meshopt |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const char* name : {"elephant.off", "fandisk.off", "camel.off", "ChineseDragon-10kv.off", "armadillo.off", "bunny00.off"}) {
    const Mesh m = load_mesh(dir + "/" + name);
    const double d = diameter(m);
    for (double keep : {0.5, 0.25, 0.125, 0.0625}) {
      const std::size_t target = std::size_t(double(m.triangle_count()) * keep);
      struct Row { const char* backend; double ms; double error; std::size_t triangles; };
      std::vector<Row> rows;
      for (int b = 0; b < 4; ++b) {
        Mesh best;
        double ms = 1e30;
        for (int r = 0; r < repeats; ++r) {
          const auto t0 = std::chrono::steady_clock::now();
          Mesh out = b == 3 ? meshopt(m, target) : decimate(m, target, {Backend(b), false});
          ms = std::min(ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
          best = std::move(out);
        }
        const char* label = b == 3 ? "meshoptimizer" : to_string(Backend(b));
        rows.push_back({label, ms, hausdorff(m, best, d / 250) / d, best.triangle_count()});
      }
      const Row& ref = rows[3];
      for (const Row& r : rows)
        std::printf("| %s | %zu | %.2f%% | %s | %zu | %.1f | %.5f | %.2f | %.2f |\n", name, m.triangle_count(), 100 * keep,
                    r.backend, r.triangles, r.ms, r.error, r.ms / ref.ms, r.error / ref.error);
      std::fflush(stdout);
    }
  }
}
