// The judge's detection model (acuity/sim/detection.hpp).
#include "acuity/sim/detection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <span>
#include <stdexcept>

namespace acuity::sim {
namespace {

constexpr double kPi = 3.14159265358979323846, kDeg = 180.0 / kPi;
constexpr double kLuminanceStep = 1.0 / 8;  // the luminance table's step [octaves]

// Per grid point of one band grid: the eccentricity [deg] and the meridian's weight w in [0, 1]
// (0 horizontal: nasal for one eye; 1 vertical), stelaCSF's vis_field = 180 + 90 w.
struct Field {
  std::vector<double> eccentricity, meridian;
};

// Without a gaze, the point of the no-gaze disc (Placement; centre c, unit, radius [rad]) nearest to
// the direction d: d itself inside it, else its centre turned towards d by the radius.
glm::dvec3 no_gaze_point(const glm::dvec3& c, double radius, const glm::dvec3& d) {
  const double angle = std::atan2(glm::length(glm::cross(c, d)), glm::dot(c, d));
  if (angle <= radius) return d;
  glm::dvec3 across = d - glm::dot(d, c) * c;  // d is not c (angle > 0); opposite it, any side
  if (glm::length(across) < 1e-12)
    across = glm::cross(c, std::abs(c.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0));
  return std::cos(radius) * c + std::sin(radius) * glm::normalize(across);
}

Field field(const Placement& pl, std::uint32_t n, std::uint32_t m) {
  Field out;
  const std::size_t count = std::size_t(m) * m;
  out.eccentricity.assign(count, 0.0);
  out.meridian.assign(count, 0.0);
  const bool disc = pl.gazes.empty();  // no gaze: each point's own gaze on the no-gaze disc
  if (disc && !(pl.no_gaze_radius_deg < 180)) return out;
  const glm::dvec3 disc_centre = glm::normalize(pl.view_centre);
  const double disc_radius = std::max(pl.no_gaze_radius_deg, 0.0) / kDeg;
  for (std::uint32_t j = 0; j < m; ++j)
    for (std::uint32_t i = 0; i < m; ++i) {
      const double sx = (double(i) * n / m + 0.5) / n * 2 - 1, sy = 1 - (double(j) * n / m + 0.5) / n * 2;
      const glm::dvec3 d = glm::normalize(pl.centre + pl.radius * (sx * pl.right + sy * pl.up));
      double best = 1e300, weight = 0;
      glm::dvec3 nearest;
      std::span<const glm::dvec3> gazes = pl.gazes;
      if (disc) {
        nearest = no_gaze_point(disc_centre, disc_radius, d);
        gazes = {&nearest, 1};
      }
      for (const glm::dvec3& g : gazes) {
        const double e = std::atan2(glm::length(glm::cross(d, g)), glm::dot(d, g)) * kDeg;
        if (e >= best) continue;
        best = e;
        const glm::dvec3 off = d - glm::dot(d, g) * g;
        glm::dvec3 h = glm::cross(pl.head_up, g);
        const double hl = glm::length(h);
        if (hl < 1e-9 || glm::length(off) < 1e-12) {
          weight = 0;
          continue;
        }
        h /= hl;
        const glm::dvec3 v = glm::cross(g, h);
        weight = std::atan2(std::abs(glm::dot(off, v)), std::abs(glm::dot(off, h))) / (0.5 * kPi);
      }
      out.eccentricity[std::size_t(j) * m + i] = best;
      out.meridian[std::size_t(j) * m + i] = std::clamp(weight, 0.0, 1.0);
    }
  return out;
}

// ln S at unbounded area at the fovea, tabulated over log2 luminance from `low` in kLuminanceStep.
struct LuminanceTable {
  double low = 0;
  std::vector<double> ln_s;
  double at(double log2_l) const {
    const double u = std::clamp((log2_l - low) / kLuminanceStep, 0.0, double(ln_s.size() - 1));
    const std::size_t k = std::min(std::size_t(u), ln_s.size() - 1);
    if (k + 1 >= ln_s.size()) return ln_s.back();
    const double a = u - double(k);
    return (1 - a) * ln_s[k] + a * ln_s[k + 1];
  }
};

LuminanceTable luminance_table(double f, double omega, double low, double high, const StelaConstants& c) {
  LuminanceTable t;
  t.low = low;
  const std::size_t steps = std::size_t(std::ceil((high - low) / kLuminanceStep)) + 1;
  const double inf = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < std::max<std::size_t>(steps, 2); ++k)
    t.ln_s.push_back(std::max(  // S = 0 (e.g. a temporal frequency past both mechanisms) as e^-700
        -700.0,
        std::log(stela_csf(f, omega, std::exp2(low + kLuminanceStep * double(k)), inf, 0.0, 0.0, c))));
  return t;
}

}  // namespace

Detector::Detector(std::uint32_t pixels, const DetectionSettings& settings)
    : settings_(settings), analyzer_(pixels, settings.analysis) {
  if (!(settings_.white_luminance > 0) || !(settings_.beta >= 1) || std::isnan(settings_.nyquist_cpd))
    throw std::invalid_argument("detection needs a white luminance > 0 and beta >= 1");
}

struct Detector::Prepared {
  std::shared_ptr<const spectra::LostContrast::Reference> reference;
  Placement placement;
  std::map<std::uint32_t, Field> fields;  // per band grid's side
};

std::shared_ptr<const Detector::Prepared> Detector::prepare(const spectra::Image& reference,
                                                            const Placement& pl) const {
  const double distance = glm::length(pl.centre);
  if (!(pl.radius > 0) || !(distance > 0) || !std::isfinite(distance) || !std::isfinite(pl.radius))
    throw std::invalid_argument("detection needs an image of radius > 0 at a finite distance > 0");
  auto p = std::make_shared<Prepared>();
  p->reference = analyzer_.prepare(reference);
  p->placement = pl;
  for (std::uint32_t m = 8; m <= reference.width; m *= 2)  // every band grid's side (a power of two)
    p->fields.emplace(m, field(pl, reference.width, m));
  return p;
}

Detection Detector::detect(const spectra::Image& level, const spectra::Image& reference,
                           const Placement& placement) const {
  return detect(level, *prepare(reference, placement));
}

Detection Detector::detect(const spectra::Image& level, const Prepared& prepared) const {
  const Placement& pl = prepared.placement;
  const double distance = glm::length(pl.centre);
  const std::vector<float>& bands = analyzer_.bands();
  const std::vector<float> angles = spectra::orientation_angles(settings_.analysis);
  const double width_deg = 2 * std::atan(pl.radius / distance) * kDeg;
  const StelaConstants& sc = settings_.params.stela;
  const double inf = std::numeric_limits<double>::infinity();
  // The retinal velocity less the eyes' drift (stelaCSF's static data hold the drift), and its angle.
  const double speed = std::max(0.0, glm::length(pl.retinal_velocity) - settings_.params.drift);
  const double heading = std::atan2(pl.retinal_velocity.y, pl.retinal_velocity.x);

  struct Band {
    bool seen = false;
    const Field* field = nullptr;
    std::vector<double> log2_l;  // log2 of the local luminance
    double low = 0, high = 0;    // its range
    std::vector<double> energy;  // sum over orientations of (c S)^2
  };
  std::vector<Band> state(bands.size());
  const double spacing = 180.0 / double(std::max(1u, analyzer_.orientation_count()));
  analyzer_.visit(level, *prepared.reference, [&](const spectra::LostContrast::Channel& ch) {
    const double centre_f = double(bands[ch.band]) / width_deg;
    if (centre_f > settings_.nyquist_cpd) return;
    Band& s = state[ch.band];
    const std::size_t count = std::size_t(ch.m) * ch.m;
    if (ch.orientation == 0) {
      s.seen = true;
      s.field = &prepared.fields.at(ch.m);
      s.log2_l.resize(count);
      s.low = 1e300;
      s.high = -1e300;
      for (std::size_t i = 0; i < count; ++i) {
        s.log2_l[i] = std::log2(settings_.white_luminance * double(ch.mean[i]));
        s.low = std::min(s.low, s.log2_l[i]);
        s.high = std::max(s.high, s.log2_l[i]);
      }
      s.energy.assign(count, 0.0);
    }
    if (!s.seen) return;
    // The channel's frequency and orientation where its loss lies (the analyzer's energy-weighted
    // estimates within the band), so that a carrier between two bands is weighed at its own frequency.
    const double f = centre_f * std::exp2(double(ch.offset));
    const double angle = (double(angles[ch.orientation]) + double(ch.turn) * spacing) / kDeg;
    const double omega = f * speed * std::abs(std::cos(angle - heading));
    // Eccentricity's drop is stelaCSF's S x 10^-((d + f d_f) e), its constants interpolated between
    // the nasal and the temporal meridian by w: ln S falls linearly in e, at a slope linear in w.
    const double l0 = settings_.white_luminance;
    const double fovea = std::log(stela_csf(f, 0.0, l0, inf, 0.0, 0.0, sc));
    const double temporal = fovea - std::log(stela_csf(f, 0.0, l0, inf, 1.0, 0.0, sc));
    const double nasal = fovea - std::log(stela_csf(f, 0.0, l0, inf, 1.0, 180.0, sc));
    if (!std::isfinite(temporal) || !std::isfinite(nasal)) return;  // no sensitivity at f
    const LuminanceTable table = luminance_table(f, omega, s.low, s.high, sc);
    const Field& fd = *s.field;
    for (std::size_t i = 0; i < count; ++i) {
      if (ch.contrast[i] == 0) continue;
      const double drop = fd.eccentricity[i] * (nasal + fd.meridian[i] * (temporal - nasal));
      const double r = double(ch.contrast[i]) * std::exp(table.at(s.log2_l[i]) - drop);
      s.energy[i] += r * r;
    }
  });

  Detection out;
  double pooled = 0;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const Band& s = state[b];
    double peak = 0, sum = 0;
    for (double e : s.energy) {
      peak = std::max(peak, e);
      sum += e;
    }
    double response = 0;
    if (peak > 0) {
      const std::uint32_t m = std::uint32_t(std::lround(std::sqrt(double(s.energy.size()))));
      const double cell = width_deg / m;
      const double area = sum / peak * cell * cell;   // [deg^2]
      const double f = double(bands[b]) / width_deg;  // the area law at the band's centre
      response = std::sqrt(peak) * std::exp(-stela_log_area_penalty(f, area, sc));
    }
    out.bands.push_back(response);
    pooled += std::pow(response, settings_.beta);
  }
  out.score = std::pow(pooled, 1.0 / settings_.beta);
  return out;
}

}  // namespace acuity::sim
