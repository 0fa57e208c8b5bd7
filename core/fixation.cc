#include "core/fixation.h"

#include <algorithm>

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

Eigen::Vector3f Fixation::FoveaAt(double capture_time_s, double max_horizon_s) const {
  const double dt = std::clamp(capture_time_s - time_s, 0.0, std::max(0.0, max_horizon_s));
  return fovea_m + velocity_mps * static_cast<float>(dt);
}

}  // namespace saccade
