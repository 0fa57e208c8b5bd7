// Object recognition by correspondence grouping (paper §4): SHOT descriptors with local
// reference frames, nearest-neighbour matching in descriptor space, 3D Hough voting.
// The model is described once and reused for every scene; scenes may be foveated or plain.
#pragma once

#include "core/features.h"
#include "core/foveation.h"
#include "core/parallel.h"
#include "core/types.h"
#include "core/verification.h"

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// Correspondence-grouping parameters, in metres. "scene" values apply to the scene cloud,
/// "model" values to the model cloud. The defaults are Saccade's (docs/RESULTS.md): radii fitted
/// to each model, wide supports sampled, a quick descriptor match. The radius fields hold the
/// paper's Table 1 values and are used as given only with radii_from_model off
/// (configs/paper.yaml, Paper()).
struct RecognitionOptions {
  int scene_normal_neighbors = 10;            // k_ns
  float scene_keypoint_radius_m = 0.03f;      // r_ks (plain recognition only)
  float scene_shot_radius_m = 0.02f;          // r_ss
  float scene_lrf_radius_m = 0.015f;          // r_ls
  int model_normal_neighbors = 10;            // k_nm
  float model_keypoint_radius_m = 0.01f;      // r_km
  float model_shot_radius_m = 0.02f;          // r_sm
  float model_lrf_radius_m = 0.015f;          // r_lm
  float max_descriptor_sqr_distance = 0.25f;  // d²_max: accept a match below this
  float hough_bin_m = 0.01f;                  // L_h
  int hough_threshold = 5;                    // V_h: minimum votes of an instance
  /// A correspondence stays in an instance when the instance's pose maps its model keypoint
  /// within this distance of its scene keypoint.
  float pose_inlier_threshold_m = 0.02f;
  /// Levels coarser than this (by d_k) are not described: a SHOT support of a few points is
  /// noise (PERFORMANCE.md §2). Their points still count as surface for finer levels.
  float max_described_density_m = 0.01f;
  /// On an organized scene, SHOT and LRF supports whose pixel window reaches farther than this
  /// from the keypoint (wide radii, near the camera) are sampled every few pixels down to about
  /// this window's point count: the histogram's shape is kept at a fraction of the cost. 0: use
  /// every pixel.
  int max_support_half_window_px = 8;
  /// Correspondences vote for where the model's centroid lies (paper Algorithm 5). With this
  /// set they vote for the model frame's origin instead: right for a model whose frame is
  /// centred on the object (a ball cut around its centre), where the centroid of the seen cap
  /// is off-centre and every local frame's free spin about the normal scatters its votes.
  bool vote_for_model_origin = false;
  /// Matching: a hierarchical k-means tree over the model descriptors (branching factor) and
  /// the descriptors compared per query (more: closer to exact, slower).
  int match_branching = 8;
  int match_checks = 16;
  unsigned match_seed = 42;
  /// A second hypothesis generator beside Hough voting: each match's two local frames give a
  /// whole pose, the poses most matches agree with (within pose_inlier_threshold_m) are refit
  /// on them and proposed. It finds an object whose few true matches scatter over Hough cells.
  bool consensus_grouping = true;
  int consensus_min_votes = 4;       // matches that must agree on a proposed pose
  int consensus_max_hypotheses = 8;  // proposals at most, most agreed first
  /// Hypothesis verification after grouping (ICP, surface and free-space checks, colour).
  VerificationOptions verify;
  /// Replace the radii above (keypoints, SHOT, LRF, Hough bin, pose inliers) by ones fitted to
  /// the model's size and point spacing (FitRadii), so a new object needs no hand tuning.
  bool radii_from_model = true;

  bool IsValid(std::string* error) const;
  bool operator==(const RecognitionOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const RecognitionOptions& o) const { return !(*this == o); }
  /// The keys of the `recognition` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("scene_normal_neighbors", &scene_normal_neighbors);
    a->Visit("scene_keypoint_radius_m", &scene_keypoint_radius_m);
    a->Visit("scene_shot_radius_m", &scene_shot_radius_m);
    a->Visit("scene_lrf_radius_m", &scene_lrf_radius_m);
    a->Visit("model_normal_neighbors", &model_normal_neighbors);
    a->Visit("model_keypoint_radius_m", &model_keypoint_radius_m);
    a->Visit("model_shot_radius_m", &model_shot_radius_m);
    a->Visit("model_lrf_radius_m", &model_lrf_radius_m);
    a->Visit("max_descriptor_sqr_distance", &max_descriptor_sqr_distance);
    a->Visit("hough_bin_m", &hough_bin_m);
    a->Visit("hough_threshold", &hough_threshold);
    a->Visit("pose_inlier_threshold_m", &pose_inlier_threshold_m);
    a->Visit("max_described_density_m", &max_described_density_m);
    a->Visit("max_support_half_window_px", &max_support_half_window_px);
    a->Visit("vote_for_model_origin", &vote_for_model_origin);
    a->Visit("match_branching", &match_branching);
    a->Visit("match_checks", &match_checks);
    a->Visit("match_seed", &match_seed);
    a->Visit("radii_from_model", &radii_from_model);
    a->Visit("consensus_grouping", &consensus_grouping);
    a->Visit("consensus_min_votes", &consensus_min_votes);
    a->Visit("consensus_max_hypotheses", &consensus_max_hypotheses);
    verify.Serialize(a);
  }
  /// The keys FitRadii replaces while radii_from_model is set: a file that sets them is told
  /// they are ignored.
  std::vector<std::string> IgnoredKeys() const;

  /// The paper's Table 1 as given: hand-set radii, every support pixel, and the slower, nearer
  /// exact match Saccade used before fitted radii.
  static RecognitionOptions Paper();
  /// Table 1's values were tuned for a model cut from the very frame it is searched in. A
  /// model from another capture needs wider supports (repeatable local frames from another
  /// viewpoint) and a coarser Hough grid (the residual frame error); see docs/BENCHMARKS.md.
  /// Hand-set radii, from Paper().
  static RecognitionOptions CrossCapture();
};

/// How big a model is and how finely it is sampled: what its radii must fit.
struct ModelScale {
  float size_m = 0;     // the diagonal of its bounding box
  float spacing_m = 0;  // the median distance from a point to its nearest neighbour
};

/// The scale of the model's finite points; zeros when it has fewer than two.
ModelScale MeasureModel(const Cloud& model);

/// `base` with radii fitted to a model of `scale`: a SHOT support of a sixth of the model's size
/// (enough of the object to be distinctive, little enough to survive occlusion and another
/// viewpoint) but at least eight point spacings (a histogram needs points), an LRF radius of
/// three quarters of it, model keypoints a quarter of it apart (scene keypoints of plain
/// recognition too; the fovea's come from FoveaOptions), and a Hough bin and pose tolerance of
/// half of it (the residual error of frames that wide). Other fields are kept.
RecognitionOptions FitRadii(const RecognitionOptions& base, const ModelScale& scale);

/// The options a model of `scale` is described and searched with: FitRadii(options, scale) when
/// options.radii_from_model is set, else `options` as they are.
RecognitionOptions RadiiForModel(const RecognitionOptions& options, const ModelScale& scale);

/// The model, described once: its keypoints, their frames and descriptors, and a search
/// index over the descriptors. Immutable after DescribeModel; safe to share between threads.
class ModelDescription {
 public:
  ~ModelDescription();
  ModelDescription(ModelDescription&&) noexcept;
  ModelDescription& operator=(ModelDescription&&) noexcept;

  const Cloud& cloud() const { return cloud_; }
  const Descriptors& descriptors() const { return descriptors_; }
  /// The point instances vote for, model frame, metres: the centroid of the model's points, or
  /// the origin with RecognitionOptions::vote_for_model_origin.
  const Eigen::Vector3f& centroid() const { return centroid_; }
  /// The model as hypothesis verification uses it.
  const VerificationModel& verification() const { return verification_; }
  /// Its size and point spacing: with radii_from_model, Recognize fits its radii to these.
  const ModelScale& scale() const { return scale_; }

  /// Nearest model descriptor of `shot` (kShotLength floats) within sqrt(max_sqr_distance):
  /// index into descriptors() (-1 when none is that near) and squared distance. The bound
  /// prunes the search.
  std::pair<int, float> Nearest(
      const float* shot, float max_sqr_distance = std::numeric_limits<float>::infinity()) const;

 private:
  friend std::optional<ModelDescription> DescribeModel(const Cloud&, const RecognitionOptions&,
                                                       std::string*);
  ModelDescription() = default;
  Cloud cloud_;
  Descriptors descriptors_;
  Eigen::Vector3f centroid_ = Eigen::Vector3f::Zero();
  VerificationModel verification_;
  ModelScale scale_;
  struct Index;
  std::unique_ptr<Index> index_;
  int checks_ = 0;  // set from RecognitionOptions::match_checks by DescribeModel
};

/// The centroid of the finite points, in the cloud's frame; nullopt when none is finite.
std::optional<Eigen::Vector3f> FiniteCentroid(const Cloud& cloud);

/// Describes the model (normals k_nm, uniform-sampling keypoints r_km, SHOT r_sm, LRF r_lm).
/// nullopt with `error` set when the cloud has no finite point or no describable keypoint.
std::optional<ModelDescription> DescribeModel(const Cloud& model, const RecognitionOptions& options,
                                              std::string* error);

/// What a recognition run did, for logs and benchmarks.
struct RecognitionStats {
  std::vector<std::size_t> level_points;     // kept points per level (one level when plain)
  std::vector<std::size_t> level_keypoints;  // keypoints per level
  std::size_t described = 0;                 // keypoints with a valid descriptor
  std::size_t correspondences = 0;           // matches below d²_max
  std::size_t hypotheses = 0;                // instances from grouping, before verification
  /// Milliseconds per stage: foveate, normals, keypoints, describe, match, group, verify, total.
  std::vector<std::pair<std::string, double>> stage_ms;
  std::size_t TotalPoints() const;
  std::size_t TotalKeypoints() const;
};

struct RecognitionResult {
  std::vector<Detection> instances;  // verified: best first; unverified: by votes, most first
  /// What grouping proposed before verification (by votes, most first; the same as `instances`
  /// when verification is off): for evaluations that ask where a miss was lost.
  std::vector<Detection> hypotheses;
  std::vector<Verdict> verdicts;  // verification's, one per hypothesis; empty when off
  /// Every descriptor match below d²_max as (model point index, scene point index).
  std::vector<std::pair<int, int>> correspondences;
  RecognitionStats stats;
  std::optional<FoveaGeometry> fovea;  // set when foveated
};

/// Where to look. Plain: no foveation, one keypoint radius r_ks over the whole scene.
struct SceneQuery {
  bool foveated = true;
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();  // camera frame; used when foveated
  FoveaOptions fovea;
  /// Intrinsics of an organized scene; estimated from the cloud when absent.
  std::optional<CameraIntrinsics> intrinsics;
};

/// Recognizes the model in the scene. Expected outcomes (no finite point, nothing found) are
/// values: an empty instance list, with `error` set only when the scene could not be processed.
/// Preconditions: options.IsValid(), query.fovea.IsValid().
RecognitionResult Recognize(const ModelDescription& model, const Cloud& scene,
                            const SceneQuery& query, const RecognitionOptions& options,
                            const ParallelFor& parallel_for = SerialFor,
                            std::string* error = nullptr);

/// Groups correspondences by 3D Hough voting of the model centroid (paper Algorithm 5) and
/// estimates each instance's pose from its inlying correspondences (proper rotations only).
/// `correspondences` are (model descriptor index, scene descriptor index).
std::vector<Detection> HoughGroup(const Descriptors& model, const Cloud& model_cloud,
                                  const Eigen::Vector3f& model_centroid, const Descriptors& scene,
                                  const Cloud& scene_cloud,
                                  const std::vector<std::pair<int, int>>& correspondences,
                                  const RecognitionOptions& options);

/// Groups correspondences by consensus on the poses their local frames give (see
/// RecognitionOptions::consensus_grouping); most agreed first.
std::vector<Detection> ConsensusGroup(const Descriptors& model, const Cloud& model_cloud,
                                      const Eigen::Vector3f& model_centroid,
                                      const Descriptors& scene, const Cloud& scene_cloud,
                                      const std::vector<std::pair<int, int>>& correspondences,
                                      const RecognitionOptions& options);

/// `a` and the hypotheses of `b` whose centroid is at least `min_separation_m` from all of
/// `a`'s, by votes.
std::vector<Detection> MergeHypotheses(std::vector<Detection> a, std::vector<Detection> b,
                                       float min_separation_m);

/// Translation error at a point (the model centroid) and rotation angle error, between poses.
struct PoseError {
  double translation_m = 0;
  double rotation_deg = 0;
};
PoseError ComparePoses(const Eigen::Matrix4f& estimate, const Eigen::Matrix4f& truth,
                       const Eigen::Vector3f& model_point);

}  // namespace saccade
