#pragma once
// acuity/spectra/cluster_loss.hpp — what each group of a cluster hierarchy loses (issue 48 item 2):
// the profile's Clusters section (acuity/profile.hpp), which Scheduler::select_cut reads through
// acuity::measured_group_loss (acuity/clusters.hpp). docs/lodgen.md, "What each group loses".
//
// The measurement, per group g and view direction: the object drawn at its finest everywhere
// (the reference) against the same mesh with g's region — the finest clusters g's simplifications
// replace — drawn as the clusters g made, which is crack-free (locked borders) and differs from
// the reference only inside g's bounding sphere. Both are rendered by the snapshot renderer
// (render_snapshot: orthographic, every triangle that can reach the window, so the rest of the
// object occludes and frames g as it would in the whole image) in a square *window* around g's
// sphere, and the lost contrast per orientation and band is LostContrast's (analyze.hpp), the one
// measurement the chain profiles use. Because the window is small, the bands reach the group's own
// scale: the window's diameter is the object's diameter / 2^n, the largest such that the window's
// radius is at least `margin` x g's, so its bands of c cycles per window are bands of c 2^n cycles per
// object diameter, on one octave grid for every group. What the group loses is then stored per band
// (cycles per object diameter) as the largest over the views and orientations, what the cut reads:
//   - the window's own bands: measured;
//   - bands below its lowest: its lowest band's value x (f / f_lowest)^2 (a band-pass's response to a
//     patch smaller than its wavelength is at most the patch's integral x the kernel's peak, which
//     falls as f^2; tests/test_cluster_loss.cpp compares it with direct measurements in wider windows);
//   - bands above its finest: the larger of its finest band's value (a flat spectrum beyond it) and
//     what the groups that made its members lost there (their finer windows measured it).
// and per view cell (the profile's ClusterViews section): the same folding of the largest over the
// orientations and the measured directions in or near each of kClusterCells cells (the directions of
// the icosahedron's vertices), so the cut reads what a group loses seen from where the eye is (a
// group hidden from a whole cell loses nothing there). The Clusters section's row is the largest
// over the cells.
// Thread-safe measurement; the builder runs groups x views on oneTBB.
#include <cstdint>
#include <span>
#include <vector>

#include "acuity/clusters.hpp"
#include "acuity/spectra/analyze.hpp"
#include "acuity/spectra/profile_builder.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "acuity/spectra/render.hpp"

namespace acuity::spectra {

// A mesh with its cluster hierarchy (lodgen::ClusterHierarchy's arrays), by reference.
struct ClusterMesh {
  MeshView mesh;                           // vertices (positions, normals, texcoords); indices unused
  std::span<const std::uint32_t> indices;  // the hierarchy's: three per triangle, into mesh's vertices
  std::span<const Cluster> clusters;       // laid out as lodgen::check_cluster_hierarchy requires
  std::span<const ClusterGroup> groups;
};

inline constexpr std::uint32_t kClusterCells = 12;  // view cells per group (ClusterViews section)

struct ClusterLossSettings {
  RenderSettings render;      // pixels: across each group's window [Limit: power of two, 16 .. 4096];
                              // supersample, background, ambient; the sphere is the object's (set
                              // by the measurer: level 0's bounding_sphere, as the profile's Meta)
  AnalysisSettings analysis;  // orientations, lowest_band, bands_per_octave [Limit: an integer >= 1],
                              // mean_floor; every band up to pixels / 4 is measured (bands unused)
  std::uint32_t views = 12;   // directions per group: the first 12, 42 or 162 vertices of icosphere(2)
                              // (nested), framed by make_view [Limit: 12, 42 or 162]; the cells are
                              // read by the cut only from 162 (kMinCellSamples)
  // The loss per view cell (the profile's ClusterViews section, 12 cells x bands per group: about
  // 337 bytes per group at 7 bands) is kept only when the cut reads it, from kMinCellSamples (162)
  // directions, or when asked here (an experiment: from fewer its rows do not bound the loss).
  bool view_cells = false;
  float margin = 1.25f;  // a window's radius is at least this x its group's [Limit: >= 1]
  unsigned jobs = 0;     // worker threads; 0: all cores
};

// Renders and analyses one group's window from one view; shared by the builder and by tests'
// direct measurements at other views.
class ClusterLossMeasurer {
 public:
  // Throws std::invalid_argument for settings out of their limits, a hierarchy without groups, or a
  // mesh without extent. `mesh` and `material` are kept by reference (they must outlive it).
  ClusterLossMeasurer(const ClusterMesh& mesh, const Material& material, const ClusterLossSettings& settings);
  ~ClusterLossMeasurer();

  // The stored band grid [cycles per object diameter]: lowest_band x 2^(j / bands_per_octave).
  const std::vector<float>& bands() const { return bands_; }
  // The object's sphere (centre, radius [object units]); its diameter is what the bands are per.
  const float* sphere() const { return render_.sphere; }
  std::uint32_t window_bands() const { return analyzer_.band_count(); }  // Bw, per window
  std::uint32_t orientations() const { return analyzer_.orientation_count(); }
  // Group g's window level n (window diameter = the object's / 2^n) and the stored band of its
  // window's band 0 (its window band i is stored band first_band(g) + i).
  std::uint32_t window_level(std::uint32_t g) const { return level_[g]; }
  std::uint32_t first_band(std::uint32_t g) const { return level_[g] * per_octave_; }
  // The window's sphere of group g: its group's centre, radius = the object's / 2^level (its own
  // window level n by default).
  static constexpr std::uint32_t kOwnLevel = 0xFFFFFFFFu;
  void window(std::uint32_t g, float sphere[4], std::uint32_t level = kOwnLevel) const;

  // The whole mesh's triangles with group g's region drawn as the clusters g made (what measure()
  // renders in g's window, there culled to the clusters that reach it), and the finest mesh's.
  std::vector<std::uint32_t> coarse_indices(std::uint32_t g) const;
  std::span<const std::uint32_t> finest_indices() const;

  // Lost contrast of group g seen from `view`, [T Bw] (t * Bw + i) in its window's bands; all 0 when
  // the two images are the same (g hidden from there). `level`: a window of another level (a wider
  // one, level < window_level(g), for direct measurements of coarser bands: its band i is stored band
  // level x bands_per_octave + i). Thread-safe.
  std::vector<float> measure(std::uint32_t g, const ProfileView& view, std::uint32_t level = kOwnLevel) const;

 private:
  void append_cluster(std::vector<std::uint32_t>& out, std::uint32_t c) const;  // its triangles' indices

  ClusterMesh mesh_;
  const Material& material_;
  RenderSettings render_;
  LostContrast analyzer_;
  std::uint32_t per_octave_ = 1;
  std::vector<float> bands_;
  std::vector<std::uint32_t> level_;                // [G] window level
  std::vector<std::uint32_t> finest_;               // finest clusters' ids, 0 .. F-1
  std::vector<std::vector<std::uint32_t>> region_;  // [G] finest clusters g replaces, sorted
  std::vector<std::vector<std::uint32_t>> made_;    // [G] the clusters g made
  std::vector<float> cluster_sphere_;               // [C][4] each cluster's bounding sphere
};

struct ClusterLossReport {
  std::uint32_t groups = 0, views = 0;  // measured: groups x views windows
  std::uint32_t hidden = 0;             // of them, windows whose two images were the same
  double seconds = 0;                   // wall time
};

// Every group's loss over settings.views directions, as the profile's Clusters section stores it
// (bands, lost [G Bc], window_pixels, view_count, hierarchy_hash), and per view cell (view_directions,
// view_lost, view_samples: the ClusterViews section) when settings.views >= kMinCellSamples or
// settings.view_cells, else those empty. progress: ("windows", done, total),
// one window per group and view.
ProfileClusterData measure_cluster_loss(const ClusterMesh& mesh, const Material& material,
                                        const ClusterLossSettings& settings, const ProgressFn& progress = {},
                                        ClusterLossReport* report = nullptr);

}  // namespace acuity::spectra
