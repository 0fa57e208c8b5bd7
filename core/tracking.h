// Frame-to-frame tracking (issue 16): the last pose of an object, refined against the next
// organized frame directly. Projective data association (each model point that faces the
// camera is projected into the depth image and paired with the point seen at that pixel: no
// kd-tree), point-to-plane steps on the frame's normals (from the pixel's neighbours), a few
// iterations; then a score that says whether the track still holds. Pure; thread-safe.
#pragma once

#include "core/camera.h"
#include "core/schema.h"
#include "core/types.h"
#include "core/verification.h"

#include <Eigen/Core>

#include <string>

namespace saccade {

struct TrackOptions {
  int iterations = 8;                // point-to-plane steps per frame
  float max_distance_m = 0.03f;      // pairs farther apart are left out of a step
  float inlier_distance_m = 0.006f;  // a model point this near its pixel's point lies on it
  /// A model point this far or more in front of the surface seen at its pixel should have been
  /// seen: it counts against the track (free space). Farther behind it is hidden: neutral.
  float free_space_margin_m = 0.02f;
  /// TRACKING while inliers / (inliers + points in free space) reaches min_fitness and
  /// inliers / model points facing the camera in the image reaches min_coverage.
  float min_fitness = 0.6f;
  float min_coverage = 0.25f;
  int normal_step_px = 2;  // the frame's normal at a pixel from the points this far around it
  /// Below this share of the model's points that face the camera falling inside the image (an
  /// object leaving or entering at an edge), only the position is refined and the predicted
  /// turn is held: the part in view no longer pins the turn down.
  float min_in_image_to_turn = 0.5f;

  bool IsValid(std::string* error) const;
  bool operator==(const TrackOptions& o) const { return SameFields(*this, o); }
  /// The keys of a `tracking` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("iterations", &iterations);
    a->Visit("max_distance_m", &max_distance_m);
    a->Visit("inlier_distance_m", &inlier_distance_m);
    a->Visit("free_space_margin_m", &free_space_margin_m);
    a->Visit("min_fitness", &min_fitness);
    a->Visit("min_coverage", &min_coverage);
    a->Visit("normal_step_px", &normal_step_px);
    a->Visit("min_in_image_to_turn", &min_in_image_to_turn);
  }
};

/// A refined pose and how well the frame supports it.
struct TrackResult {
  Eigen::Matrix4f model_to_camera = Eigen::Matrix4f::Identity();  // X_CM after refinement
  int facing = 0;      // model points facing the camera that project into the image
  int inliers = 0;     // of those, on the surface seen at their pixel
  int free_space = 0;  // of those, in front of it by the margin or more
  float fitness = 0;   // inliers / (inliers + free_space)
  float coverage = 0;  // inliers / facing
  float rms_m = 0;     // point-to-plane residual of the inliers
  int iterations = 0;  // steps taken (fewer when it converged)
  /// Of the model points facing the camera, the share inside the image (1 when none faces it).
  float in_image = 1;
  bool turn_held = false;  // too little of it in the image at the start: its turn was kept
  bool tracking = false;   // fitness and coverage reach the options' minimums
};

/// Refines `predicted` (X_CM, e.g. the constant-velocity prediction) against `frame`, an
/// organized cloud in the camera frame with `intrinsics`, using the model's verification
/// points and normals (model frame). Preconditions: options.IsValid(), frame organized with
/// intrinsics.width x intrinsics.height points.
TrackResult TrackPose(const VerificationModel& model, const Cloud& frame,
                      const CameraIntrinsics& intrinsics, const Eigen::Matrix4f& predicted,
                      const TrackOptions& options);

/// The score TrackPose ends with, of `X_CM` as given (no step taken; iterations 0). Same
/// preconditions.
TrackResult ScorePose(const VerificationModel& model, const Cloud& frame,
                      const CameraIntrinsics& intrinsics, const Eigen::Matrix4f& X_CM,
                      const TrackOptions& options);

}  // namespace saccade
