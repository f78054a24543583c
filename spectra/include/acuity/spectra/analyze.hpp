#pragma once
// acuity/spectra/analyze.hpp — what a coarser level loses, per orientation and frequency band.
//
// Lost contrast (Peli 1990, vision-models.md section 7): for band b and orientation t,
//   c(x) = |(D * G_bt)(x)| / max((R * L_b)(x), mean_floor),   D = level - reference,
// G_bt a one-sided (analytic) filter: a cos window one band wide in log2 frequency times a cos
// window one orientation step wide in angle, gain 2 so a grating of amplitude A reads A; L_b the
// low-pass of everything below band b. The profile keeps max_x c(x). Frequencies are in cycles
// per image = cycles per object diameter (the snapshot frames the diameter). Windows of
// neighbouring bands (orientations) overlap by half: a grating at a band centre reads its full
// contrast there and exactly 0 one band spacing away; between two centres each reads 0.71 of it.
// Orientation t is the angle of the frequency vector from image +x (right) towards +y (up), in
// [0, 180). Images wrap around in the FFT: the object sits inside the frame with background at the
// edges, which keeps the wrap harmless (a documented limitation for objects touching the frame).
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "acuity/spectra/render.hpp"

namespace acuity::spectra {

struct AnalysisSettings {
  std::uint32_t orientations = 8;  // over [0, 180)
  float lowest_band = 2.0f;        // centre of the lowest band [cycles per diameter]
  float bands_per_octave = 1.0f;   // 1: octave bands; 2: half-octave
  std::uint32_t bands = 0;         // 0: every band whose centre is at most pixels / 4
  float mean_floor = 0.02f;        // floor of the local mean luminance (black backgrounds)
};

// Band centres [cycles per diameter] for snapshots of `pixels` across.
std::vector<float> band_centres(std::uint32_t pixels, const AnalysisSettings& settings);
// Orientations [deg].
std::vector<float> orientation_angles(const AnalysisSettings& settings);

class LostContrast {
 public:
  LostContrast(std::uint32_t pixels, const AnalysisSettings& settings);
  ~LostContrast();
  LostContrast(const LostContrast&) = delete;
  LostContrast& operator=(const LostContrast&) = delete;

  std::uint32_t band_count() const { return static_cast<std::uint32_t>(bands_.size()); }
  std::uint32_t orientation_count() const { return settings_.orientations; }
  const std::vector<float>& bands() const { return bands_; }

  // The reference's spectrum and per-band local means, computed once per view.
  struct Reference;
  std::shared_ptr<const Reference> prepare(const Image& reference) const;
  // out[t * B + b] = max over the image of the lost contrast. Thread-safe. Images must be
  // pixels x pixels. area, when given, receives the extent of each band's loss: sum over the image
  // of c(x)^2 / max c^2, as a fraction of the image (the squared diameter), in [0, 1]; 0 where
  // nothing is lost. For a Gabor patch of envelope exp(-r^2 / 2 sigma^2) whose spectrum lies within
  // the band it is pi sigma^2 / D^2, stelaCSF's area of the patch; a band narrower than the
  // stimulus's spectrum widens the envelope it sees, so the area errs large (towards sensitivity).
  // offset, when given, receives the energy-weighted mean of log2 of the frequency of each band's
  // filtered loss, minus log2 of the band's centre [octaves] (0 where nothing is lost): a grating
  // half-way between two centres reads +-1/2 of the spacing, where the filter passes 0.71 of it.
  // turn, when given, receives the same mean of the frequency vector's angle from the orientation's
  // centre, in orientation spacings (a grating half-way between two orientations: +-1/2).
  // pooled and pooled_area, when given ([B] each), receive each band's loss pooled over the
  // orientations as the eye pools them (stelaCSF's detection, sim's judge): the peak over the grid of
  // sqrt(sum_t c_t(x)^2), and that energy's extent (sum over the grid / its peak, a fraction of the
  // image as area's; 0 where nothing is lost).
  void measure(const Image& level, const Reference& reference, float* out, float* area = nullptr,
               float* offset = nullptr, float* turn = nullptr, float* pooled = nullptr,
               float* pooled_area = nullptr) const;
  // The lost contrast behind measure(), pixel by pixel: visit(channel) once per band b and
  // orientation t (bands outermost), with c(x) and the floored local mean (R * L_b)(x) of the
  // reference on band b's m x m grid (m a power of two <= pixels, the band's bandwidth: grid point
  // (i, j) samples the image at pixel (i pixels / m, j pixels / m), row 0 at the top), and the
  // channel's offset and turn as measure() gives them. The pointers are valid during the call only.
  // Thread-safe.
  struct Channel {
    std::uint32_t band, orientation, m;
    const float* contrast;  // [m * m]
    const float* mean;      // [m * m]
    float offset, turn;     // [octaves], [orientation spacings]
  };
  using ChannelVisitor = std::function<void(const Channel&)>;
  void visit(const Image& level, const Reference& reference, const ChannelVisitor& visit) const;
  // The same in one call (area, offset, turn: as above, [T * B], when given).
  std::vector<float> measure(const Image& level, const Image& reference, std::vector<float>* area = nullptr,
                             std::vector<float>* offset = nullptr, std::vector<float>* turn = nullptr) const;
  // Where the contrast is lost (visit()'s maps, kept): maps[t * B + b] is band b's lost contrast at
  // orientation t over the image, map_size(b) x map_size(b) samples (row-major, row 0 at the top; sample (r, c) lies at the
  // centre of pixel (r s, c s), s = pixels / map_size(b)), whose maximum is measure()'s value. For judges whose
  // threshold varies over the image (a cut's eccentricity). Thread-safe.
  std::vector<std::vector<float>> contrast_maps(const Image& level, const Reference& reference) const;
  std::uint32_t map_size(std::uint32_t band) const { return crop_[band]; }

 private:
  struct Plans;
  // The one loop of measure() and visit(): every channel's map, with its offset and turn when
  // `position` (else 0).
  void channels(const Image& level, const Reference& reference, bool position,
                const ChannelVisitor& visit) const;
  std::uint32_t n_;
  AnalysisSettings settings_;
  std::vector<float> bands_;
  std::vector<std::uint32_t> crop_;  // per band: the size of the cropped inverse FFT
  float spacing_;                    // between orientations [deg]
  std::unique_ptr<Plans> plans_;
};

// Reddy (section 5.2): per orientation t, the fundamental frequency of the smallest feature,
// 1 / (2 x its cross-sectional length), in cycles per diameter (image width = diameter). A feature
// is a run between two luminance edges (steps above edge_step, located at sub-pixel precision at
// the midpoint of the ramp) along lines at angle t; runs touching the image border and runs under
// 1.5 px (edge ramps) are not features. 0 when an orientation has none.
std::vector<float> reddy_features(const Image& image, const AnalysisSettings& settings,
                                  float edge_step = 0.04f);

}  // namespace acuity::spectra
