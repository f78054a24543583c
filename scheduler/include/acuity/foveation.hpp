#pragma once
// acuity/foveation.hpp — Guenter et al. 2012 eccentricity layers (shared/papers/guenter2012, §4.3).
// Angles in degrees; display sizes in any one length unit (cm in the paper); resolution in pixels.
// Not for the per-frame path: guenter_layers() allocates its search table.

namespace acuity {

inline constexpr int kMaxGuenterLayers = 8;

// Display angular radius e* = atan(W / (2 V)) [deg] (Eq. 6).
double guenter_display_radius(double width, double distance);
// Display sharpness w* = atan(2 W / (V D)) [deg per cycle; one cycle = two pixels] (Eq. 7).
double guenter_display_sharpness(double width, double distance, double pixels);

struct GuenterLayers {
  int n_layers = 0;                            // 0 when the input was invalid (every other field is then NaN)
  double e_star = 0;                           // display angular radius [deg]
  double omega_star = 0;                       // display sharpness [deg per cycle]
  double radius[kMaxGuenterLayers] = {};       // e_i [deg]; the outer layer's is e_star
  double sampling[kMaxGuenterLayers] = {};     // s_i >= 1: pixel size as a multiple of the display's
  double diameter_px[kMaxGuenterLayers] = {};  // D_i [layer pixels] (Eq. 3)
  double pixels[kMaxGuenterLayers] = {};       // P_i (Eq. 4)
  double work = 0;                             // P = sum P_i, weights w_i = 1 (Eq. 5)
  double display_work = 0;                     // P* = aspect D^2 (Eq. 8)
  double speedup = 0;                          // P* / P
};

// Layer radii and sampling factors minimising Eq. 5 for the MAR line slope e + omega0 (Eq. 1, 2).
// width, distance: display width W and viewing distance V (same unit); pixels: horizontal
// resolution D; aspect: height / width (<= 1); n_layers in [1, kMaxGuenterLayers].
// The radii are searched on `grid` equal steps of (0, e*): the exact minimum over that grid (the
// paper's brute force), found by dynamic programming since each term couples two neighbours only.
GuenterLayers guenter_layers(double width, double distance, double pixels, double aspect, double slope,
                             int n_layers, double omega0 = 1.0 / 48.0, int grid = 2000);

}  // namespace acuity
