#include "attention/attention.h"

#include <algorithm>
#include <cmath>

namespace saccade {

const char* ModeName(AttentionMode mode) {
  switch (mode) {
    case AttentionMode::kTracking:
      return "TRACKING";
    case AttentionMode::kSearching:
      return "SEARCHING";
    case AttentionMode::kFullScan:
      return "FULL_SCAN";
  }
  return "?";
}

bool AttentionOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!std::isfinite(growth_min_m) || growth_min_m < 0) return fail("growth_min_m must be >= 0");
  if (!std::isfinite(growth_max_m) || growth_max_m < growth_min_m)
    return fail("growth_max_m must be >= growth_min_m");
  if (!std::isfinite(growth_step) || growth_step <= 0) return fail("growth_step must be > 0");
  if (multiplicative && growth_step <= 1)
    return fail("growth_step must be > 1 when multiplicative");
  return true;
}

Attention::Attention(const AttentionOptions& options, const Eigen::Vector3f& initial_fovea_m)
    : options_(options) {
  Reset(initial_fovea_m);
}

void Attention::Reset(const Eigen::Vector3f& fovea_m) {
  current_ = Fixation{};
  current_.fovea_m = fovea_m;
  current_.growth_m = options_.growth_min_m;
  current_.mode = AttentionMode::kSearching;
  current_.reason = "reset";
}

Fixation Attention::Update(std::int64_t frame_seq, double time_s,
                           const std::vector<Detection>& detections) {
  Fixation next = current_;
  next.frame_seq = frame_seq;
  next.time_s = time_s;
  if (!detections.empty()) {
    // Follow the instance nearest the previous fovea.
    int best = 0;
    for (int i = 1; i < static_cast<int>(detections.size()); ++i)
      if ((detections[i].centroid_m - current_.fovea_m).squaredNorm() <
          (detections[best].centroid_m - current_.fovea_m).squaredNorm())
        best = i;
    next.fovea_m = detections[best].centroid_m;
    next.growth_m = options_.growth_min_m;
    next.mode = AttentionMode::kTracking;
    next.target = best;
    next.reason = "detected";
  } else {
    next.target = -1;
    if (current_.mode == AttentionMode::kFullScan) {
      next.reason = "full_scan";
    } else {
      const float grown = options_.multiplicative
                              ? std::max(current_.growth_m, 0.01f) * options_.growth_step
                              : current_.growth_m + options_.growth_step;
      if (current_.growth_m >= options_.growth_max_m && options_.full_scan_fallback) {
        next.mode = AttentionMode::kFullScan;
        next.reason = "full_scan";
      } else {
        next.growth_m = std::min(grown, options_.growth_max_m);
        next.mode = AttentionMode::kSearching;
        next.reason = current_.mode == AttentionMode::kTracking ? "lost" : "grow";
      }
    }
  }
  current_ = next;
  return next;
}

}  // namespace saccade
