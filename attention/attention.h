// The attention loop of paper §3.4: the fovea jumps to the detected object; while the object
// is lost the fovea's growth factor G grows each frame until it is found again, and past G_max
// the configured fallback takes over. Pure: detections in, one Fixation per frame out.
#pragma once

#include "core/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

enum class AttentionMode { kTracking, kSearching, kFullScan };
const char* ModeName(AttentionMode mode);

/// One frame's fixation: where the next frame will be foveated, and why.
struct Fixation {
  std::int64_t frame_seq = 0;  // the frame whose detections produced this fixation
  double time_s = 0;           // that frame's capture time
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();  // camera frame
  float growth_m = 0;                                 // G, applied on every axis
  AttentionMode mode = AttentionMode::kSearching;
  int target = -1;     // index of the followed instance in the frame, -1 when none
  std::string reason;  // "detected", "lost", "grow", "full_scan", "reset"
};

struct AttentionOptions {
  float growth_min_m = 0.0f;       // G_min, used while tracking
  float growth_max_m = 1.0f;       // G_max, after which the fallback takes over
  float growth_step = 0.1f;        // metres added per lost frame, or the factor when multiplicative
  bool multiplicative = false;     // G := max(G, step_floor) * growth_step instead of G + step
  bool full_scan_fallback = true;  // past G_max: search the unfoveated frame

  bool IsValid(std::string* error) const;
};

/// Serial state machine; call Update once per frame, in frame order. Not thread-safe.
class Attention {
 public:
  Attention(const AttentionOptions& options, const Eigen::Vector3f& initial_fovea_m);

  /// Digests one frame's detections (model->scene poses, centroids in the camera frame).
  Fixation Update(std::int64_t frame_seq, double time_s, const std::vector<Detection>& detections);
  /// Forgets the target: back to searching around `fovea_m` with G_min.
  void Reset(const Eigen::Vector3f& fovea_m);
  const Fixation& current() const { return current_; }

 private:
  AttentionOptions options_;
  Fixation current_;
};

}  // namespace saccade
