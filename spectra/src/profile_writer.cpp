#include "acuity/spectra/profile_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace acuity::spectra {
namespace {

template <class T>
void append(std::vector<unsigned char>& out, const T* values, std::size_t count) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(values);
  out.insert(out.end(), bytes, bytes + count * sizeof(T));
  out.resize((out.size() + 7) / 8 * 8, 0);  // every section starts 8-byte aligned
}

void require(bool ok, const std::string& what) {
  if (!ok) throw InvalidProfile("profile: " + what);
}

// For each cube-map cell, the kLookupCandidates views nearest its centre (nearest first).
std::vector<std::uint16_t> build_lookup(const std::vector<ProfileView>& views, std::uint32_t r) {
  const std::uint32_t cells = 6 * r * r;
  std::vector<std::uint16_t> lookup(std::size_t(cells) * kLookupCandidates);
  for (std::uint32_t c = 0; c < cells; ++c) {
    float d[3];
    cube_cell_center(c, r, d);
    std::uint16_t best[kLookupCandidates];
    float best_dot[kLookupCandidates];
    std::fill(best_dot, best_dot + kLookupCandidates, -2.0f);
    std::fill(best, best + kLookupCandidates, std::uint16_t(0));
    for (std::size_t v = 0; v < views.size(); ++v) {
      const float* w = views[v].direction;
      float dot = d[0] * w[0] + d[1] * w[1] + d[2] * w[2];
      auto idx = static_cast<std::uint16_t>(v);
      for (std::uint32_t i = 0; i < kLookupCandidates; ++i)  // insertion into the sorted short list
        if (dot > best_dot[i]) {
          std::swap(dot, best_dot[i]);
          std::swap(idx, best[i]);
        }
    }
    for (std::uint32_t i = 0; i < kLookupCandidates; ++i)  // fewer views than candidates: repeat
      lookup[c * kLookupCandidates + i] = best_dot[i] > -2.0f ? best[i] : best[0];
  }
  return lookup;
}

}  // namespace

ProfileView make_view(float x, float y, float z) {
  const float n = std::sqrt(x * x + y * y + z * z);
  require(n > 0 && std::isfinite(n), "view direction must be finite and non-zero");
  ProfileView v{{x / n, y / n, z / n}, {0, 1, 0}};
  if (std::abs(v.direction[1]) > 0.999f) {
    v.up[1] = 0;
    v.up[2] = 1;
  }
  const float d = v.up[0] * v.direction[0] + v.up[1] * v.direction[1] + v.up[2] * v.direction[2];
  float len = 0;
  for (int i = 0; i < 3; ++i) {
    v.up[i] -= d * v.direction[i];
    len += v.up[i] * v.up[i];
  }
  len = std::sqrt(len);
  for (float& u : v.up) u /= len;
  return v;
}

ProfileDetail encode_detail(float area, float offset_octaves, float turn) {
  ProfileDetail d;
  // 2^(-code / 8) >= area: the code is floor(-8 log2 area), clamped (NaN or 0: nothing lost, 255).
  const float code = area > 0 ? std::floor(-8.0f * std::log2(area)) : 255.0f;
  d.area_code = static_cast<std::uint8_t>(std::clamp(code == code ? code : 255.0f, 0.0f, 255.0f));
  auto signed_code = [](float x) {
    const float c = std::round(128.0f * x);
    return static_cast<std::int8_t>(std::clamp(c == c ? c : 0.0f, -127.0f, 127.0f));
  };
  d.frequency_code = signed_code(offset_octaves);
  d.orientation_code = signed_code(turn);
  return d;
}

ProfilePooled encode_pooled(float lost, float area) {
  return {lost, encode_detail(area, 0.0f, 0.0f).area_code, {0, 0, 0}};
}

Blob encode_profile(const ProfileData& data) {
  const std::size_t K = data.levels.size(), V = data.views.size(), T = data.orientations.size(),
                    B = data.bands.size();
  require(K >= 1 && K <= kMaxLevels,
          "needs 1.." + std::to_string(kMaxLevels) + " levels, has " + std::to_string(K));
  require(V >= 1 && V <= kMaxViews,
          "needs 1.." + std::to_string(kMaxViews) + " views, has " + std::to_string(V));
  require(T >= 1 && T <= kMaxOrientations, "needs 1.." + std::to_string(kMaxOrientations) + " orientations");
  require(B >= 1 && B <= kMaxBands, "needs 1.." + std::to_string(kMaxBands) + " bands");
  require(data.lost.size() == (K - 1) * V * T * B,
          "lost has " + std::to_string(data.lost.size()) +
              " values, expected (K-1) V T B = " + std::to_string((K - 1) * V * T * B));
  require(data.features.size() == K * V * T, "features has " + std::to_string(data.features.size()) +
                                                 " values, expected K V T = " + std::to_string(K * V * T));
  require(data.detail.empty() || data.detail.size() == data.lost.size(),
          "detail has " + std::to_string(data.detail.size()) +
              " entries, expected none or one per lost value (" + std::to_string(data.lost.size()) + ")");
  for (const ProfileDetail& d : data.detail)
    require(d.frequency_code != -128 && d.orientation_code != -128,
            "detail: a code -128 is invalid (-127..127)");
  require(data.pooled.empty() || data.pooled.size() == (K - 1) * V * B,
          "pooled has " + std::to_string(data.pooled.size()) +
              " entries, expected none or (K-1) V B = " + std::to_string((K - 1) * V * B));
  for (const ProfilePooled& e : data.pooled)
    require(std::isfinite(e.lost) && e.lost >= 0 && !e.zero[0] && !e.zero[1] && !e.zero[2],
            "pooled: a loss is negative or not finite, or its padding is not zero");
  const ProfileClusterData& c = data.clusters;
  const std::size_t Bc = c.bands.size();
  if (!c.empty()) {
    require(Bc >= 1 && Bc <= kMaxBands, "clusters: needs 1.." + std::to_string(kMaxBands) + " bands");
    require(c.lost.size() % Bc == 0 && c.lost.size() / Bc <= kMaxClusterGroups,
            "clusters: lost has " + std::to_string(c.lost.size()) + " values, not groups (1.." +
                std::to_string(kMaxClusterGroups) + ") x " + std::to_string(Bc) + " bands");
    require(c.window_pixels >= 1 && c.view_count >= 1, "clusters: window_pixels and view_count must be >= 1");
    const std::size_t Vc = c.view_directions.size() / 3;
    require(c.view_directions.size() % 3 == 0 && Vc <= kMaxClusterViews &&
                c.view_lost.size() == Vc * c.lost.size() && (Vc == 0 || c.view_samples >= Vc),
            "clusters: view_directions (" + std::to_string(c.view_directions.size()) +
                " values) and view_lost (" + std::to_string(c.view_lost.size()) + ") must be cells (0.." +
                std::to_string(kMaxClusterViews) + ") x 3 and cells x groups x bands, view_samples >= cells");
  }
  const bool views_section = !c.empty() && !c.view_lost.empty();
  std::uint32_t r = data.lookup_resolution;
  if (r == 0)
    r = std::clamp(static_cast<std::uint32_t>(std::ceil(std::sqrt(double(V)))) + 1, 1u, kMaxLookupResolution);
  require(r <= kMaxLookupResolution, "lookup_resolution above " + std::to_string(kMaxLookupResolution));

  ProfileMeta meta{};
  meta.level_count = static_cast<std::uint32_t>(K);
  meta.view_count = static_cast<std::uint32_t>(V);
  meta.orientation_count = static_cast<std::uint32_t>(T);
  meta.band_count = static_cast<std::uint32_t>(B);
  meta.lookup_resolution = r;
  meta.snapshot_pixels = data.snapshot_pixels;
  std::copy(data.sphere, data.sphere + 4, meta.sphere);
  const std::vector<std::uint16_t> lookup = build_lookup(data.views, r);

  // Header and table are written last, once the offsets are known.
  const std::size_t section_count = 8 + (data.detail.empty() ? 0 : 1) + (data.pooled.empty() ? 0 : 1) +
                                    (c.empty() ? 0 : 1) + (views_section ? 1 : 0);
  const std::size_t table_end = sizeof(ProfileHeader) + section_count * sizeof(ProfileSectionEntry);
  std::vector<unsigned char> body(table_end, 0);
  ProfileSectionEntry table[12] = {};
  std::size_t n = 0;
  auto section = [&](ProfileSection id, const auto* values, std::size_t count) {
    const std::size_t offset = body.size();
    append(body, values, count);
    table[n++] = {static_cast<std::uint32_t>(id), 0, offset, count * sizeof(*values)};
  };
  section(ProfileSection::Meta, &meta, 1);
  section(ProfileSection::Levels, data.levels.data(), K);
  section(ProfileSection::Views, data.views.data(), V);
  section(ProfileSection::Lookup, lookup.data(), lookup.size());
  section(ProfileSection::Orientations, data.orientations.data(), T);
  section(ProfileSection::Bands, data.bands.data(), B);
  section(ProfileSection::Lost, data.lost.data(), data.lost.size());
  section(ProfileSection::Features, data.features.data(), data.features.size());
  if (!data.detail.empty()) section(ProfileSection::Detail, data.detail.data(), data.detail.size());
  if (!data.pooled.empty()) section(ProfileSection::Pooled, data.pooled.data(), data.pooled.size());
  if (!c.empty()) {  // header, bands and loss in one section
    const ProfileClusterMeta meta_c{static_cast<std::uint32_t>(c.lost.size() / Bc),
                                    static_cast<std::uint32_t>(Bc),
                                    c.window_pixels,
                                    c.view_count,
                                    c.hierarchy_hash,
                                    {0, 0}};
    std::vector<unsigned char> bytes(sizeof meta_c + (Bc + c.lost.size()) * sizeof(float));
    std::memcpy(bytes.data(), &meta_c, sizeof meta_c);
    std::memcpy(bytes.data() + sizeof meta_c, c.bands.data(), Bc * sizeof(float));
    std::memcpy(bytes.data() + sizeof meta_c + Bc * sizeof(float), c.lost.data(),
                c.lost.size() * sizeof(float));
    section(ProfileSection::Clusters, bytes.data(), bytes.size());
  }
  if (views_section) {  // header, directions and loss in one section
    const ProfileClusterViewsMeta meta_v{
        static_cast<std::uint32_t>(c.view_directions.size() / 3), c.view_samples, {0, 0}};
    std::vector<unsigned char> bytes(sizeof meta_v +
                                     (c.view_directions.size() + c.view_lost.size()) * sizeof(float));
    std::memcpy(bytes.data(), &meta_v, sizeof meta_v);
    std::memcpy(bytes.data() + sizeof meta_v, c.view_directions.data(),
                c.view_directions.size() * sizeof(float));
    std::memcpy(bytes.data() + sizeof meta_v + c.view_directions.size() * sizeof(float), c.view_lost.data(),
                c.view_lost.size() * sizeof(float));
    section(ProfileSection::ClusterViews, bytes.data(), bytes.size());
  }

  ProfileHeader header{
      kProfileMagic, kProfileVersion, body.size(), static_cast<std::uint32_t>(section_count), 0, 0};
  std::memcpy(&body[0], &header, sizeof header);
  std::memcpy(&body[sizeof header], table, section_count * sizeof(ProfileSectionEntry));
  header.checksum = profile_checksum(body.data(), body.size());
  std::memcpy(&body[0], &header, sizeof header);

  Blob blob;
  blob.size = body.size();
  blob.storage.assign((blob.size + 7) / 8, 0);
  std::memcpy(blob.storage.data(), body.data(), blob.size);
  Profile check;
  ProfileError error;
  require(open_profile(blob.data(), blob.size, &check, &error) == ProfileStatus::Ok, error.message);
  return blob;
}

void write_profile(const std::string& path, const ProfileData& data) {
  const Blob blob = encode_profile(data);
  io::write_file_atomically(path, blob.data(), blob.size);
}

}  // namespace acuity::spectra
