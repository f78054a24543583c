#include "acuity/sim/foveation_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <stb_easy_font.h>

namespace acuity::sim {
namespace {
constexpr double kDeg = 180.0 / std::numbers::pi;

struct Colour {
  std::uint8_t r, g, b;
};

// Pixels per shade (x * y) -> colour: 1 none, 2 blue, 4 green, 8 yellow, 16 red.
Colour rate_colour(int rx, int ry) {
  switch (rx * ry) {
    case 2:
      return {70, 130, 255};
    case 4:
      return {40, 190, 70};
    case 8:
      return {240, 200, 30};
    case 16:
      return {230, 50, 40};
    default:
      return {0, 0, 0};
  }
}

// Bias [octaves] -> a dark-blue, purple, orange, yellow ramp (0 none, 4 and more the top).
Colour bias_colour(float b) {
  const float t = std::clamp(b / 4.0f, 0.0f, 1.0f);
  const Colour stops[] = {{40, 40, 160}, {150, 50, 170}, {240, 120, 40}, {255, 230, 60}};
  const float x = t * 3.0f;
  const int i = std::min(2, static_cast<int>(x));
  const float f = x - static_cast<float>(i);
  const auto mix = [f](std::uint8_t a, std::uint8_t c) {
    return static_cast<std::uint8_t>(std::lround(a + f * (c - a)));
  };
  return {mix(stops[i].r, stops[i + 1].r), mix(stops[i].g, stops[i + 1].g), mix(stops[i].b, stops[i + 1].b)};
}

void put(RgbImage* im, int x, int y, Colour c, float alpha = 1.0f) {
  if (x < 0 || y < 0 || x >= im->width || y >= im->height) return;
  std::uint8_t* p = &im->pixels[3 * (static_cast<std::size_t>(y) * im->width + x)];
  p[0] = static_cast<std::uint8_t>(std::lround(p[0] + alpha * (c.r - p[0])));
  p[1] = static_cast<std::uint8_t>(std::lround(p[1] + alpha * (c.g - p[1])));
  p[2] = static_cast<std::uint8_t>(std::lround(p[2] + alpha * (c.b - p[2])));
}

void fill_rect(RgbImage* im, int x0, int y0, int w, int h, Colour c) {
  for (int y = y0; y < y0 + h; ++y)
    for (int x = x0; x < x0 + w; ++x) put(im, x, y, c);
}

// Text from stb_easy_font's quads, scaled by an integer factor.
void text(RgbImage* im, int x0, int y0, const std::string& s, int scale, Colour c) {
  std::vector<char> buf(s.begin(), s.end());
  buf.push_back('\0');
  std::vector<float> quads(s.size() * 400 + 64);
  const int n = stb_easy_font_print(0, 0, buf.data(), nullptr, quads.data(),
                                    static_cast<int>(quads.size() * sizeof(float)));
  for (int q = 0; q < n; ++q) {
    const float* v = &quads[static_cast<std::size_t>(q) * 16];  // 4 vertices x (x, y, z, rgba)
    const int ax = static_cast<int>(v[0]), ay = static_cast<int>(v[1]);
    const int bx = static_cast<int>(v[8]), by = static_cast<int>(v[9]);
    fill_rect(im, x0 + ax * scale, y0 + ay * scale, (bx - ax) * scale, (by - ay) * scale, c);
  }
}

// Angle between two unit vectors [deg].
double angle(const double a[3], const double b[3]) {
  return std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0)) * kDeg;
}

void direction_at(const Eye& eye, double x, double y, double d[3]) {
  const double tl = std::tan(eye.fov_deg[0] / kDeg), tr = std::tan(eye.fov_deg[1] / kDeg);
  const double tu = std::tan(eye.fov_deg[2] / kDeg), td = std::tan(eye.fov_deg[3] / kDeg);
  d[0] = tl + x / eye.viewport[0] * (tr - tl);
  d[1] = tu - y / eye.viewport[1] * (tu - td);
  d[2] = -1;
  const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + 1);
  for (int k = 0; k < 3; ++k) d[k] /= n;
}
}  // namespace

Eye display_eye(std::uint32_t width, std::uint32_t height, double hfov_deg) {
  if (width == 0 || height == 0 || !(hfov_deg > 0 && hfov_deg < 179))
    throw std::runtime_error(
        "display: width and height must be positive and the field of view in (0, 179) deg");
  Eye eye;
  const double half = std::tan(hfov_deg / 2 / kDeg);
  const double vhalf = std::atan(half * height / width) * kDeg;
  eye.fov_deg[0] = static_cast<float>(-hfov_deg / 2);
  eye.fov_deg[1] = static_cast<float>(hfov_deg / 2);
  eye.fov_deg[2] = static_cast<float>(vhalf);
  eye.fov_deg[3] = static_cast<float>(-vhalf);
  eye.viewport[0] = width;
  eye.viewport[1] = height;
  return eye;
}

Gaze gaze_toward(double yaw_deg, double pitch_deg) {
  Gaze g;
  g.valid = true;
  const double y = yaw_deg / kDeg, p = pitch_deg / kDeg;
  g.direction[0] = static_cast<float>(std::sin(y) * std::cos(p));
  g.direction[1] = static_cast<float>(std::sin(p));
  g.direction[2] = static_cast<float>(-std::cos(y) * std::cos(p));
  return g;
}

PlanResult plan_eye(const FoveationPlanner& planner, const Eye& eye, const Gaze& gaze,
                    std::uint32_t tile_px) {
  PlanResult r;
  std::uint32_t cols = 0, rows = 0;
  if (!foveation_map_size(eye, tile_px, &cols, &rows))
    throw std::runtime_error(
        "plan: the tile must be 8, 16 or 32 px and the display at most 2048 tiles across");
  r.rate.assign(2 * std::size_t(cols) * rows, 1);
  r.bias.assign(std::size_t(cols) * rows, 0.0f);
  r.maps.tile_px = tile_px;
  r.maps.capacity = cols * rows;
  r.maps.shading_rate = r.rate.data();
  r.maps.mip_bias = r.bias.data();
  r.status = plan_foveation(planner, eye, gaze, &r.maps);
  return r;
}

std::vector<Gaze> gazes_from_track(const Table& track, double fps) {
  const int t = track.column("t", true);
  const double seconds = track.rows.empty() ? 0.0 : track.rows.back()[static_cast<std::size_t>(t)];
  const std::size_t frames = static_cast<std::size_t>(std::floor(seconds * fps)) + 1;
  if (frames > 1000000) throw std::runtime_error(track.source + ": more than a million frames");
  return gazes_from(gaze_trace_from(track, fps, frames));
}

std::vector<Gaze> gazes_from(const std::vector<GazeSample>& samples) {
  std::vector<Gaze> gazes;
  gazes.reserve(samples.size());
  for (const GazeSample& s : samples) {
    Gaze g;
    for (int k = 0; k < 3; ++k) g.direction[k] = static_cast<float>(s.direction[k]);
    g.confidence = s.confidence;
    g.valid = s.confidence > 0;
    gazes.push_back(g);
  }
  return gazes;
}

TrackPlan plan_track(const FoveationPlanner& planner, const Eye& eye, const std::vector<Gaze>& gazes,
                     std::uint32_t tile_px, double fps, std::size_t shown) {
  TrackPlan out;
  out.csv = "frame,time_s,status,origin_x_px,origin_y_px,shaded_px,full_px,saved\n";
  char line[256];
  for (std::size_t f = 0; f < gazes.size(); ++f) {
    PlanResult r = plan_eye(planner, eye, gazes[f], tile_px);
    std::snprintf(line, sizeof line, "%zu,%.6f,%s,%.2f,%.2f,%.0f,%.0f,%.6f\n", f, double(f) / fps,
                  to_string(r.status), r.maps.origin_px[0], r.maps.origin_px[1], r.maps.shaded, r.maps.pixels,
                  r.saved());
    out.csv += line;
    out.total_saved += r.saved();
    if (f == shown) out.shown = std::move(r);
  }
  out.shown.maps.shading_rate = out.shown.rate.data();  // after the move
  out.shown.maps.mip_bias = out.shown.bias.data();
  return out;
}

RgbImage draw_plan(const Eye& eye, const Gaze& gaze, const PlanResult& plan, int panel_width,
                   const std::string& caption) {
  const int pw = std::max(200, panel_width);
  const int ph = static_cast<int>(std::lround(double(pw) * eye.viewport[1] / eye.viewport[0]));
  const int gap = 16, legend = 150;
  RgbImage im;
  im.width = 2 * pw + 3 * gap;
  im.height = ph + legend + 2 * gap + 30;
  im.pixels.assign(3 * static_cast<std::size_t>(im.width) * im.height, 255);
  const double sx = double(eye.viewport[0]) / pw, sy = double(eye.viewport[1]) / ph;
  const std::uint32_t T = plan.maps.tile_px, cols = plan.maps.cols;
  double o[3] = {0, 0, -1};
  const bool has_gaze = plan.status == FoveationStatus::Ok;
  if (has_gaze) {
    const double n = std::sqrt(double(gaze.direction[0]) * gaze.direction[0] +
                               double(gaze.direction[1]) * gaze.direction[1] +
                               double(gaze.direction[2]) * gaze.direction[2]);
    for (int k = 0; k < 3; ++k) o[k] = gaze.direction[k] / n;
  }
  const int top = gap + 30;
  for (int panel = 0; panel < 2; ++panel) {
    const int x0 = gap + panel * (pw + gap);
    text(&im, x0, gap, panel == 0 ? "SHADING RATE (PIXELS PER SHADE, X x Y)" : "TEXTURE MIP BIAS (OCTAVES)",
         2, {20, 20, 20});
    for (int y = 0; y < ph; ++y)
      for (int x = 0; x < pw; ++x) {
        const double px = (x + 0.5) * sx, py = (y + 0.5) * sy;
        // The frame: a grey checkerboard of 5-degree squares in tangent space.
        double d[3];
        direction_at(eye, px, py, d);
        const int cu = static_cast<int>(std::floor(std::atan(d[0] / -d[2]) * kDeg / 5.0));
        const int cv = static_cast<int>(std::floor(std::atan(d[1] / -d[2]) * kDeg / 5.0));
        const std::uint8_t g = ((cu + cv) & 1) ? 150 : 185;
        put(&im, x0 + x, top + y, {g, g, g});
        const std::size_t t = static_cast<std::size_t>(py / T) * cols + static_cast<std::size_t>(px / T);
        if (panel == 0) {
          const int rx = plan.rate[2 * t], ry = plan.rate[2 * t + 1];
          if (rx * ry > 1) put(&im, x0 + x, top + y, rate_colour(rx, ry), 0.7f);
        } else if (plan.bias[t] > 0) {
          put(&im, x0 + x, top + y, bias_colour(plan.bias[t]), 0.75f);
        }
        // Rings every 10 deg from the gaze (or from the view centre without one), one pixel wide.
        const double a = angle(d, o);
        double dr[3];
        direction_at(eye, px + sx, py, dr);
        const double step = std::max(1e-9, std::abs(angle(dr, o) - a));
        const double m = std::fmod(a, 10.0);
        if (a > 5 && m < step) put(&im, x0 + x, top + y, {255, 255, 255}, 0.9f);
      }
    // The gaze (or the view centre): a cross.
    const int gx = x0 + static_cast<int>(plan.maps.origin_px[0] / sx),
              gy = top + static_cast<int>(plan.maps.origin_px[1] / sy);
    fill_rect(&im, gx - 12, gy - 1, 25, 3, {0, 0, 0});
    fill_rect(&im, gx - 1, gy - 12, 3, 25, {0, 0, 0});
  }
  // Legends.
  const int ly = top + ph + gap;
  const struct {
    int rx, ry;
    const char* label;
  } rates[] = {{1, 1, "1X1"}, {2, 1, "2X1,1X2"}, {2, 2, "2X2"}, {4, 2, "4X2,2X4"}, {4, 4, "4X4"}};
  for (int i = 0; i < 5; ++i) {
    const int x = gap + i * (pw / 5);
    const Colour c =
        rates[i].rx * rates[i].ry == 1 ? Colour{168, 168, 168} : rate_colour(rates[i].rx, rates[i].ry);
    fill_rect(&im, x, ly, 28, 28, {20, 20, 20});
    fill_rect(&im, x + 2, ly + 2, 24, 24, c);
    text(&im, x + 34, ly + 7, rates[i].label, 2, {20, 20, 20});
  }
  const int bx = 2 * gap + pw, bw = pw - 60;
  for (int x = 0; x < bw; ++x)
    fill_rect(&im, bx + x, ly, 1, 28, bias_colour(4.0f * static_cast<float>(x) / static_cast<float>(bw)));
  for (int k = 0; k <= 4; ++k) {
    const int x = bx + k * (bw - 1) / 4;
    fill_rect(&im, x, ly + 28, 2, 8, {20, 20, 20});
    text(&im, x - 4, ly + 40, k == 4 ? "4+" : std::to_string(k), 2, {20, 20, 20});
  }
  text(&im, gap, ly + 60, "WHITE RINGS: EVERY 10 DEG FROM THE GAZE (CROSS). GREY SQUARES: 5 DEG OF THE VIEW.",
       2, {20, 20, 20});
  text(&im, gap, ly + 90, caption, 2, {20, 20, 20});
  return im;
}

std::string savings_table(const FoveationConfig& config, std::uint32_t tile_px) {
  auto planner = std::make_unique<FoveationPlanner>();
  if (init_foveation_planner(config, planner.get()) != FoveationStatus::Ok)
    throw std::runtime_error("plan: invalid configuration");
  struct Display {
    std::uint32_t w, h;
    double hfov;
    const char* name;
  };
  const Display displays[] = {{1920, 1920, 90, "1920x1920, 90 deg"},
                              {2000, 2000, 100, "2000x2000, 100 deg"},
                              {3840, 2160, 90, "3840x2160 (4K), 90 deg horizontal"}};
  std::string out;
  char line[512];
  out += "| display | gaze | shading work saved | tiles at 1x1 / coarser / 4x4 |\n|---|---|---|---|\n";
  for (const Display& d : displays) {
    const Eye eye = display_eye(d.w, d.h, d.hfov);
    Gaze none;
    const struct {
      Gaze g;
      const char* name;
    } gazes[] = {{gaze_toward(0, 0), "centred"},
                 {gaze_toward(20, 10), "20 deg right, 10 deg up"},
                 {none, "none (no-gaze disc)"}};
    for (const auto& g : gazes) {
      const PlanResult r = plan_eye(*planner, eye, g.g, tile_px);
      std::size_t full = 0, coarse = 0, finest4 = 0;
      for (std::size_t t = 0; t < r.bias.size(); ++t) {
        const int p = r.rate[2 * t] * r.rate[2 * t + 1];
        full += p == 1;
        coarse += p > 1;
        finest4 += p == 16;
      }
      const double n = double(r.bias.size());
      std::snprintf(line, sizeof line, "| %s | %s | %.1f%% | %.0f%% / %.0f%% / %.0f%% |\n", d.name, g.name,
                    100 * r.saved(), 100 * double(full) / n, 100 * double(coarse) / n,
                    100 * double(finest4) / n);
      out += line;
    }
  }
  out +=
      "\nGuenter layers for the same displays from the same model (gaze tracked, 3 layers):\n\n"
      "| display | MAR line w0 + m e [deg/cycle] | layer radii [deg] | sampling factors | pixels saved |\n"
      "|---|---|---|---|---|\n";
  for (const Display& d : displays) {
    const FoveationLayers l = foveation_layers(*planner, display_eye(d.w, d.h, d.hfov), 3);
    const GuenterLayers& g = l.layers;
    std::snprintf(line, sizeof line,
                  "| %s | %.4f + %.4f e | %.1f, %.1f, %.1f | %.2f, %.2f, %.2f | %.1f%% |\n", d.name, l.omega0,
                  l.slope, g.radius[0], g.radius[1], g.radius[2], g.sampling[0], g.sampling[1], g.sampling[2],
                  100 * (1 - 1 / g.speedup));
    out += line;
  }
  return out;
}

}  // namespace acuity::sim
