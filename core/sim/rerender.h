// New frames from a real capture (issue 16's real-data sequences): a captured organized frame
// is the world, and a virtual camera near the original viewpoint sees it again, its points
// splatted into a z-buffer, so the holes, shadows and sensor noise are the capture's own. One
// labelled object may move rigidly through it. Pure.
#pragma once

#include "core/camera.h"
#include "core/types.h"

#include <Eigen/Geometry>

#include <vector>

namespace saccade {

/// What moves and where the virtual camera is, all in the capture's camera frame W.
struct RerenderPose {
  Eigen::Isometry3f X_WC = Eigen::Isometry3f::Identity();  // the virtual camera C in W
  /// The indices (into the capture) of one object's points, and the rigid motion applied to
  /// them in W (identity: the object stays where it was captured).
  std::vector<int> object;
  Eigen::Isometry3f object_motion_W = Eigen::Isometry3f::Identity();
};

/// Renders the capture `world` (an organized frame, camera frame W = its own) as the camera at
/// pose.X_WC with intrinsics `k` sees it: each finite point is splatted over the pixels its
/// capture footprint covers at its new depth (one pixel at the captured depth, more when the
/// camera came nearer), the nearest point winning each pixel. `labels`, when given, gets per
/// pixel 1 where the object's points won and 0 elsewhere. Pixels nothing reaches are NaN.
Cloud RerenderCapture(const Cloud& world, const CameraIntrinsics& k, const RerenderPose& pose,
                      std::vector<std::uint8_t>* labels = nullptr);

}  // namespace saccade
