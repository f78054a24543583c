#pragma once
// acuity/sim/detection.hpp — the judge: how visible the difference between two renders of one view
// is, by a detection model of its own (issue 47 item 5; docs/design.md section 9), not by the rule's
// chain. The judged decisions of `acuity simulate`, `acuity demo` and the sampled runs use it.
//
// The difference level - reference goes through the snapshot analyzer (spectra::LostContrast: octave
// bands, 8 orientations, Peli's local contrast c(x) against the reference's local mean), and every
// grid point of every channel is weighed by stelaCSF's sensitivity there (models.hpp stela_csf, its
// published constants): the channel's frequency [cpd] and orientation where its loss lies (the
// analyzer's energy-weighted estimates within the band and orientation, so a carrier between two
// bands is weighed at its own frequency), the temporal frequency of that orientation under the
// object's retinal velocity, f |v . n| (v less the eyes' drift, as the runtime's stela-csf), the
// local luminance (white_luminance x the local mean), the point's own eccentricity from the gaze and
// its meridian (both eyes open: an offset at angle phi from the horizontal is nasal for one eye, so
// vis_field = 180 + phi), at unbounded area. Pooling, per band: orientations as energy at each point,
// E(x) = sqrt(sum_t (c_t S_t)^2); space by stelaCSF's own area law: R = max_x E / sqrt(1 + A_c / A)
// with A = sum_x E^2 dA / max E^2 the loss's extent [deg^2] (a Gabor patch's pi sigma^2) and A_c
// Rovamo's critical area at the band's frequency; bands by probability summation,
// score = (sum_b R_b^beta)^(1/beta), beta = kBandPooling (3.5). Bands above the display's Nyquist
// frequency are not seen. A score of 1 is "just detectable": Gabor patches at stelaCSF's threshold
// contrast read 1 within the tolerance tests/test_detection.cpp checks (its calibration table:
// `test_detection --gtest_also_run_disabled_tests --gtest_filter=*Table*`).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "acuity/models.hpp"
#include "acuity/spectra/analyze.hpp"

namespace acuity::sim {

struct DetectionSettings {
  spectra::AnalysisSettings analysis{};  // the analyzer's channels (octave bands, 8 orientations)
  double white_luminance = 100.0;        // luminance of image value 1 [cd/m^2] (the display's white)
  double nyquist_cpd = 1e30;             // the display's Nyquist frequency [cpd]: bands above are unseen
  double beta = kBandPooling;            // probability summation over bands
  ModelParams params{};                  // stelaCSF's constants and the eyes' drift [deg/s]
};

// Where the snapshot lies in the visual field, in any frame whose origin is the eye (the eyes'
// midpoint). The image is the square of side 2 radius through `centre`, perpendicular to it
// (orthographic, as spectra's renderer frames a bounding sphere): pixel (x, y) lies at centre +
// ((x + 0.5) / n * 2 - 1) radius right + (1 - (y + 0.5) / n * 2) radius up.
struct Placement {
  glm::dvec3 centre{0.0, 0.0, -1.0};  // the image's centre from the eye [m]
  glm::dvec3 right{1.0, 0.0, 0.0};    // the image's +x, unit
  glm::dvec3 up{0.0, 1.0, 0.0};       // the image's +y (rows run down), unit
  double radius = 0.01;               // half the image's side [m] (> 0)
  // Unit gaze directions (one per eye; a point's eccentricity is the smaller). None: no gaze known,
  // the gaze anywhere within no_gaze_radius_deg of view_centre (a unit direction), as the scheduler
  // assumes (SchedulerConfig::no_gaze_radius_deg): a point's gaze is the disc's nearest point to it;
  // a radius of 180 or more: every point is looked at (eccentricity 0).
  std::vector<glm::dvec3> gazes;
  glm::dvec3 view_centre{0.0, 0.0, -1.0};
  double no_gaze_radius_deg = 180.0;
  glm::dvec3 head_up{0.0, 1.0, 0.0};  // the head's up: the visual field's vertical meridian
  glm::dvec2 retinal_velocity{0.0};   // the image on the retina, along right and up [deg/s]
};

struct Detection {
  double score = 0;           // 1 = just detectable; 0 for no difference; finite
  std::vector<double> bands;  // [band] R_b, the band's pooled response
};

// One per image size and settings; detect() is thread-safe.
class Detector {
 public:
  // pixels: the images' side, a power of two >= 8. Throws std::invalid_argument otherwise.
  Detector(std::uint32_t pixels, const DetectionSettings& settings);
  const spectra::LostContrast& analyzer() const { return analyzer_; }
  const DetectionSettings& settings() const { return settings_; }

  // The reference at its placement, prepared once for several levels: its spectrum and local means,
  // every band grid's eccentricities and meridians. Throws std::invalid_argument for a radius or
  // distance that is not finite and > 0.
  struct Prepared;
  std::shared_ptr<const Prepared> prepare(const spectra::Image& reference, const Placement& placement) const;
  Detection detect(const spectra::Image& level, const Prepared& prepared) const;
  Detection detect(const spectra::Image& level, const spectra::Image& reference,
                   const Placement& placement) const;

 private:
  DetectionSettings settings_;
  spectra::LostContrast analyzer_;
};

}  // namespace acuity::sim
