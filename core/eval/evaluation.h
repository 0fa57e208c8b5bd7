// Scoring recognition against ground truth with the paper's rule (§5.3), and the RANSAC sphere
// fit the paper used to make that ground truth (§5.2).
#pragma once

#include "core/types.h"
#include "core/verification.h"

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

/// A binomial proportion's 95% Wilson score interval, [low, high] in [0, 1]; [0, 1] when n is 0.
struct Interval {
  double low = 0, high = 1;
};
Interval WilsonInterval(int successes, int n, double z = 1.96);

/// The symmetric average distance of two poses of the same points (ADD-S, Hinterstoisser et al.
/// 2012): the mean, over `points` (model frame) placed by `estimate`, of the distance to the
/// nearest of the points placed by `truth`. It does not penalize a turn that maps the object
/// onto itself (a can about its axis). Metres; 0 for no points.
double SymmetricPoseDistance(const Eigen::Matrix4f& estimate, const Eigen::Matrix4f& truth,
                             const std::vector<Eigen::Vector3f>& points);

/// Where a case's true instance was lost, in the pipeline's order: the first stage that no
/// longer held it.
enum class CaseStage {
  kFound,                    // a reported instance is within the rule's distance of the truth
  kNoCorrectCorrespondence,  // fewer than 3 descriptor matches agree with the true pose
  kNoHypothesis,             // grouping proposed nothing near the truth
  kNotVerified,              // a true hypothesis ranked below verification's candidates
  kRejected,                 // verification's checks rejected every true hypothesis
  kOutranked,                // a true hypothesis passed, but a false one took its place
};
const char* CaseStageName(CaseStage s);

/// What a case's run looked like from the truth's side.
struct CaseEvidence {
  /// Matches whose scene point the true pose explains; -1 when the pipeline does not report its
  /// matches (PCL's stock stages, OpenCV's PPF).
  int correct_correspondences = 0;
  /// Verification's verdict on each hypothesis near the truth (model centre within the rule's
  /// distance), best-voted first; empty when none was near.
  std::vector<Verdict> true_hypotheses;
  bool found = false;
};

/// The stage a case was lost at (kFound when found). Correspondences count only when given a
/// true pose; without one the first stage is judged by the hypotheses.
CaseStage DiagnoseCase(const CaseEvidence& evidence, bool has_truth_pose);

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
