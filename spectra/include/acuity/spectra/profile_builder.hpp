#pragma once
// acuity/spectra/profile_builder.hpp — from a chain of levels to a profile (docs/design.md sections 4, 7).
//
// For each view: render every level, measure level k's lost contrast against level 0 per
// orientation and band, and Reddy's feature frequencies per level and orientation.
// Views: a fixed number (Fibonacci sphere), or adaptive: the nested icosphere vertex sets of 12,
// 42 and 162 directions, refined while some view is predicted badly by its nearest other view,
// then pruned greedily while every measured view stays predicted well by its nearest kept view.
// "Predicted well" is about decisions: each level's switching distance (where its loss becomes
// just visible to a still fovea, default model) from the predicting view is within
// view_tolerance of the view's own. A sphere keeps few views; a statue keeps many.
#include <cstdint>
#include <functional>
#include <vector>

#include "acuity/spectra/analyze.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "acuity/spectra/render.hpp"

namespace acuity::spectra {

struct LevelInput {
  MeshView mesh;
  std::uint32_t triangles = 0;  // cost; 0 takes index_count / 3
  float geometric_error = 0;    // Hausdorff distance to level 0 [object diameters]
};

struct ProfileSettings {
  RenderSettings render;  // pixels, supersample, background, ambient; the sphere is level 0's
  AnalysisSettings analysis;
  std::uint32_t views = 0;       // 0: adaptive; else exactly this many (Fibonacci sphere)
  float view_tolerance = 0.25f;  // adaptive: largest relative error of a switching distance
  std::uint32_t max_views = 42;  // adaptive: stop refining here (12, 42 or 162); past 42 the
                                 // per-view spread of the image maximum dominates (docs/spectra.md)
  bool prune = true;             // adaptive: drop views their neighbours predict
  unsigned jobs = 0;             // worker threads; 0: all cores
};

struct ProfileReport {
  std::uint32_t views_measured = 0, views_kept = 0;
  float prediction_error = 0;  // largest relative switching-distance error of a measured view
                               // predicted by its nearest kept view
  double seconds = 0;          // wall time
};

// stage ("views"), done, total. Called from worker threads, one call at a time.
using ProgressFn = std::function<void(const char* stage, std::size_t done, std::size_t total)>;

// One view's measurement.
struct ViewMeasurement {
  std::vector<float> lost;       // [(K-1) T B]
  std::vector<float> features;   // [K T]
  std::vector<float> switching;  // [K-1] angular diameter [deg] at which level k's loss becomes
                                 // visible (still object, fovea, default model; 180 = never, 1e-4 = always)
};

// Renders and analyses a chain at any view; shared by the builder and by direct ground truth.
class ProfileMeasurer {
 public:
  ProfileMeasurer(const std::vector<LevelInput>& levels, const Material& material,
                  const ProfileSettings& settings);
  ViewMeasurement measure(const ProfileView& view) const;  // thread-safe
  const LostContrast& analyzer() const { return analyzer_; }
  const float* sphere() const { return render_.sphere; }

 private:
  std::vector<LevelInput> levels_;
  Material material_;
  RenderSettings render_;
  AnalysisSettings analysis_;
  LostContrast analyzer_;
};

// Throws std::invalid_argument for an empty chain or a degenerate level 0.
ProfileData build_profile(const std::vector<LevelInput>& levels, const Material& material,
                          const ProfileSettings& settings, const ProgressFn& progress = {},
                          ProfileReport* report = nullptr);

// Largest |ln(a / b)| over the levels' switching angles (the adaptive criterion, in log).
float view_difference(const ViewMeasurement& a, const ViewMeasurement& b);
// The angular diameter [deg] at which lost contrast `lost` [T B] in `bands` [cpod] reaches one
// threshold of the default model for a still object at the fovea.
float switching_angle(const float* lost, std::size_t orientations, const std::vector<float>& bands);

// Unit sphere meshes and direction sets.
struct SphereMesh {
  std::vector<float> positions;  // unit vectors; the first 12 / 42 / 162 are nested across levels
  std::vector<std::uint32_t> indices;
};
SphereMesh icosphere(int subdivisions);
std::vector<ProfileView> fibonacci_views(std::uint32_t count);

}  // namespace acuity::spectra
