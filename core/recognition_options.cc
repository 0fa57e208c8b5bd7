#include "core/recognition_options.h"

#include "core/fail.h"

#include <cmath>

namespace saccade {
namespace {

bool PositiveFinite(float v) { return std::isfinite(v) && v > 0; }

}  // namespace

bool RecognitionOptions::IsValid(std::string* error) const {
  if (scene_normal_neighbors < 3) return Fail(error, "scene_normal_neighbors must be >= 3");
  if (model_normal_neighbors < 3) return Fail(error, "model_normal_neighbors must be >= 3");
  const std::pair<const char*, float> radii[] = {
      {"scene_keypoint_radius_m", scene_keypoint_radius_m},
      {"scene_shot_radius_m", scene_shot_radius_m},
      {"scene_lrf_radius_m", scene_lrf_radius_m},
      {"model_keypoint_radius_m", model_keypoint_radius_m},
      {"model_shot_radius_m", model_shot_radius_m},
      {"model_lrf_radius_m", model_lrf_radius_m},
      {"max_descriptor_sqr_distance", max_descriptor_sqr_distance},
      {"hough_bin_m", hough_bin_m},
      {"pose_inlier_threshold_m", pose_inlier_threshold_m},
  };
  for (const auto& [name, value] : radii)
    if (!PositiveFinite(value)) return Fail(error, std::string(name) + " must be finite and > 0");
  if (max_scene_keypoints < 0) return Fail(error, "max_scene_keypoints must be >= 0");
  if (!std::isfinite(max_described_density_m) || max_described_density_m < 0)
    return Fail(error, "max_described_density_m must be finite and >= 0");
  if (hough_threshold < 1) return Fail(error, "hough_threshold must be >= 1");
  if (match_branching < 2) return Fail(error, "match_branching must be >= 2");
  if (match_checks < 1) return Fail(error, "match_checks must be >= 1");
  if (max_support_half_window_px < 0) return Fail(error, "max_support_half_window_px must be >= 0");
  if (consensus_min_votes < 3) return Fail(error, "consensus_min_votes must be >= 3");
  if (consensus_max_hypotheses < 1) return Fail(error, "consensus_max_hypotheses must be >= 1");
  return verify.IsValid(error);
}

RecognitionOptions RecognitionOptions::Paper() {
  RecognitionOptions o;
  o.radii_from_model = false;
  o.max_support_half_window_px = 0;
  o.match_branching = 16;
  o.match_checks = 32;
  return o;
}

RecognitionOptions RecognitionOptions::CrossCapture() {
  RecognitionOptions o = Paper();
  o.scene_shot_radius_m = o.model_shot_radius_m = 0.04f;
  o.scene_lrf_radius_m = o.model_lrf_radius_m = 0.03f;
  o.hough_bin_m = 0.02f;
  return o;
}

std::vector<std::string> RecognitionOptions::IgnoredKeys() const {
  if (!radii_from_model) return {};
  return {"scene_keypoint_radius_m",
          "scene_shot_radius_m",
          "scene_lrf_radius_m",
          "model_keypoint_radius_m",
          "model_shot_radius_m",
          "model_lrf_radius_m",
          "hough_bin_m",
          "pose_inlier_threshold_m"};
}

}  // namespace saccade
