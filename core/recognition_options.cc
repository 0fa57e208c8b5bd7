#include "core/recognition_options.h"

#include "core/fail.h"

#include <cmath>

namespace saccade {
namespace {

bool PositiveFinite(float v) { return std::isfinite(v) && v > 0; }

}  // namespace

bool RecognitionOptions::IsValid(std::string* error) const {
  // Whole-number options within ranges that no arithmetic on them overflows (a half window of
  // 2^31 - 1 pixels once divided by zero).
  const struct {
    const char* name;
    int value, lo, hi;
  } counts[] = {
      {"scene_normal_neighbors", scene_normal_neighbors, 3, 1000},
      {"model_normal_neighbors", model_normal_neighbors, 3, 1000},
      {"model_views", model_views, 1, 1000},
      {"max_scene_keypoints", max_scene_keypoints, 0, 10'000'000},
      {"hough_threshold", hough_threshold, 1, 1'000'000},
      {"match_branching", match_branching, 2, 1024},
      {"match_checks", match_checks, 1, 1'000'000},
      {"max_support_half_window_px", max_support_half_window_px, 0, 1000},
      {"consensus_min_votes", consensus_min_votes, 3, 1'000'000},
      {"consensus_max_hypotheses", consensus_max_hypotheses, 1, 10'000},
  };
  for (const auto& c : counts)
    if (c.value < c.lo || c.value > c.hi)
      return Fail(error, std::string(c.name) + " must be from " + std::to_string(c.lo) + " to " +
                             std::to_string(c.hi));
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
      {"model_view_distance_m", model_view_distance_m},
  };
  for (const auto& [name, value] : radii)
    if (!PositiveFinite(value)) return Fail(error, std::string(name) + " must be finite and > 0");
  if (!std::isfinite(model_view_noise_m) || model_view_noise_m < 0)
    return Fail(error, "model_view_noise_m must be finite and >= 0");
  if (!(model_min_relief >= 0 && model_min_relief < 1))
    return Fail(error, "model_min_relief must be in [0, 1)");
  if (!std::isfinite(max_described_density_m) || max_described_density_m < 0)
    return Fail(error, "max_described_density_m must be finite and >= 0");
  if (!(min_vote_significance >= 0 && min_vote_significance <= 100))
    return Fail(error, "min_vote_significance must be from 0 to 100");
  if (!(table_keypoint_distance_m >= 0 && table_keypoint_distance_m <= 1))
    return Fail(error, "table_keypoint_distance_m must be from 0 to 1 (metres)");
  if (!(library_radius_ratio >= 1 && library_radius_ratio <= 4))
    return Fail(error, "library_radius_ratio must be from 1 to 4");
  return verify.IsValid(error);
}

RecognitionOptions RecognitionOptions::Paper() {
  RecognitionOptions o;
  o.radii_from_model = false;
  o.max_support_half_window_px = 0;
  o.match_branching = 16;
  o.match_checks = 32;
  o.table_keypoint_distance_m = 0;  // every keypoint of the frame is described
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
