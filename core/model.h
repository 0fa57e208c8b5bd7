// A model described once for recognition: its scale, the radii fitted to it, its keypoints'
// local frames and SHOT descriptors, and the search index over them.
#pragma once

#include "core/features.h"
#include "core/recognition_options.h"
#include "core/types.h"
#include "core/verification.h"

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// How big a model is and how finely it is sampled: what its radii must fit.
struct ModelScale {
  float size_m = 0;     // the diagonal of its bounding box
  float spacing_m = 0;  // the median distance from a point to its nearest neighbour
  /// The SHOT radius FitRadii gives, when set (a library's grid, OnRadiusGrid); 0: fitted from
  /// the size and spacing.
  float shot_radius_m = 0;
};

/// `scale` with the SHOT radius FitRadii would fit rounded to the nearest 3 cm x ratio^k:
/// models whose radii round alike describe a frame alike, once for all of them
/// (core/library.h). Unchanged when ratio <= 1 or the scale is empty.
ModelScale OnRadiusGrid(const ModelScale& scale, float ratio);

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

/// A search index over SHOT descriptors: FLANN's hierarchical k-means tree, seeded
/// (options.match_seed, match_branching, match_checks), so that every build and every match is
/// the same on every run. Immutable once built; safe to share between threads.
class ShotIndex {
 public:
  /// `shots`: rows of kShotLength floats (at least one row).
  ShotIndex(std::vector<float> shots, const RecognitionOptions& options);
  ~ShotIndex();
  ShotIndex(const ShotIndex&) = delete;
  ShotIndex& operator=(const ShotIndex&) = delete;
  /// Nearest row to `shot` within sqrt(max_sqr_distance): its index (-1 when none is that near)
  /// and squared distance. The bound prunes the search.
  std::pair<int, float> Nearest(
      const float* shot, float max_sqr_distance = std::numeric_limits<float>::infinity()) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

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
  /// The turns about centroid() that map a whole-surface model onto itself (core/symmetry.h),
  /// identity first; just the identity for a model seen from one side.
  const std::vector<Eigen::Matrix3f>& symmetries() const { return symmetries_; }
  /// A model of several captured views: each view alone as verification uses it (its points
  /// count as a one-view model's do), in the views' order. Empty for one view or a mesh.
  const std::vector<VerificationModel>& view_verification() const { return view_verification_; }
  /// The view holding model point `cloud_index` (an index into cloud()); 0 for one view.
  int ViewOf(int cloud_index) const;

  /// Nearest model descriptor of `shot` (kShotLength floats) within sqrt(max_sqr_distance):
  /// index into descriptors() (-1 when none is that near) and squared distance. The bound
  /// prunes the search.
  std::pair<int, float> Nearest(
      const float* shot, float max_sqr_distance = std::numeric_limits<float>::infinity()) const {
    return index_->Nearest(shot, max_sqr_distance);
  }

 private:
  friend std::optional<ModelDescription> DescribeModel(const std::vector<Cloud>&,
                                                       const RecognitionOptions&, std::string*,
                                                       float);
  ModelDescription() = default;
  Cloud cloud_;
  Descriptors descriptors_;
  Eigen::Vector3f centroid_ = Eigen::Vector3f::Zero();
  VerificationModel verification_;
  ModelScale scale_;
  std::vector<Eigen::Matrix3f> symmetries_{Eigen::Matrix3f::Identity()};
  std::vector<VerificationModel> view_verification_;
  std::vector<std::size_t> view_starts_;  // view v is cloud_[view_starts_[v], view_starts_[v + 1])
  std::unique_ptr<ShotIndex> index_;
};

/// The centroid of the finite points, in the cloud's frame; nullopt when none is finite.
std::optional<Eigen::Vector3f> FiniteCentroid(const Cloud& cloud);

/// Describes the model (normals k_nm, uniform-sampling keypoints r_km, SHOT r_sm, LRF r_lm).
/// nullopt with `error` set when the cloud has no finite point or no describable keypoint.
std::optional<ModelDescription> DescribeModel(const Cloud& model, const RecognitionOptions& options,
                                              std::string* error);

/// The finite points of every view, in order, as one cloud (a model of views as any reader of
/// one cloud sees it).
Cloud MergeViews(const std::vector<Cloud>& views);

/// A model captured from several places: `views` in one model frame, each with its sensor
/// origin (sensor_origin_, in that frame). Each view is described as a captured model is (its
/// normals facing its sensor) and every descriptor joins one index, so that a scene showing any
/// of the views' sides votes for one pose; verification counts the points a pose turns towards
/// the camera. One view is DescribeModel(view). `radius_ratio` > 1 puts the fitted radii on
/// that grid (OnRadiusGrid), for a model searched in a library.
std::optional<ModelDescription> DescribeModel(const std::vector<Cloud>& views,
                                              const RecognitionOptions& options, std::string* error,
                                              float radius_ratio = 1);

}  // namespace saccade
