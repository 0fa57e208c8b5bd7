// Scoring recognition against ground truth with the paper's rule (§5.3), and the RANSAC sphere
// fit the paper used to make that ground truth (§5.2).
#pragma once

#include "core/types.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// The outcome of one scene: a true positive when some detection lies within the threshold of
/// the true centre (several there count once); every other detection is a false positive.
struct SceneScore {
  int true_positives = 0;  // 0 or 1 (one object per scene)
  int false_positives = 0;
  float nearest_m = -1;  // distance of the nearest detection to the truth; -1 when none
};

/// Scores detections (centres in the scene frame, metres) against the true centre.
/// Precondition: threshold_m > 0.
SceneScore ScoreScene(const std::vector<Eigen::Vector3f>& detected_m,
                      const Eigen::Vector3f& truth_m, float threshold_m = 0.08f);

struct SphereFitOptions {
  float min_radius_m = 0.03f;  // spheres outside [min, max] are not considered
  float max_radius_m = 0.2f;
  float inlier_distance_m = 0.005f;  // |distance to centre - radius| below this is an inlier
  int iterations = 5000;
  /// Where the sensor was (camera frame: the origin): only sphere points facing it count.
  Eigen::Vector3f viewpoint_m = Eigen::Vector3f::Zero();
  std::uint32_t seed = 1;  // the same cloud and seed give the same sphere
  bool IsValid(std::string* error) const;
};

struct Sphere {
  Eigen::Vector3f centre_m = Eigen::Vector3f::Zero();
  float radius_m = 0;
  std::size_t inliers = 0;
};

/// RANSAC over 4-point minimal samples drawn from one cell of a grid of max_radius_m, ranked
/// on an even subset of the points, then refit on all the best sphere's inliers (algebraic, then
/// geometric least squares). nullopt when the cloud has fewer than 4 finite points or no sphere in
/// range is found.
std::optional<Sphere> FitSphere(const Cloud& cloud, const SphereFitOptions& options);

}  // namespace saccade
