// Scoring a tracked pose against a truth that may be off by itself: the error at a pose, the
// least over an object's symmetric turns, and the error of its motion from frame to frame.
// Shared by `saccade bench-track` and the peer tracker it is compared with.
#pragma once

#include "core/recognition.h"

#include <Eigen/Core>

#include <vector>

namespace saccade {

/// The 24 turns of a cube onto itself (its frame's axes onto each other, keeping handedness).
std::vector<Eigen::Matrix4f> CubeRotations();

/// The pose error of a model placed at `model_in_object` in an object whose truth is `truth`,
/// the object turned by whichever of `turns` brings it nearest in rotation (the identity alone
/// for an object with no symmetry); the translation error is measured at `centre` (model frame).
/// `matched`, when given, is set to the model's truth so turned (what StepError compares with).
PoseError LeastError(const Eigen::Matrix4f& estimate, const Eigen::Matrix4f& truth,
                     const Eigen::Matrix4f& model_in_object, const Eigen::Vector3f& centre,
                     const std::vector<Eigen::Matrix4f>& turns, Eigen::Matrix4f* matched = nullptr);

/// How far the motion between two frames (`pose_a` to `pose_b`: `centre`'s shift and the turn)
/// differs from the truth's (`truth_a` to `truth_b`). A truth's own slow error cancels out of it,
/// and so does a symmetric object's turn as long as it stays the same.
PoseError StepError(const Eigen::Matrix4f& pose_a, const Eigen::Matrix4f& pose_b,
                    const Eigen::Matrix4f& truth_a, const Eigen::Matrix4f& truth_b,
                    const Eigen::Vector3f& centre);

/// The p-th quantile (0..1) of `values`, -1 when there are none.
double Quantile(std::vector<double> values, double p);

}  // namespace saccade
