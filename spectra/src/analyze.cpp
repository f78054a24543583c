// Lost contrast with FFTW (single precision) and Reddy's feature frequencies. See analyze.hpp.
#include "acuity/spectra/analyze.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>

namespace acuity::spectra {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

std::mutex& planner_mutex() {  // FFTW's planner is not thread-safe; execution is
  static std::mutex m;
  return m;
}

// fftwf_malloc'd complex buffer: every execute_dft array shares the planning arrays' alignment.
struct Buffer {
  fftwf_complex* p = nullptr;
  std::size_t n = 0;
  explicit Buffer(std::size_t count)
      : p(static_cast<fftwf_complex*>(fftwf_malloc(sizeof(fftwf_complex) * count))), n(count) {
    if (!p) throw std::bad_alloc();
  }
  ~Buffer() { fftwf_free(p); }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
};

// Signed frequency of FFT index k on an m-point axis [cycles per image].
int signed_frequency(std::uint32_t k, std::uint32_t m) { return k < m / 2 ? int(k) : int(k) - int(m); }

}  // namespace

struct LostContrast::Plans {
  fftwf_plan forward = nullptr;                  // n x n
  std::map<std::uint32_t, fftwf_plan> backward;  // m x m per crop size
  std::vector<std::vector<float>> band_filter;   // [b * T + t] on the crop grid: radial x angular x 2
  std::vector<std::vector<float>> lowpass;       // [b] on the crop grid
  std::vector<std::vector<float>> log_offset;    // [b] log2(f / band centre) on the crop grid (0 at f = 0)
  std::vector<std::vector<float>> angle;         // [b] the frequency vector's angle [deg] on the crop grid
  ~Plans() {
    std::lock_guard<std::mutex> lock(planner_mutex());
    if (forward) fftwf_destroy_plan(forward);
    for (auto& [m, p] : backward) fftwf_destroy_plan(p);
  }
};

struct LostContrast::Reference {
  std::unique_ptr<Buffer> spectrum;      // n x n
  std::vector<std::vector<float>> mean;  // [b] local mean below band b, on the crop grid (floored)
};

std::vector<float> band_centres(std::uint32_t pixels, const AnalysisSettings& s) {
  std::vector<float> out;
  const float step = std::pow(2.0f, 1.0f / std::max(0.25f, s.bands_per_octave));
  for (float f = s.lowest_band; f <= 0.25f * static_cast<float>(pixels) * 1.0001f; f *= step) {
    out.push_back(f);
    if (s.bands && out.size() == s.bands) break;
  }
  return out;
}

std::vector<float> orientation_angles(const AnalysisSettings& s) {
  std::vector<float> out;
  for (std::uint32_t t = 0; t < s.orientations; ++t) out.push_back(180.0f * float(t) / float(s.orientations));
  return out;
}

LostContrast::LostContrast(std::uint32_t pixels, const AnalysisSettings& settings)
    : n_(pixels),
      settings_(settings),
      bands_(band_centres(pixels, settings)),
      spacing_(180.0f / float(std::max(1u, settings.orientations))),
      plans_(std::make_unique<Plans>()) {
  if (n_ < 8 || (n_ & (n_ - 1)) != 0)
    throw std::invalid_argument("analysis needs a power-of-two image size >= 8");
  if (settings_.orientations == 0 || bands_.empty())
    throw std::invalid_argument("analysis needs >= 1 orientation and band");
  const std::uint32_t T = settings_.orientations;
  const float width = 1.0f / settings_.bands_per_octave;  // band spacing [octaves]
  const float spacing = 180.0f / float(T);
  {
    std::lock_guard<std::mutex> lock(planner_mutex());
    Buffer a(std::size_t(n_) * n_), b(std::size_t(n_) * n_);
    plans_->forward = fftwf_plan_dft_2d(int(n_), int(n_), a.p, b.p, FFTW_FORWARD, FFTW_ESTIMATE);
    for (float f : bands_) {
      std::uint32_t m = 8;
      while (m < n_ && float(m) <= 4.0f * f * std::pow(2.0f, width - 1.0f) * 1.0001f) m *= 2;
      crop_.push_back(m);
      if (!plans_->backward.count(m)) {
        Buffer c(std::size_t(m) * m), d(std::size_t(m) * m);
        plans_->backward[m] = fftwf_plan_dft_2d(int(m), int(m), c.p, d.p, FFTW_BACKWARD, FFTW_ESTIMATE);
      }
    }
  }
  // Filters on each band's crop grid.
  for (std::size_t b = 0; b < bands_.size(); ++b) {
    const std::uint32_t m = crop_[b];
    const float log_fb = std::log2(bands_[b]);
    std::vector<float> radial(std::size_t(m) * m), angle(std::size_t(m) * m), low(std::size_t(m) * m),
        offset(std::size_t(m) * m);
    for (std::uint32_t ky = 0; ky < m; ++ky)
      for (std::uint32_t kx = 0; kx < m; ++kx) {
        const float u = float(signed_frequency(kx, m)), v = float(signed_frequency(ky, m));
        const float f = std::sqrt(u * u + v * v);
        const std::size_t i = std::size_t(ky) * m + kx;
        const float d = f > 0 ? (std::log2(f) - log_fb) / width : -1e9f;  // in band spacings
        offset[i] = f > 0 ? std::log2(f) - log_fb : 0.0f;
        radial[i] = std::abs(d) < 1.0f ? std::cos(0.5f * kPi * d) : 0.0f;
        low[i] = d <= -1.0f ? 1.0f : (d < 0.0f ? std::pow(std::cos(0.5f * kPi * (d + 1.0f)), 2.0f) : 0.0f);
        angle[i] = std::atan2(-v, u) * 180.0f / kPi;  // image y runs down; orientation is measured upwards
      }
    plans_->lowpass.push_back(std::move(low));
    plans_->log_offset.push_back(std::move(offset));
    plans_->angle.push_back(angle);
    for (std::uint32_t t = 0; t < T; ++t) {
      std::vector<float> h(std::size_t(m) * m);
      for (std::size_t i = 0; i < h.size(); ++i) {
        float delta = angle[i] - spacing * float(t);
        delta -= 360.0f * std::round(delta / 360.0f);  // (-180, 180]: one-sided, not mod 180
        const float a = std::abs(delta) < spacing ? std::cos(0.5f * kPi * delta / spacing) : 0.0f;
        h[i] = 2.0f * radial[i] * a;
      }
      plans_->band_filter.push_back(std::move(h));
    }
  }
}

LostContrast::~LostContrast() = default;

namespace {
void forward(fftwf_plan plan, const Image& image, std::uint32_t n, Buffer& out) {
  if (image.width != n || image.height != n)
    throw std::invalid_argument("image size differs from the analyzer's");
  Buffer in(std::size_t(n) * n);
  for (std::size_t i = 0; i < in.n; ++i) {
    in.p[i][0] = image.pixels[i];
    in.p[i][1] = 0.0f;
  }
  fftwf_execute_dft(plan, in.p, out.p);
}

// Copies the m x m low-frequency block of an n x n spectrum, multiplied by a filter.
void crop(const Buffer& spectrum, std::uint32_t n, std::uint32_t m, const std::vector<float>& filter,
          Buffer& out) {
  for (std::uint32_t ky = 0; ky < m; ++ky) {
    const int v = signed_frequency(ky, m);
    const std::uint32_t sy = std::uint32_t(v >= 0 ? v : v + int(n));
    for (std::uint32_t kx = 0; kx < m; ++kx) {
      const int u = signed_frequency(kx, m);
      const std::uint32_t sx = std::uint32_t(u >= 0 ? u : u + int(n));
      const float g = filter[std::size_t(ky) * m + kx];
      const fftwf_complex& s = spectrum.p[std::size_t(sy) * n + sx];
      out.p[std::size_t(ky) * m + kx][0] = g * s[0];
      out.p[std::size_t(ky) * m + kx][1] = g * s[1];
    }
  }
}
}  // namespace

std::shared_ptr<const LostContrast::Reference> LostContrast::prepare(const Image& reference) const {
  auto ref = std::make_shared<Reference>();
  ref->spectrum = std::make_unique<Buffer>(std::size_t(n_) * n_);
  forward(plans_->forward, reference, n_, *ref->spectrum);
  const float norm = 1.0f / (float(n_) * float(n_));
  for (std::size_t b = 0; b < bands_.size(); ++b) {
    const std::uint32_t m = crop_[b];
    Buffer in(std::size_t(m) * m), out(std::size_t(m) * m);
    crop(*ref->spectrum, n_, m, plans_->lowpass[b], in);
    fftwf_execute_dft(plans_->backward.at(m), in.p, out.p);
    std::vector<float> mean(std::size_t(m) * m);
    for (std::size_t i = 0; i < mean.size(); ++i)
      mean[i] = std::max(out.p[i][0] * norm, settings_.mean_floor);
    ref->mean.push_back(std::move(mean));
  }
  return ref;
}

void LostContrast::channels(const Image& level, const Reference& ref, bool position,
                            const ChannelVisitor& visit) const {
  Buffer diff(std::size_t(n_) * n_);
  forward(plans_->forward, level, n_, diff);
  for (std::size_t i = 0; i < diff.n; ++i) {  // linearity: FFT(level - reference)
    diff.p[i][0] -= ref.spectrum->p[i][0];
    diff.p[i][1] -= ref.spectrum->p[i][1];
  }
  const std::uint32_t T = settings_.orientations, B = band_count();
  const float norm = 1.0f / (float(n_) * float(n_));
  for (std::uint32_t b = 0; b < B; ++b) {
    const std::uint32_t m = crop_[b];
    Buffer in(std::size_t(m) * m), out(std::size_t(m) * m);
    const std::vector<float>& mean = ref.mean[b];
    std::vector<float> contrast(mean.size());
    for (std::uint32_t t = 0; t < T; ++t) {
      crop(diff, n_, m, plans_->band_filter[std::size_t(b) * T + t], in);
      Channel c{b, t, m, contrast.data(), mean.data(), 0.0f, 0.0f};
      if (position) {  // the filtered spectrum's energy-weighted mean position (`in`)
        double power = 0, weighted = 0, turned = 0;
        const std::vector<float>& lo = plans_->log_offset[b];
        const std::vector<float>& angle = plans_->angle[b];
        const float centre = spacing_ * float(t);
        for (std::size_t i = 0; i < lo.size(); ++i) {
          const double p = double(in.p[i][0]) * in.p[i][0] + double(in.p[i][1]) * in.p[i][1];
          if (p == 0) continue;
          float delta = angle[i] - centre;
          delta -= 360.0f * std::round(delta / 360.0f);
          power += p;
          weighted += p * lo[i];
          turned += p * delta;
        }
        c.offset = power > 0 ? float(weighted / power) : 0.0f;
        c.turn = power > 0 ? float(turned / power) / spacing_ : 0.0f;
      }
      fftwf_execute_dft(plans_->backward.at(m), in.p, out.p);
      for (std::size_t i = 0; i < mean.size(); ++i)
        contrast[i] = std::hypot(out.p[i][0], out.p[i][1]) * norm / mean[i];
      visit(c);
    }
  }
}

void LostContrast::visit(const Image& level, const Reference& ref, const ChannelVisitor& visit) const {
  channels(level, ref, true, visit);
}

std::vector<std::vector<float>> LostContrast::contrast_maps(const Image& level, const Reference& ref) const {
  const std::uint32_t B = band_count();
  std::vector<std::vector<float>> out(std::size_t(settings_.orientations) * B);
  channels(level, ref, false, [&](const Channel& c) {
    out[std::size_t(c.orientation) * B + c.band].assign(c.contrast, c.contrast + std::size_t(c.m) * c.m);
  });
  return out;
}

namespace {
// A loss's extent as a fraction of the grid (`count` points): its energy over its peak's (0: none).
float extent(double energy, double peak_energy, std::size_t count) {
  return peak_energy > 0 ? float(std::min(1.0, energy / peak_energy / double(count))) : 0.0f;
}
}  // namespace

void LostContrast::measure(const Image& level, const Reference& ref, float* result, float* area,
                           float* offset, float* turn, float* pooled, float* pooled_area) const {
  const std::uint32_t B = band_count(), T = settings_.orientations;
  std::vector<double> energy_map;  // one band's sum over orientations of c^2 (pooled)
  channels(level, ref, offset || turn, [&](const Channel& c) {
    if (pooled || pooled_area) {
      const std::size_t count = std::size_t(c.m) * c.m;
      if (c.orientation == 0) energy_map.assign(count, 0.0);
      for (std::size_t i = 0; i < count; ++i) energy_map[i] += double(c.contrast[i]) * c.contrast[i];
      if (c.orientation + 1 == T) {
        double peak = 0, sum = 0;
        for (const double e : energy_map) {
          peak = std::max(peak, e);
          sum += e;
        }
        if (pooled) pooled[c.band] = float(std::sqrt(peak));
        if (pooled_area) pooled_area[c.band] = extent(sum, peak, count);
      }
    }
    float best = 0;
    double energy = 0;
    const std::size_t count = std::size_t(c.m) * c.m, at = std::size_t(c.orientation) * B + c.band;
    for (std::size_t i = 0; i < count; ++i) {
      best = std::max(best, c.contrast[i]);
      energy += double(c.contrast[i]) * c.contrast[i];
    }
    result[at] = best;
    if (area) area[at] = extent(energy, double(best) * best, count);
    if (offset) offset[at] = c.offset;
    if (turn) turn[at] = c.turn;
  });
}

std::vector<float> LostContrast::measure(const Image& level, const Image& reference, std::vector<float>* area,
                                         std::vector<float>* offset, std::vector<float>* turn) const {
  std::vector<float> out(std::size_t(settings_.orientations) * band_count());
  for (std::vector<float>* v : {area, offset, turn})
    if (v) v->assign(out.size(), 0.0f);
  measure(level, *prepare(reference), out.data(), area ? area->data() : nullptr,
          offset ? offset->data() : nullptr, turn ? turn->data() : nullptr);
  return out;
}

// ---- Reddy's features ------------------------------------------------------------------------------

std::vector<float> reddy_features(const Image& image, const AnalysisSettings& settings, float edge_step) {
  const float n = float(image.width);
  std::vector<float> out;
  auto sample = [&](float x, float y) {  // bilinear at pixel-centre coordinates
    const float fx = std::clamp(x - 0.5f, 0.0f, n - 1.0f),
                fy = std::clamp(y - 0.5f, 0.0f, float(image.height) - 1.0f);
    const std::uint32_t x0 = std::uint32_t(fx), y0 = std::uint32_t(fy);
    const std::uint32_t x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
    const float ax = fx - float(x0), ay = fy - float(y0);
    return (1 - ay) * ((1 - ax) * image.at(x0, y0) + ax * image.at(x1, y0)) +
           ay * ((1 - ax) * image.at(x0, y1) + ax * image.at(x1, y1));
  };
  const float reach = 0.5f * n * std::sqrt(2.0f);
  std::vector<float> line;
  for (float angle : orientation_angles(settings)) {
    const float a = angle * kPi / 180.0f;
    const float dx = std::cos(a), dy = -std::sin(a);  // along the frequency vector, array coordinates
    const float px = -dy, py = dx;                    // across it
    float smallest = 0;
    for (float o = -reach; o <= reach; o += 1.0f) {
      line.clear();
      for (float s = -reach; s <= reach; s += 1.0f) {
        const float x = 0.5f * n + o * px + s * dx, y = 0.5f * float(image.height) + o * py + s * dy;
        if (x >= 0 && x <= n && y >= 0 && y <= float(image.height))
          line.push_back(sample(x, y));
        else if (!line.empty())
          break;
      }
      // Edges: maximal ramps of same-signed steps above edge_step, placed where the luminance
      // crosses the midpoint between the ramp's two ends.
      float previous_edge = -1;
      for (std::size_t i = 0; i + 1 < line.size();) {
        const float step = line[i + 1] - line[i];
        if (std::abs(step) <= edge_step) {
          ++i;
          continue;
        }
        std::size_t j = i + 1;
        while (j + 1 < line.size() && std::abs(line[j + 1] - line[j]) > edge_step &&
               (line[j + 1] - line[j]) * step > 0)
          ++j;
        const float mid = 0.5f * (line[i] + line[j]);
        float edge = float(i);
        for (std::size_t k = i; k < j; ++k)
          if ((line[k] - mid) * (line[k + 1] - mid) <= 0 && line[k + 1] != line[k]) {
            edge = float(k) + (mid - line[k]) / (line[k + 1] - line[k]);
            break;
          }
        if (previous_edge >= 0) {
          const float length = edge - previous_edge;
          if (length >= 1.5f && (smallest == 0 || length < smallest)) smallest = length;
        }
        previous_edge = edge;
        i = j;
      }
    }
    out.push_back(smallest > 0 ? n / (2.0f * smallest) : 0.0f);
  }
  return out;
}

}  // namespace acuity::spectra
