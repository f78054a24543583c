#pragma once
// acuity/lodgen/chain.hpp — a chain of levels of detail from one mesh, measured.
#include <cstddef>
#include <functional>
#include <vector>

#include "acuity/lodgen/decimate.hpp"
#include "acuity/lodgen/mesh.hpp"

namespace acuity::lodgen {

struct ChainOptions {
  std::size_t levels =
      0;                 // 0: halve (ratio) until about 1% or min_triangles; never more than kMaxLevels (32)
  double ratio = 0.5;    // triangles of level k+1 over level k
  double max_error = 0;  // > 0: instead, levels at errors max_error / 2^(L-k) ... up to this
                         // Hausdorff distance [object diameters]
  std::size_t min_triangles = 64;
  DecimateOptions decimate;  // decimate.crease_degrees: edges sharper than this are drawn sharp
                             // in every level (split_creases); >= 180: all smooth
  bool repair = true;        // repair bad input (with a warning) instead of rejecting it
  DeviationOptions measure;  // bounds on the error measurement (sample count, seconds per level)
};

struct Level {
  Mesh mesh;
  std::size_t target_triangles = 0;
  double hausdorff = 0;         // to level 0 [object diameters]
  double normal_deviation = 0;  // 99th-percentile angle between its shading normals and level 0's [degrees]
  double normal_deviation_max = 0;  // the largest such angle [degrees]
  bool measured_fully = true;  // false: the measurement's time cap cut sampling short (a looser lower bound)
  double seconds = 0;          // to build this level
};

struct Chain {
  std::vector<Level> levels;  // finest first
  double diameter = 0;        // level 0's bounding-sphere diameter [object units]
  std::vector<std::string> warnings;
};

// stage, done, total
using ChainProgress = std::function<void(const char* stage, std::size_t done, std::size_t total)>;

// Level 0 is the input (repaired if needed) with normals split at creases (decimate.crease_degrees).
// meshopt decimates level 0 keeping its creases as seams, level after level, until such a result
// is rejected; from that level on it decimates level 0 welded, each level from the previous one
// (decimate_meshopt_level). The other back-ends decimate the welded input, every level from level
// 0, and split each level at its own creases. Every level is measured against level 0
// (lodgen::deviation, bounded by options.measure): the Hausdorff error and
// the normal deviations are made non-decreasing along the chain (a level is never reported better
// than a finer one). Throws InputError for unusable input.
Chain build_chain(const Mesh& mesh, const std::string& where, const ChainOptions& options,
                  const ChainProgress& progress = {});

// One meshopt level of build_chain, levels made finest first with one state: `level0`
// (crease-split) decimated to `target` triangles keeping its seams, as long as that result is
// accepted (under 1% flipped triangles, at most 5% above the target: see decimate()). Once one is
// rejected, that level is decimated from level 0 welded (seams closed) and split at its own
// creases, as decimate() does, and every later level continues the welded decimation from the
// previous one (`previous_welded`): level 0 is neither tried again nor decimated again, so a
// rejected level costs two decimations of level 0 and the later ones about their input's size
// (docs/lodgen.md).
struct MeshoptChainState {
  bool welded = false;  // a level was rejected: the later ones continue previous_welded
  Mesh previous_welded;
};
Mesh decimate_meshopt_level(const Mesh& level0, std::size_t target, const DecimateOptions& options,
                            MeshoptChainState* state);

// A chain from given levels (refinement output), measured as build_chain does.
Chain measure_chain(std::vector<Mesh> levels, const ChainProgress& progress = {},
                    const DeviationOptions& measure = {});

}  // namespace acuity::lodgen
