// Renderer and analyzers against analytic answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "acuity/spectra/analyze.hpp"
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
