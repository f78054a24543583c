// Renderer and analyzers against analytic answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "acuity/spectra/analyze.hpp"
#include "acuity/spectra/profile_builder.hpp"
#include "acuity/spectra/profile_writer.hpp"
#include "acuity/spectra/render.hpp"
#include "mesh_fixture.hpp"

using namespace acuity;
using namespace acuity::spectra;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr std::uint32_t N = 256;

Image constant(float value) {
  Image im;
  im.width = im.height = N;
  im.pixels.assign(std::size_t(N) * N, value);
  return im;
}

// mean (1 + c cos(2 pi (u x + v y_up) / N)) with x right and y up from the image centre.
Image grating(int u, int v, float contrast, float mean = 0.5f) {
  Image im = constant(mean);
  for (std::uint32_t r = 0; r < N; ++r)
    for (std::uint32_t c = 0; c < N; ++c) {
      const double x = c, y_up = -double(r);
      im.pixels[std::size_t(r) * N + c] =
          float(mean * (1 + contrast * std::cos(2 * kPi * (u * x + v * y_up) / N)));
    }
  return im;
}

int band_of(const std::vector<float>& bands, float f) {
  for (std::size_t b = 0; b < bands.size(); ++b)
    if (std::abs(bands[b] / f - 1) < 1e-3) return int(b);
  return -1;
}
}  // namespace

TEST(LostContrast, GratingsAtBandCentres) {
  AnalysisSettings s;
  const LostContrast analyzer(N, s);
  const auto& bands = analyzer.bands();
  ASSERT_EQ(bands.size(), 6u);  // 2 .. 64 cycles per diameter
  const Image reference = constant(0.5f);
  struct Case {
    int u, v, orientation;
    float f;
  };
  for (const Case c :
       {Case{8, 0, 0, 8}, Case{32, 0, 0, 32}, Case{0, 16, 4, 16}, Case{0, 4, 4, 4}, Case{0, -64, 4, 64}}) {
    const float contrast = 0.3f;
    const std::vector<float> lost = analyzer.measure(grating(c.u, c.v, contrast), reference);
    const int b = band_of(bands, c.f);
    ASSERT_GE(b, 0);
    EXPECT_NEAR(lost[c.orientation * bands.size() + b], contrast, 0.05f * contrast) << c.u << "," << c.v;
    for (std::uint32_t t = 0; t < 8; ++t)
      for (std::size_t k = 0; k < bands.size(); ++k) {
        if (int(k) == b && int(t) == c.orientation) continue;
        EXPECT_LT(lost[t * bands.size() + k], 0.01f * contrast)
            << t << " " << k;  // another band or orientation
      }
  }
}

// A band's loss pooled over orientations as the eye pools it (the Pooled section, the area law's
// input): energy summed per point, then its peak and extent. A grating between two orientations is
// read whole (each channel passes cos(pi/2 d) of it, d its turn from the channel's centre in
// spacings: cos^2 + sin^2 = 1), a Gabor patch keeps its area pi sigma^2, and two patches of other
// orientations apart pool as the larger one, not as their energy.
TEST(LostContrast, PooledOverOrientations) {
  const LostContrast analyzer(N, AnalysisSettings{});
  const auto& bands = analyzer.bands();
  const std::size_t B = bands.size(), T = AnalysisSettings{}.orientations;
  const Image reference = constant(0.5f);
  std::vector<float> pooled(B), pooled_area(B), lost(T * B);
  const int b = band_of(bands, 32);
  {  // (31, 6) cycles across: 0.487 orientation spacings up from +x, 31.6 cycles
    analyzer.measure(grating(31, 6, 0.2f), *analyzer.prepare(reference), lost.data(), nullptr, nullptr,
                     nullptr, pooled.data(), pooled_area.data());
    const double offset = std::log2(std::hypot(31.0, 6.0) / 32);
    EXPECT_NEAR(pooled[b], 0.2 * std::cos(0.5 * kPi * offset), 0.006);
    EXPECT_GT(pooled[b], 1.3f * std::max(lost[0 * B + b], lost[1 * B + b]));  // one channel reads 0.7 of it
    EXPECT_NEAR(pooled_area[b], 1.0f, 0.02f);
  }
  auto gabor = [](Image& im, double cx, double sigma, bool vertical) {
    for (std::uint32_t r = 0; r < N; ++r)
      for (std::uint32_t c = 0; c < N; ++c) {
        const double x = c + 0.5 - cx, y = r + 0.5 - N / 2.0;
        im.pixels[std::size_t(r) * N + c] +=
            float(0.5 * 0.01 * std::exp(-(x * x + y * y) / (2 * sigma * sigma)) *
                  std::cos(2 * kPi * 32 * (vertical ? y : x) / N));
      }
  };
  {  // one Gabor, sigma = N / 6: area pi sigma^2 / D^2, the peak its contrast
    Image im = constant(0.5f);
    gabor(im, N / 2.0, N / 6.0, false);
    analyzer.measure(im, *analyzer.prepare(reference), lost.data(), nullptr, nullptr, nullptr, pooled.data(),
                     pooled_area.data());
    EXPECT_NEAR(pooled[b], 0.01f, 0.0005f);
    EXPECT_NEAR(pooled_area[b], kPi / 36.0, 0.05 * kPi / 36.0);
  }
  {  // two Gabors, sigma = N / 12, half the image apart, at right angles: each channel's peak is one
     // patch's, their energy would read sqrt 2 of it
    Image im = constant(0.5f);
    gabor(im, N / 4.0, N / 12.0, false);
    gabor(im, 3 * N / 4.0, N / 12.0, true);
    analyzer.measure(im, *analyzer.prepare(reference), lost.data(), nullptr, nullptr, nullptr, pooled.data(),
                     pooled_area.data());
    double energy = 0;
    for (std::size_t t = 0; t < T; ++t) energy += double(lost[t * B + b]) * lost[t * B + b];
    EXPECT_NEAR(pooled[b], 0.01f, 0.0005f);
    EXPECT_GT(std::sqrt(energy), 1.3 * pooled[b]);
    EXPECT_NEAR(pooled_area[b], 2 * kPi / 144.0,
                0.08 * 2 * kPi / 144.0);  // two patches' areas (the band widens them a little)
  }
  {  // nothing lost: 0
    analyzer.measure(reference, *analyzer.prepare(reference), lost.data(), nullptr, nullptr, nullptr,
                     pooled.data(), pooled_area.data());
    for (std::size_t i = 0; i < B; ++i) EXPECT_EQ(pooled[i] + pooled_area[i], 0.0f);
  }
}

// The Detail a profile keeps (issue 47): a Gabor patch's loss covers pi sigma^2 (stelaCSF's area of
// the patch) in its band, and a grating between two band centres reads its own frequency in both.
TEST(LostContrast, AreaAndFrequencyOfTheLoss) {
  const LostContrast analyzer(N, AnalysisSettings{});
  const auto& bands = analyzer.bands();
  const Image reference = constant(0.5f);
  {  // Gabor: 32 cycles across, sigma = N / 6
    Image im = constant(0.5f);
    const double sigma = N / 6.0;
    for (std::uint32_t r = 0; r < N; ++r)
      for (std::uint32_t c = 0; c < N; ++c) {
        const double x = c + 0.5 - N / 2.0, y = r + 0.5 - N / 2.0;
        im.pixels[std::size_t(r) * N + c] =
            float(0.5 * (1 + 0.01 * std::exp(-(x * x + y * y) / (2 * sigma * sigma)) *
                                 std::cos(2 * kPi * 32 * x / N)));
      }
    std::vector<float> area, offset;
    const std::vector<float> lost = analyzer.measure(im, reference, &area, &offset);
    const int b = band_of(bands, 32);
    EXPECT_NEAR(lost[b], 0.01f, 0.0005f);
    EXPECT_NEAR(area[b], kPi / 36.0, 0.03 * kPi / 36.0);  // pi sigma^2 / D^2
    EXPECT_NEAR(offset[b], 0.0f, 0.02f);
    for (std::size_t i = 0; i < area.size(); ++i) {
      EXPECT_GE(area[i], 0.0f);
      EXPECT_LE(area[i], 1.0f);
    }
  }
  {  // a grating at 8 sqrt 2 cycles: half-way between the bands at 8 and 16, read at its frequency
    const float contrast = 0.2f;
    const int u = 11;  // 11 cycles across: log2(11 / 8) = 0.46 octaves above 8
    std::vector<float> area, offset;
    const std::vector<float> lost = analyzer.measure(grating(u, 0, contrast), reference, &area, &offset);
    for (const float centre : {8.0f, 16.0f}) {
      const int b = band_of(bands, centre);
      EXPECT_NEAR(offset[b], std::log2(11.0f / centre), 0.01f) << centre;
      // the filter passes cos(pi/2 d) of it, d the offset in band spacings
      EXPECT_NEAR(lost[b], contrast * std::cos(0.5 * kPi * std::abs(std::log2(11.0 / centre))), 0.01f)
          << centre;
      EXPECT_NEAR(area[b], 1.0f, 0.02f);  // a grating fills the image
    }
  }
  {  // a grating near half-way between orientations 0 and 1 reads its angle in both: (31, 6) cycles
     // across, 10.95 deg up from +x (0.487 orientation spacings), 31.6 cycles (at the band of 32)
    const double angle = std::atan2(6.0, 31.0) * 180 / kPi / 22.5;
    std::vector<float> area, offset, turn;
    const std::vector<float> lost = analyzer.measure(grating(31, 6, 0.2f), reference, &area, &offset, &turn);
    const std::size_t B = bands.size(), b = std::size_t(band_of(bands, 32));
    EXPECT_NEAR(turn[0 * B + b], angle, 0.01);
    EXPECT_NEAR(turn[1 * B + b], angle - 1, 0.01);
    EXPECT_NEAR(offset[b], std::log2(std::hypot(31.0, 6.0) / 32), 0.01);
    EXPECT_NEAR(lost[0 * B + b], 0.2 * std::cos(0.5 * kPi * angle) * std::cos(0.5 * kPi * offset[b]), 0.005);
  }
  {  // nothing lost: 0 everywhere
    std::vector<float> area, offset, turn;
    analyzer.measure(reference, reference, &area, &offset, &turn);
    for (std::size_t i = 0; i < area.size(); ++i) EXPECT_EQ(area[i] + offset[i] + turn[i], 0.0f);
  }
}

TEST(LostContrast, DiagonalGratingWithHalfOctaveBands) {
  AnalysisSettings s;
  s.bands_per_octave = 2;  // centres 2, 2.83, 4, 5.66, 8, 11.3, ...: 11.31 = |(8, 8)|
  const LostContrast analyzer(N, s);
  const auto& bands = analyzer.bands();
  const int b = band_of(bands, float(8 * std::sqrt(2.0)));
  ASSERT_GE(b, 0);
  const std::vector<float> lost = analyzer.measure(grating(8, 8, 0.2f), constant(0.5f));
  EXPECT_NEAR(lost[2 * bands.size() + b], 0.2f, 0.01f);  // 45 deg: orientation 2 of 8
  EXPECT_LT(lost[6 * bands.size() + b], 0.002f);         // 135 deg: the other diagonal
  EXPECT_LT(lost[2 * bands.size() + b + 2], 0.002f);     // an octave up
  EXPECT_LT(lost[2 * bands.size() + b - 2], 0.002f);     // an octave down
}

TEST(LostContrast, ContrastIsRelativeToTheLocalMean) {
  // The same grating on a darker reference reads proportionally more contrast.
  const LostContrast analyzer(N, AnalysisSettings{});
  Image dark = constant(0.25f), level = grating(16, 0, 0.2f, 0.5f);
  const std::vector<float> lost = analyzer.measure(level, dark);  // difference: 0.25 + 0.1 cos
  // Band 16 sees amplitude 0.1 over a local mean of 0.25.
  EXPECT_NEAR(lost[0 * analyzer.band_count() + 3], 0.4f, 0.02f);
}

TEST(LostContrast, ZeroForIdenticalConstantAndBlackImages) {
  const LostContrast analyzer(N, AnalysisSettings{});
  const Image g = grating(8, 4, 0.4f);
  for (const Image* im : {&g}) {
    for (float x : analyzer.measure(*im, *im)) EXPECT_EQ(x, 0.0f);
  }
  for (float value : {0.0f, 0.5f, 1.0f})
    for (float x : analyzer.measure(constant(value), constant(value))) {
      EXPECT_EQ(x, 0.0f);
      EXPECT_FALSE(std::isnan(x));
    }
  // Against a black reference the floor keeps every value finite.
  for (float x : analyzer.measure(g, constant(0.0f))) EXPECT_TRUE(std::isfinite(x));
}

TEST(ReddyFeatures, BarsOfKnownWidth) {
  for (float width : {12.0f, 20.0f, 31.5f}) {
    Image im = constant(0.5f);
    // Vertical bars with fractional edges (area coverage), gaps of 2 widths.
    for (std::uint32_t r = 0; r < N; ++r)
      for (std::uint32_t c = 0; c < N; ++c) {
        float cover = 0;
        for (float start = 20.3f; start + width < N - 10; start += 3 * width) {
          const float lo = std::max(float(c), start), hi = std::min(float(c) + 1, start + width);
          cover += std::max(0.0f, hi - lo);
        }
        im.pixels[std::size_t(r) * N + c] = 0.5f + 0.4f * cover;
      }
    const std::vector<float> f = reddy_features(im, AnalysisSettings{});
    ASSERT_EQ(f.size(), 8u);
    EXPECT_NEAR(f[0], N / (2 * width), 0.05f * N / (2 * width)) << width;  // across the bars
    EXPECT_EQ(f[4], 0.0f);  // along them: every run touches the border
  }
  EXPECT_EQ(reddy_features(constant(0.3f), AnalysisSettings{})[0], 0.0f);
}

TEST(Renderer, DeterministicAndSphereSilhouette) {
  const auto sphere = acuity::testing::icosphere(5, 2.0f);
  MeshView mesh;
  mesh.positions = sphere.positions.data();
  mesh.vertex_count = sphere.positions.size() / 3;
  mesh.indices = sphere.indices.data();
  mesh.index_count = sphere.indices.size();
  mesh.normals = sphere.normals.data();
  RenderSettings rs;
  bounding_sphere(mesh, rs.sphere);
  EXPECT_NEAR(rs.sphere[3], 2.0f, 1e-5f);
  const ProfileView view = make_view(0.3f, 0.5f, 0.8f);
  const Image a = render_snapshot(mesh, Material{}, view, rs),
              b = render_snapshot(mesh, Material{}, view, rs);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)), 0);
  // The disc of radius N/2: full coverage inside R - 1, background outside R + 1.
  const double R = N / 2.0;
  int inside = 0, outside = 0;
  for (std::uint32_t y = 0; y < N; ++y)
    for (std::uint32_t x = 0; x < N; ++x) {
      const double d = std::hypot(x + 0.5 - R, y + 0.5 - R);
      const float v = a.at(x, y);
      if (d > R + 1) {
        EXPECT_EQ(v, rs.background);
        ++outside;
      }
      if (d < R - 1) {
        EXPECT_NE(v, rs.background);
        ++inside;
      }
    }
  EXPECT_GT(inside, 50000);
  EXPECT_GT(outside, 10000);
  // Headlight Lambert: the centre faces the camera, so it is the albedo's luminance.
  EXPECT_NEAR(a.at(N / 2, N / 2), 0.8f, 0.01f);
}

// ---- Profile building ----------------------------------------------------------------------------

namespace {
// A sphere chain, or a bumpy "statue" whose detail depends on the direction.
std::vector<acuity::testing::TestMesh> chain(bool bumpy) {
  std::vector<acuity::testing::TestMesh> out;
  for (int s : {5, 3, 2, 1}) {
    auto m = acuity::testing::icosphere(s);
    if (bumpy) {
      for (std::size_t i = 0; i < m.positions.size(); i += 3) {
        const float x = m.positions[i], y = m.positions[i + 1], z = m.positions[i + 2];
        const float r = 1.0f + 0.25f * std::max(0.0f, x) * std::sin(9 * y) * std::cos(7 * z);
        for (int k = 0; k < 3; ++k) m.positions[i + k] *= r;
      }
      m.normals.clear();  // flat shading shows the facets
    }
    out.push_back(std::move(m));
  }
  return out;
}
std::vector<LevelInput> inputs(const std::vector<acuity::testing::TestMesh>& meshes) {
  std::vector<LevelInput> levels;
  for (const auto& m : meshes) levels.push_back({m.view(), 0, 0.0f});
  return levels;
}
ProfileSettings small_settings() {
  ProfileSettings s;
  s.render.pixels = 128;
  s.render.supersample = 2;
  return s;
}
}  // namespace

TEST(ProfileBuilder, ASphereNeedsFewViewsAStatueMore) {
  const auto sphere = chain(false), statue = chain(true);
  ProfileReport rs, rt;
  const ProfileData ps = build_profile(inputs(sphere), Material{}, small_settings(), {}, &rs);
  const ProfileData pt = build_profile(inputs(statue), Material{}, small_settings(), {}, &rt);
  EXPECT_LE(rs.views_kept, 3u) << "sphere measured " << rs.views_measured;
  std::printf("sphere: %u of %u views kept; statue: %u of %u\n", rs.views_kept, rs.views_measured,
              rt.views_kept, rt.views_measured);
  EXPECT_GT(rt.views_kept, rs.views_kept) << "statue measured " << rt.views_measured;
  EXPECT_LE(rs.prediction_error, 0.25f);
  EXPECT_LE(rt.prediction_error, 0.25f + 1e-6f);
  EXPECT_EQ(ps.views.size(), rs.views_kept);
  // The blob is valid and as small as the object allows.
  const Blob bs = encode_profile(ps), bt = encode_profile(pt);
  Profile p;
  ASSERT_EQ(open_profile(bs.data(), bs.size, &p), ProfileStatus::Ok);
  EXPECT_EQ(p.meta.level_count, 4u);
  EXPECT_EQ(p.levels[0].triangles, sphere[0].indices.size() / 3);
  EXPECT_LT(bs.size, bt.size);
}

TEST(ProfileBuilder, StoredValuesAreTheDirectMeasurementAndThreadsDoNotMatter) {
  const auto statue = chain(true);
  ProfileSettings s = small_settings();
  s.views = 6;
  s.jobs = 1;
  s.bound_cells = false;
  const ProfileData one = build_profile(inputs(statue), Material{}, s);
  s.jobs = 2;
  std::size_t calls = 0;
  const ProfileData two =
      build_profile(inputs(statue), Material{}, s, [&](const char*, std::size_t done, std::size_t total) {
        ++calls;
        EXPECT_LE(done, total);
      });
  EXPECT_EQ(calls, 6u);
  const Blob a = encode_profile(one), b = encode_profile(two);
  ASSERT_EQ(a.size, b.size);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size), 0);
  const ProfileMeasurer measurer(inputs(statue), Material{}, s);
  const ViewMeasurement m = measurer.measure(one.views[3]);
  const std::size_t T = one.orientations.size(), B = one.bands.size();
  for (std::size_t k = 1; k < 4; ++k)
    for (std::size_t i = 0; i < T * B; ++i)
      EXPECT_EQ(one.lost[((k - 1) * 6 + 3) * T * B + i], m.lost[(k - 1) * T * B + i]);
}

TEST(ProfileBuilder, BadChains) {
  EXPECT_THROW(build_profile({}, Material{}, small_settings()), std::invalid_argument);
  const float nan_points[9] = {NAN, 0, 0, NAN, 1, 0, NAN, 0, 1};
  const std::uint32_t tri[3] = {0, 1, 2};
  LevelInput bad;
  bad.mesh.positions = nan_points;
  bad.mesh.vertex_count = 3;
  bad.mesh.indices = tri;
  bad.mesh.index_count = 3;
  EXPECT_THROW(build_profile({bad}, Material{}, small_settings()), std::invalid_argument);
}

// ---- Bounds over the cells of the runtime's nearest-view lookup ------------------------------------

namespace {
// Per band, the largest lost contrast over orientations (what a still object's decision reads).
std::vector<float> band_peaks(const float* lost, std::size_t T, std::size_t B) {
  std::vector<float> out(B, 0.0f);
  for (std::size_t t = 0; t < T; ++t)
    for (std::size_t b = 0; b < B; ++b) out[b] = std::max(out[b], lost[t * B + b]);
  return out;
}

// The statue measured directly (no builder) at every sample direction, once.
const std::vector<ViewMeasurement>& statue_at_samples() {
  static const std::vector<ViewMeasurement> out = [] {
    const auto statue = chain(true);
    const ProfileMeasurer measurer(inputs(statue), Material{}, small_settings());
    std::vector<ViewMeasurement> m;
    for (const ProfileView& v : bound_sample_views()) m.push_back(measurer.measure(v));
    return m;
  }();
  return out;
}

// The statue's profile with bounds (default settings but small snapshots), built once.
const ProfileData& statue_bounded(ProfileReport* report = nullptr) {
  static ProfileReport r;
  static const ProfileData p = build_profile(inputs(chain(true)), Material{}, small_settings(), {}, &r);
  if (report) *report = r;
  return p;
}

// Every sample direction's direct measurement is at most the profile's nearest view, per level
// and band (orientations folded: the sample's frame is not the view's).
void expect_bound_at_samples(const ProfileData& p, const char* what) {
  const auto& direct = statue_at_samples();
  const std::vector<ProfileView> samples = bound_sample_views();
  const std::size_t V = p.views.size(), T = p.orientations.size(), B = p.bands.size();
  const std::size_t K = p.levels.size();
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const std::size_t v = nearest_view(p.views, samples[s].direction);
    for (std::size_t k = 1; k < K; ++k) {
      const auto stored = band_peaks(&p.lost[((k - 1) * V + v) * T * B], T, B);
      const auto seen = band_peaks(&direct[s].lost[(k - 1) * T * B], T, B);
      for (std::size_t b = 0; b < B; ++b)
        ASSERT_GE(stored[b], seen[b])
            << what << ": sample " << s << " view " << v << " level " << k << " band " << b;
      EXPECT_LE(switching_angle(&p.lost[((k - 1) * V + v) * T * B], T, p.bands),
                direct[s].switching[k - 1] * 1.0001f)
          << what << ": sample " << s << " level " << k;
      // The Pooled entry bounds the sample under the area law: its loss L at least the sample's
      // pooled loss c, and its energy L^2 A at least c^2 a (docs/design.md section 4).
      ASSERT_EQ(p.pooled.size(), (K - 1) * V * B);
      for (std::size_t b = 0; b < B; ++b) {
        const ProfilePooled& e = p.pooled[((k - 1) * V + v) * B + b];
        const double c = direct[s].pooled[(k - 1) * B + b], a = direct[s].pooled_area[(k - 1) * B + b];
        ASSERT_GE(e.lost, c) << what << ": sample " << s << " level " << k << " band " << b;
        ASSERT_GE(double(e.lost) * e.lost * std::exp2(-0.125 * e.area_code), c * c * a * (1 - 1e-6))
            << what << ": sample " << s << " level " << k << " band " << b;
      }
    }
  }
}
}  // namespace

TEST(ProfileBounds, MaxInFrameFollowsTheRoll) {
  // Lost contrast at one orientation of `from`; `to` looks the same way with its up rolled.
  constexpr std::size_t T = 8, B = 2;
  const ProfileView from = make_view(0, 0, 1);  // up +y, right +x
  auto rolled = [&](double degrees) {           // `to`'s up at 90 + degrees in `from`'s image
    ProfileView to = from;
    const double a = (90 + degrees) * kPi / 180;
    to.up[0] = float(std::cos(a));
    to.up[1] = float(std::sin(a));
    to.up[2] = 0;
    return to;
  };
  std::vector<float> lost(T * B, 0.0f);
  lost[3 * B + 1] = 0.5f;  // orientation 3 (67.5 deg), band 1
  auto read = [&](const ProfileView& to) {
    std::vector<float> out(T * B, 0.0f);
    max_in_frame(lost.data(), from, to, T, B, out.data());
    return out;
  };
  // Same frame: unchanged.
  EXPECT_EQ(read(from), lost);
  // Rolled by one orientation step: `from`'s 67.5 deg is `to`'s 45 deg (index 2).
  std::vector<float> want(T * B, 0.0f);
  want[2 * B + 1] = 0.5f;
  EXPECT_EQ(read(rolled(22.5)), want);
  // Half a step: both neighbours carry it (the conservative reading).
  want[3 * B + 1] = 0.5f;
  EXPECT_EQ(read(rolled(11.25)), want);
  // A grating along `from`'s x (0 deg) rolled by one step reads at 180 - 22.5 deg (index 7).
  std::fill(lost.begin(), lost.end(), 0.0f);
  lost[0 * B + 0] = 0.25f;
  std::vector<float> wrap(T * B, 0.0f);
  wrap[7 * B + 0] = 0.25f;
  EXPECT_EQ(read(rolled(22.5)), wrap);
  // A direction apart from `from` still carries `to`'s up: a view tilted about its own up keeps its roll.
  ProfileView tilted = make_view(0.3f, 0, 1);
  EXPECT_EQ(read(tilted), lost);
  // Accumulates as a maximum; no frame (up along `from`'s direction): every orientation.
  ProfileView edge = from;
  edge.up[0] = 0;
  edge.up[1] = 0;
  edge.up[2] = 1;
  std::vector<float> out(T * B, 0.1f);
  max_in_frame(lost.data(), from, edge, T, B, out.data());
  for (std::size_t t = 0; t < T; ++t) {
    EXPECT_EQ(out[t * B + 0], 0.25f);
    EXPECT_EQ(out[t * B + 1], 0.1f);
  }
}

TEST(ProfileBounds, HoldAtTheSampledDirectionsInsideEveryCell) {
  const auto statue = chain(true);
  ProfileReport r;
  const ProfileData& p = statue_bounded(&r);
  std::printf("statue with bounds: %u views kept, %u directions measured, bound pessimism %.1f%%, %.1f s\n",
              r.views_kept, r.views_sampled, 100 * r.bound_pessimism, r.seconds);
  EXPECT_EQ(r.views_sampled, 162u);
  EXPECT_GE(r.bound_pessimism, 0.0f);
  expect_bound_at_samples(p, "adaptive");
  // Without bounds the same object's nearest view is optimistic at some samples: the test can fail.
  ProfileSettings own = small_settings();
  own.bound_cells = false;
  const ProfileData q = build_profile(inputs(statue), Material{}, own);
  const auto& direct = statue_at_samples();
  const std::vector<ProfileView> samples = bound_sample_views();
  std::size_t optimistic = 0;
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const std::size_t v = nearest_view(q.views, samples[s].direction);
    const std::size_t T = q.orientations.size(), B = q.bands.size();
    optimistic += switching_angle(&q.lost[v * T * B], T, q.bands) > direct[s].switching[0] * 1.0001f;
  }
  EXPECT_GT(optimistic, 0u);
}

TEST(ProfileBounds, RefinementAddsViewsWhereCellsDisagreeAndStillBounds) {
  ProfileReport plain, refined;
  statue_bounded(&plain);
  ProfileSettings s = small_settings();
  s.bound_views = 48;
  const ProfileData p = build_profile(inputs(chain(true)), Material{}, s, {}, &refined);
  std::printf("statue: %u views, pessimism %.1f%%; refined to %u views, %.1f%%\n", plain.views_kept,
              100 * plain.bound_pessimism, refined.views_kept, 100 * refined.bound_pessimism);
  EXPECT_GT(refined.views_kept, plain.views_kept);
  EXPECT_LE(refined.views_kept, 48u);
  EXPECT_LT(refined.bound_pessimism, plain.bound_pessimism);
  expect_bound_at_samples(p, "refined");
}

TEST(ProfileBounds, CellsAreCoveredBySamples) {
  // Every direction lies near a sample that its own nearest kept view's cell bounds: the median
  // direction within the covering radius of the samples (the farthest any direction is from any
  // sample), and the farthest (at cell borders) nearer than the farthest direction of a cell from
  // its view (sampling only the views would not do).
  const ProfileData& p = statue_bounded();
  const std::vector<ProfileView> samples = bound_sample_views();
  std::vector<std::size_t> cell_of(samples.size()), members(p.views.size(), 0);
  for (std::size_t s = 0; s < samples.size(); ++s)
    ++members[cell_of[s] = nearest_view(p.views, samples[s].direction)];
  auto degrees = [](const float* a, const float* b) {
    return float(std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0f, 1.0f)) * 180 / kPi);
  };
  const auto dense = acuity::testing::icosphere(4);  // 2562 directions
  float same_cell = 0, any_cell = 0, cell_radius = 0;
  std::vector<float> distances;
  for (std::size_t i = 0; i < dense.positions.size(); i += 3) {
    const float* d = &dense.positions[i];
    const float n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const float u[3] = {d[0] / n, d[1] / n, d[2] / n};
    const std::size_t cell = nearest_view(p.views, u);
    float best = 180, best_any = 180;
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const float a = degrees(u, samples[s].direction);
      best_any = std::min(best_any, a);
      if (cell_of[s] == cell) best = std::min(best, a);
    }
    same_cell = std::max(same_cell, best);
    distances.push_back(best);
    any_cell = std::max(any_cell, best_any);
    cell_radius = std::max(cell_radius, degrees(u, p.views[cell].direction));
  }
  std::sort(distances.begin(), distances.end());
  const float median = distances[distances.size() / 2];
  std::printf(
      "%zu cells: direction to the nearest sample of its cell: median %.1f deg, farthest %.1f; to any "
      "sample: "
      "farthest %.1f; to its view: farthest %.1f\n",
      p.views.size(), median, same_cell, any_cell, cell_radius);
  EXPECT_LE(median, any_cell);
  EXPECT_LT(same_cell, cell_radius);
  for (std::size_t v = 0; v < p.views.size(); ++v) EXPECT_GE(members[v], 1u) << "view " << v;
}

TEST(ProfileBounds, OneViewBoundsTheWholeSphere) {
  const auto statue = chain(true);
  ProfileSettings s = small_settings();
  s.views = 1;
  ProfileReport r;
  const ProfileData p = build_profile(inputs(statue), Material{}, s, {}, &r);
  ASSERT_EQ(p.views.size(), 1u);     // a fixed count: bounds add no views
  EXPECT_EQ(r.views_sampled, 162u);  // the one view, (0 1 0), is one of the samples
  expect_bound_at_samples(p, "one view");
  // The one view's level-1 bound is the largest over the samples, orientations folded.
  const std::size_t T = p.orientations.size(), B = p.bands.size();
  float largest = 0, stored = 0;
  for (const ViewMeasurement& m : statue_at_samples())
    for (std::size_t i = 0; i < T * B; ++i) largest = std::max(largest, m.lost[i]);
  for (std::size_t i = 0; i < T * B; ++i) stored = std::max(stored, p.lost[i]);
  const ProfileMeasurer measurer(inputs(statue), Material{}, s);
  const ViewMeasurement own = measurer.measure(p.views[0]);
  EXPECT_EQ(stored, std::max(largest, *std::max_element(own.lost.begin(), own.lost.begin() + T * B)));
}

TEST(ProfileBounds, ASphereKeepsOneView) {
  // The sphere chain's coarse levels (icospheres of 80 to 1280 triangles) differ a little with the
  // direction: the bound is the largest of them, and no cell disagrees enough to add views.
  const auto sphere = chain(false);
  ProfileReport r;
  const ProfileData p = build_profile(inputs(sphere), Material{}, small_settings(), {}, &r);
  EXPECT_EQ(p.views.size(), 1u);
  EXPECT_LE(r.bound_pessimism, 0.25f);
  const ProfileMeasurer measurer(inputs(sphere), Material{}, small_settings());
  const std::size_t T = p.orientations.size(), B = p.bands.size(), V = p.views.size();
  for (std::size_t i : {std::size_t(0), std::size_t(57), std::size_t(161)}) {  // spread over the sphere
    const ProfileView sample = bound_sample_views()[i];
    const ViewMeasurement m = measurer.measure(sample);
    const std::size_t v = nearest_view(p.views, sample.direction);
    for (std::size_t k = 1; k < p.levels.size(); ++k)
      EXPECT_LE(switching_angle(&p.lost[((k - 1) * V + v) * T * B], T, p.bands), m.switching[k - 1] * 1.0001f)
          << "sample " << i << " level " << k;
  }
}
