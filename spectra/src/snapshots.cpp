#include "acuity/spectra/snapshots.hpp"

#include "color.hpp"

#include <stb_image.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "acuity/file.hpp"
#include "acuity/profile.hpp"

namespace acuity::spectra {
namespace {
[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw std::runtime_error(where + ": " + what);
}

using detail::luminance;
using detail::srgb_to_linear;

constexpr std::uint32_t kMaxSnapshotPixels = 8192;

std::array<float, 3> vec3(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    fail(where, "expected [x, y, z]");
  return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
}
}  // namespace

Image load_png_luminance(const std::string& path) {
  const Blob blob = io::read_file(path);  // a regular file only: a FIFO or device is refused, not waited on
  const auto* bytes = static_cast<const unsigned char*>(blob.data());
  if (blob.size > std::size_t(INT32_MAX)) fail(path, "too large for an image");
  int w = 0, h = 0, c = 0;
  // The header first: dimensions past kMaxSnapshotPixels across are refused before decoding.
  if (!stbi_info_from_memory(bytes, int(blob.size), &w, &h, &c))
    fail(path, std::string("not a readable image: ") + stbi_failure_reason());
  if (w <= 0 || h <= 0 || w > int(kMaxSnapshotPixels) || h > int(kMaxSnapshotPixels))
    fail(path, std::to_string(w) + "x" + std::to_string(h) + " pixels; snapshots are at most " +
                   std::to_string(kMaxSnapshotPixels) + " across");
  unsigned char* data = stbi_load_from_memory(bytes, int(blob.size), &w, &h, &c, 0);
  if (!data)
    fail(path,
         std::string("not a readable image: ") + (stbi_failure_reason() ? stbi_failure_reason() : "unknown"));
  Image im;
  im.width = std::uint32_t(w);
  im.height = std::uint32_t(h);
  im.pixels.resize(std::size_t(w) * h);
  for (std::size_t i = 0; i < im.pixels.size(); ++i) {
    const unsigned char* p = data + i * std::size_t(c);
    const float r = srgb_to_linear(p[0] / 255.0f);
    im.pixels[i] = c >= 3 ? luminance(r, srgb_to_linear(p[1] / 255.0f), srgb_to_linear(p[2] / 255.0f)) : r;
  }
  stbi_image_free(data);
  return im;
}

ProfileData profile_from_snapshots(const std::string& manifest, const AnalysisSettings& settings) {
  const Blob text = io::read_file(manifest);
  nlohmann::json j;
  try {
    const char* begin = static_cast<const char*>(text.data());
    j = nlohmann::json::parse(begin, begin + text.size);
  } catch (const std::exception& e) { fail(manifest, std::string("not valid JSON: ") + e.what()); }
  const std::filesystem::path base = std::filesystem::path(manifest).parent_path();
  if (!j.contains("pixels_per_diameter") || !j["pixels_per_diameter"].is_number_unsigned())
    fail(manifest, "needs pixels_per_diameter");
  const std::uint32_t n = j["pixels_per_diameter"].get<std::uint32_t>();
  if (n < 8 || n > kMaxSnapshotPixels)
    fail(manifest, "pixels_per_diameter must be 8 .. " + std::to_string(kMaxSnapshotPixels));
  if (!j.contains("levels") || !j["levels"].is_array() || j["levels"].size() < 2)
    fail(manifest, "needs two or more levels");
  if (j["levels"].size() > kMaxLevels) fail(manifest, "more than " + std::to_string(kMaxLevels) + " levels");
  if (!j.contains("views") || !j["views"].is_array() || j["views"].empty())
    fail(manifest, "needs one or more views");
  ProfileData out;
  out.snapshot_pixels = n;
  if (j.contains("sphere")) {
    if (!j["sphere"].is_array() || j["sphere"].size() != 4)
      fail(manifest, "sphere: expected [cx, cy, cz, r]");
    for (int k = 0; k < 4; ++k) out.sphere[k] = j["sphere"][std::size_t(k)].get<float>();
  }
  for (const auto& l : j["levels"])
    out.levels.push_back({l.value("triangles", 0u), l.value("geometric_error", 0.0f)});
  const std::size_t K = out.levels.size();
  const LostContrast analyzer(n, settings);
  out.orientations = orientation_angles(settings);
  out.bands = analyzer.bands();
  const std::size_t T = out.orientations.size(), B = out.bands.size(), V = j["views"].size();
  out.lost.assign((K - 1) * V * T * B, 0.0f);
  out.detail.assign((K - 1) * V * T * B, ProfileDetail{255, 0, 0});
  out.features.assign(K * V * T, 0.0f);
  for (std::size_t v = 0; v < V; ++v) {
    const auto& view = j["views"][v];
    const std::string where = manifest + ": views[" + std::to_string(v) + "]";
    const auto d = vec3(view.value("direction", nlohmann::json()), where + ".direction");
    auto u = vec3(view.value("up", nlohmann::json()), where + ".up");
    ProfileView pv = make_view(d[0], d[1], d[2]);
    // The user's up, made orthogonal to the direction.
    const float dot = u[0] * pv.direction[0] + u[1] * pv.direction[1] + u[2] * pv.direction[2];
    float len = 0;
    for (int k = 0; k < 3; ++k) {
      u[std::size_t(k)] -= dot * pv.direction[k];
      len += u[std::size_t(k)] * u[std::size_t(k)];
    }
    if (!(len > 1e-8f)) fail(where, "up is parallel to direction");
    for (int k = 0; k < 3; ++k) pv.up[k] = u[std::size_t(k)] / std::sqrt(len);
    out.views.push_back(pv);
    if (!view.contains("images") || !view["images"].is_array() || view["images"].size() != K)
      fail(where, "needs one image per level (" + std::to_string(K) + ")");
    std::vector<Image> images;
    for (const auto& name : view["images"]) {
      // Names are relative to the manifest's folder and stay inside it.
      if (!name.is_string()) fail(where, "images: expected file names");
      const std::filesystem::path rel = std::filesystem::path(name.get<std::string>()).lexically_normal();
      if (rel.empty() || rel.is_absolute() || *rel.begin() == "..")
        fail(where, "image '" + name.get<std::string>() + "' is not inside the manifest's folder");
      const std::string path = (base / rel).string();
      images.push_back(load_png_luminance(path));
      if (images.back().width != n || images.back().height != n)
        fail(path, "is " + std::to_string(images.back().width) + "x" + std::to_string(images.back().height) +
                       ", expected " + std::to_string(n) + "x" + std::to_string(n));
    }
    const auto reference = analyzer.prepare(images[0]);
    for (std::size_t k = 0; k < K; ++k) {
      if (k > 0) {
        const std::size_t at = ((k - 1) * V + v) * T * B;
        std::vector<float> area(T * B), offset(T * B), turn(T * B);
        analyzer.measure(images[k], *reference, &out.lost[at], area.data(), offset.data(), turn.data());
        for (std::size_t i = 0; i < T * B; ++i)
          out.detail[at + i] = encode_detail(area[i], offset[i], turn[i]);
      }
      const std::vector<float> f = reddy_features(images[k], settings);
      std::copy(f.begin(), f.end(), &out.features[(k * V + v) * T]);
    }
  }
  return out;
}

}  // namespace acuity::spectra
