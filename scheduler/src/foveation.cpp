#include "acuity/foveation.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace acuity {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

double guenter_display_radius(double width, double distance) {
  return std::atan(width / (2.0 * distance)) / kDeg;
}

double guenter_display_sharpness(double width, double distance, double pixels) {
  return std::atan(2.0 * width / (distance * pixels)) / kDeg;
}

GuenterLayers guenter_layers(double width, double distance, double pixels, double aspect, double slope,
                             int n_layers, double omega0, int grid) {
  GuenterLayers out;
  const bool valid = width > 0 && distance > 0 && pixels >= 1 && aspect > 0 && slope >= 0 && omega0 > 0 &&
                     n_layers >= 1 && n_layers <= kMaxGuenterLayers && grid >= 2 &&
                     std::isfinite(width * distance * pixels * aspect * slope * omega0);
  if (!valid) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.e_star = out.omega_star = out.work = out.display_work = out.speedup = nan;
    for (int i = 0; i < kMaxGuenterLayers; ++i)
      out.radius[i] = out.sampling[i] = out.diameter_px[i] = out.pixels[i] = nan;
    return out;
  }
  const int n = n_layers;
  out.n_layers = n;
  out.e_star = guenter_display_radius(width, distance);
  out.omega_star = guenter_display_sharpness(width, distance, pixels);
  out.display_work = aspect * pixels * pixels;

  // Candidate radii e_j = e* j / grid, j = 1 .. grid-1.
  auto radius_at = [&](int j) { return out.e_star * j / grid; };
  auto sampling_after = [&](double e) {  // Eq. 2, never finer than the display
    const double s = (slope * e + omega0) / out.omega_star;
    return s < 1.0 ? 1.0 : s;
  };
  auto inner_pixels = [&](double e, double s) {  // Eq. 3-4 for i < n
    const double d = 2.0 * (pixels / s) * std::tan(e * kDeg) * distance / width;
    return d * d;
  };
  auto outer_pixels = [&](double s) { return aspect * (pixels / s) * (pixels / s); };

  if (n == 1) {
    out.radius[0] = out.e_star;
    out.sampling[0] = 1.0;
    out.diameter_px[0] = pixels;
    out.pixels[0] = out.work = out.display_work;
    out.speedup = 1.0;
    return out;
  }

  // cost[i][j]: least work of layers 1..i+1 with layer i+1's radius at e_j; from[i][j]: its parent.
  const int m = grid;  // index 0 unused
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> cost(static_cast<size_t>(n - 1) * m, inf);
  std::vector<int> from(static_cast<size_t>(n - 1) * m, 0);
  for (int j = 1; j < m; ++j) cost[j] = inner_pixels(radius_at(j), 1.0);
  for (int i = 1; i < n - 1; ++i) {
    for (int j = i + 1; j < m; ++j) {
      double best = inf;
      int arg = 0;
      for (int k = i; k < j; ++k) {
        const double c = cost[(i - 1) * m + k] + inner_pixels(radius_at(j), sampling_after(radius_at(k)));
        if (c < best) {
          best = c;
          arg = k;
        }
      }
      cost[i * m + j] = best;
      from[i * m + j] = arg;
    }
  }
  double best = inf;
  int last = 0;
  for (int j = n - 1; j < m; ++j) {
    const double c = cost[(n - 2) * m + j] + outer_pixels(sampling_after(radius_at(j)));
    if (c < best) {
      best = c;
      last = j;
    }
  }

  // Walk back to the radii, then recompute each layer's figures.
  int idx[kMaxGuenterLayers] = {};
  idx[n - 2] = last;
  for (int i = n - 2; i > 0; --i) idx[i - 1] = from[i * m + idx[i]];
  out.work = 0;
  for (int i = 0; i < n; ++i) {
    out.sampling[i] = i == 0 ? 1.0 : sampling_after(radius_at(idx[i - 1]));
    if (i < n - 1) {
      out.radius[i] = radius_at(idx[i]);
      out.pixels[i] = inner_pixels(out.radius[i], out.sampling[i]);
      out.diameter_px[i] = std::sqrt(out.pixels[i]);
    } else {
      out.radius[i] = out.e_star;
      out.pixels[i] = outer_pixels(out.sampling[i]);
      out.diameter_px[i] = pixels / out.sampling[i];
    }
    out.work += out.pixels[i];
  }
  out.speedup = out.display_work / out.work;
  return out;
}

}  // namespace acuity
