// One depth frame as every stage sees it, and the truth a synthetic or recorded frame carries.
#pragma once

#include "core/camera.h"
#include "core/types.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace saccade {

/// What a synthetic scenario (or a recording of one) knows about a frame.
struct GroundTruth {
  Eigen::Isometry3f target_pose = Eigen::Isometry3f::Identity();  // X_CO
  Eigen::Vector3f centroid_m = Eigen::Vector3f::Zero();  // centre of the target's bounding box
  /// Visible target pixels over those it would cover rendered alone in an image without edges
  /// (0 when out of view; an object half out of the image is half visible).
  float visible_fraction = 0.0f;
  /// Further objects of the frame, as the target above (a capture sequence's `others`, in that
  /// order); centroid_m of these is the centroid of their points.
  struct Object {
    Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();  // X_CO
    Eigen::Vector3f centroid_m = Eigen::Vector3f::Zero();
    float visible_fraction = 0.0f;
  };
  std::vector<Object> others;
};

/// One depth frame. The cloud is organized, in the camera optical frame, in metres; pixels
/// without depth are NaN. Shared and immutable once made, so stages can hold it cheaply.
struct Frame {
  std::uint64_t sequence = 0;  // 0, 1, 2... in the order the source produced frames
  /// Capture time in microseconds: the sensor's timestamp when it has one, else the
  /// sequence's own clock (synthetic: frame time; files: rate or file order), else wall time.
  std::int64_t capture_utime = 0;
  /// Steady clock (SteadyNowNs) when the frame reached Saccade: latencies are measured from
  /// here. Live sources set it when they post the frame; 0 until someone does.
  std::int64_t arrival_steady_ns = 0;
  std::shared_ptr<const Cloud> cloud;
  CameraIntrinsics intrinsics;
  std::optional<GroundTruth> truth;  // synthetic frames and recordings that carry it
};

/// Depth in millimetres (0: no return) to an organized cloud in metres; `rgb` (3 bytes per
/// pixel) may be null. Pixels whose depth is 0 become NaN.
Cloud DepthToCloud(const std::uint16_t* depth_mm, const std::uint8_t* rgb,
                   const CameraIntrinsics& intrinsics);

}  // namespace saccade
