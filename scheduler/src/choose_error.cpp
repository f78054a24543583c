// The baselines Distance (OpenSceneGraph-style) and ScreenSize (Unity-style): per object and eye,
// distance / radius against per-level thresholds set at begin_frame.
#include "geometry.hpp"

namespace acuity {

// Distance (OpenSceneGraph-style) and ScreenSize (Unity-style): the least distance / radius at which
// a level whose geometric error is error_size radii is allowed, for an eye of this focal length [px]
// (+inf: never). Distance: d >= distance_scale / tan(1 arcmin) x error. ScreenSize: error / d x
// focal <= pixel_error, so never for pixel_error < 0 (or NaN), only an error of 0 for pixel_error 0.
float Scheduler::Impl::error_threshold(float error_size, float focal_px) const {
  if (config_.rule == SelectionRule::Distance) return pre_->distance_per_error * error_size;
  const float allowed = config_.pixel_error;
  if (allowed > 0) return error_size * focal_px / allowed;
  return allowed == 0 && error_size == 0 ? 0.0f : kInf;
}

// One object (explain()): the coarsest level whose geometric error passes the rule's test.
Scheduler::Impl::Choice Scheduler::Impl::choose_by_error(ObjectId id, const Sight& s) const {
  const std::size_t at = std::size_t(profile_of_[id]) * kMaxLevels;
  float threshold[kMaxLevels];
  for (std::uint32_t k = 1; k < level_count_[profile_of_[id]]; ++k)
    threshold[k] = error_threshold(error_size_[at + k], s.focal_px);
  const std::uint8_t level = level_by_ratio(s.d / s.r, threshold, level_count_[profile_of_[id]]);
  return {level, level, 0};
}

// A block through Distance or ScreenSize: per object and eye the ratio distance / radius against
// the profile's thresholds of this frame (begin_frame).
void Scheduler::Impl::choose_by_error(std::uint32_t first, std::uint32_t n, const Block* blocks,
                                      Decisions* out) {
  const std::uint32_t count = max_level_count_;
  for (std::uint32_t j = 0; j < n; ++j) {
    const int p = profile_of_[first + j];
    if (p < 0) continue;
    const auto fallback =
        static_cast<std::uint8_t>(std::min<std::uint32_t>(config_.fallback_level, level_count_[p] - 1u));
    std::uint8_t fine = 255, flags = 0;
    for (std::uint32_t i = 0; i < eye_count_; ++i) {
      const Block& b = blocks[i];
      const std::uint8_t level =
          level_by_ratio(b.d[j] / b.r[j], &error_threshold_[i][std::size_t(p) * kMaxLevels], count);
      const Look look = b.state(j);
      fine = std::min(fine, look == Look::Ok ? level : look == Look::Inside ? std::uint8_t(0) : fallback);
      flags |= look == Look::Ok ? 0 : look == Look::Inside ? kFlagEyeInside : kFlagInvalidInput;
    }
    out->fine[j] = out->coarse[j] = fine;
    out->flags[j] = flags;
  }
  if (config_.keep_scores)  // these rules have no scores: 0
    for (std::uint32_t j = 0; j < n; ++j)
      if (profile_of_[first + j] >= 0)
        std::fill_n(&scores_[std::size_t(first + j) * kMaxLevels], level_count_[profile_of_[first + j]],
                    0.0f);
}

}  // namespace acuity
