// libFuzzer: the profile reader must reject or accept any bytes without crashing.
#include <cstdint>
#include <cstring>
#include <vector>

#include "acuity/profile.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint64_t> aligned((size + 7) / 8 + 1);
  std::memcpy(aligned.data(), data, size);
  acuity::Profile p;
  acuity::ProfileError e;
  if (acuity::open_profile(aligned.data(), size, &p, &e) == acuity::ProfileStatus::Ok) {
    volatile float sum = 0;  // a valid profile's every value is safe to read
    for (std::uint32_t k = 1; k < p.meta.level_count; ++k)
      for (std::uint32_t v = 0; v < p.meta.view_count; ++v)
        for (std::uint32_t t = 0; t < p.meta.orientation_count; ++t)
          for (std::uint32_t b = 0; b < p.meta.band_count; ++b) sum = sum + p.lost_contrast(k, v, t, b);
    if (p.detail)  // the optional Detail section: one entry per lost value, each decodable
      for (std::size_t i = 0; i < std::size_t(p.meta.level_count - 1) * p.meta.view_count *
                                      p.meta.orientation_count * p.meta.band_count;
           ++i)
        sum = sum + acuity::detail_area(p.detail[i]) + acuity::detail_frequency_octaves(p.detail[i]) +
              acuity::detail_turn(p.detail[i]);
    if (p.pooled)  // the optional Pooled section: one entry per level, view and band
      for (std::size_t i = 0; i < std::size_t(p.meta.level_count - 1) * p.meta.view_count * p.meta.band_count;
           ++i)
        sum = sum + p.pooled[i].lost + float(p.pooled[i].area_code);
    if (p.cluster_lost) {  // the optional Clusters section: every band and every group's loss
      for (std::uint32_t b = 0; b < p.clusters.band_count; ++b) sum = sum + p.cluster_bands[b];
      for (std::size_t i = 0; i < std::size_t(p.clusters.group_count) * p.clusters.band_count; ++i)
        sum = sum + p.cluster_lost[i];
    }
    if (p.cluster_view_lost) {  // the optional ClusterViews section: every direction and value
      const std::size_t Vc = p.cluster_views.view_count;
      for (std::size_t i = 0; i < 3 * Vc; ++i) sum = sum + p.cluster_view_directions[i];
      for (std::size_t i = 0; i < std::size_t(p.clusters.group_count) * Vc * p.clusters.band_count; ++i)
        sum = sum + p.cluster_view_lost[i];
    }
  }
  return 0;
}
