// Pinhole camera geometry: where a camera-frame point lands in the image and back. The one
// place Saccade's stages project and unproject (camera optical frame: x right, y down, z
// forward; metres; pixel centres at integer coordinates).
#pragma once

#include <Eigen/Core>

namespace saccade {

/// Pinhole intrinsics of an organized depth frame, in pixels.
struct CameraIntrinsics {
  double fx = 525.0;
  double fy = 525.0;
  double cx = 319.5;
  double cy = 239.5;
  int width = 640;
  int height = 480;

  /// The pixel (u, v) that camera-frame point `p_C` projects to. Precondition: p_C.z() > 0.
  Eigen::Vector2d Project(const Eigen::Vector3f& p_C) const {
    return {fx * p_C.x() / p_C.z() + cx, fy * p_C.y() / p_C.z() + cy};
  }
  /// The camera-frame point seen at pixel (u, v) at depth `z_m` along the optical axis
  /// (computed in double, stored in float, as every Saccade cloud is).
  Eigen::Vector3f Unproject(double u, double v, double z_m) const {
    return {static_cast<float>((u - cx) * z_m / fx), static_cast<float>((v - cy) * z_m / fy),
            static_cast<float>(z_m)};
  }
  bool operator==(const CameraIntrinsics& o) const {
    return fx == o.fx && fy == o.fy && cx == o.cx && cy == o.cy && width == o.width &&
           height == o.height;
  }
  bool operator!=(const CameraIntrinsics& o) const { return !(*this == o); }
};

}  // namespace saccade
