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
// Bounds (bound_cells, the default): the runtime reads the stored view nearest to the eye, so
// each kept view serves its cell on the sphere (the directions nearer to it than to any other
// kept view). The builder also measures the sample directions bound_sample_views() (162, nested
// with the adaptive sets), optionally (bound_views) adds kept views where a cell's samples
// disagree (silhouettes, creases), and stores per view, level, orientation and band the largest lost contrast over
// the view and every measured direction in or near its cell (orientations carried into the
// view's image frame, taking the larger of the two nearest). The nearest-view lookup then
// reads a bound at the sampled directions, not one view's value.
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
  std::uint32_t views = 0;        // 0: adaptive; else exactly this many (Fibonacci sphere; bounds
                                  // then add no views)
  float view_tolerance = 0.25f;   // adaptive: largest relative error of a switching distance
  std::uint32_t max_views = 42;   // adaptive: stop refining here (12, 42 or 162); past 42 the
                                  // per-view spread of the image maximum dominates (docs/spectra.md)
  bool prune = true;              // adaptive: drop views their neighbours predict
  bool bound_cells = true;        // store the maximum over each view's cell (above); false: the
                                  // view's own measurement (4x faster to build, optimistic often)
  std::uint32_t bound_views = 0;  // bounds: add views, up to this many, where a cell's bound switches
                                  // earlier than its samples by over half view_tolerance (mean);
                                  // 0: none (smaller cells hold fewer samples: less safe, docs/spectra.md)
  unsigned jobs = 0;              // worker threads; 0: all cores
};

struct ProfileReport {
  std::uint32_t views_measured = 0, views_kept = 0;
  float prediction_error = 0;       // largest relative switching-distance error of a measured view
                                    // predicted by its nearest kept view (own measurements, before bounds)
  double seconds = 0;               // wall time
  std::uint32_t views_sampled = 0;  // directions measured in all (views_measured and bounds' samples)
  float bound_pessimism = 0;        // bounds: median over measured directions and levels of how much
                                    // earlier the bound switches than the direction's own measurement
                                    // (switching angle ratio - 1; 0 where the bound is exact)
};

// stage ("views"), done, total. Called from worker threads, one call at a time.
using ProgressFn = std::function<void(const char* stage, std::size_t done, std::size_t total)>;

// One view's measurement.
struct ViewMeasurement {
  std::vector<float> lost;         // [(K-1) T B]
  std::vector<float> area;         // [(K-1) T B] the loss's extent (LostContrast::measure's area)
  std::vector<float> pooled;       // [(K-1) B] each band's loss pooled over orientations (... pooled)
  std::vector<float> pooled_area;  // [(K-1) B] its extent (... pooled_area)
  std::vector<float> offset;       // [(K-1) T B] its frequency within the band [octaves] (... offset)
  std::vector<float> turn;         // [(K-1) T B] its angle from the orientation [spacings] (... turn)
  std::vector<float> features;     // [K T]
  std::vector<float> switching;    // [K-1] angular diameter [deg] at which level k's loss becomes
                                   // visible (still object, fovea, default model; 180 = never, 1e-4 = always)
};

// Renders and analyses a chain at any view; shared by the builder and by direct ground truth.
class ProfileMeasurer {
 public:
  ProfileMeasurer(const std::vector<LevelInput>& levels, const Material& material,
                  const ProfileSettings& settings);
  // Thread-safe. features = false leaves ViewMeasurement::features empty (bounds' samples need none).
  ViewMeasurement measure(const ProfileView& view, bool features = true) const;
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
// The score (lost contrast in thresholds, the largest over bands) of lost contrast `lost` [T B]
// seen at angular diameter `angle` [deg], still object at the fovea, default model.
float still_score(const float* lost, std::size_t orientations, const std::vector<float>& bands, double angle);

// Unit sphere meshes and direction sets.
struct SphereMesh {
  std::vector<float> positions;  // unit vectors; the first 12 / 42 / 162 are nested across levels
  std::vector<std::uint32_t> indices;
};
SphereMesh icosphere(int subdivisions);
std::vector<ProfileView> fibonacci_views(std::uint32_t count);
// The sample directions bounds measure: the 162 vertices of icosphere(2), as make_view frames them.
std::vector<ProfileView> bound_sample_views();
// Index of the view in `views` whose direction is nearest to unit vector d (the runtime's lookup).
std::size_t nearest_view(const std::vector<ProfileView>& views, const float* d);
// The cells of the views `kept` (indices into `views`) among the directions of `views`: for each
// kept view, the directions nearer to it than to any other kept view, or within 2 degrees of that
// (a direction near a border counts for both cells), in increasing order.
std::vector<std::vector<std::size_t>> view_cells(const std::vector<ProfileView>& views,
                                                 const std::vector<std::size_t>& kept);
// Lost contrast `lost` [T B] measured in view `from`'s image frame, read in view `to`'s frame:
// out[t B + b] = the larger of the two orientations of `from` nearest to `to`'s orientation t
// (orientations uniform over [0, 180), as orientation_angles()). Directions may differ (the roll
// is taken after carrying `to`'s up onto `from`'s image plane); out is max-accumulated.
void max_in_frame(const float* lost, const ProfileView& from, const ProfileView& to, std::size_t orientations,
                  std::size_t bands, float* out);

}  // namespace acuity::spectra
