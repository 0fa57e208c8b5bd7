// Depth and colour from two cameras a few centimetres apart, as on every Kinect-class sensor:
// the depth (infrared) camera's image seen from the colour camera, and the Kinect v1's raw
// disparity. Pure geometry on images; no PCL, position-independent so the OpenNI2 driver
// links it too.
#pragma once

#include "core/camera.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace saccade {

/// Where a sensor's colour camera is relative to its depth camera.
struct ColourCalibration {
  CameraIntrinsics depth;   // the depth (infrared) camera
  CameraIntrinsics colour;  // the colour camera
  /// X_CD: a point in the depth camera's frame, in the colour camera's frame.
  Eigen::Isometry3d colour_from_depth = Eigen::Isometry3d::Identity();
};

/// X_CD of a colour camera whose origin is at `t` (metres) in the depth camera's frame, turned
/// by the rotation vector `r` (radians): the form of a colour camera file (io/formats/images.h).
Eigen::Isometry3d ColourFromDepth(const double t[3], const double r[3]);

/// A Kinect v1 / PrimeSense layout at 640x480: depth camera fx = fy = 580, colour camera
/// fx = fy = 525, both centred, the colour camera 25 mm to the depth camera's right (+x) and
/// parallel to it. Nominal figures of the family, not any one unit's factory calibration.
ColourCalibration NominalKinectCalibration();

/// The depth image `depth_mm` (from.width x from.height, millimetres, 0 = no return) as camera
/// `to` sees it, `to_from` taking `from`'s frame to `to`'s. Each pixel's point covers its
/// footprint in `to` (so nothing tears where `to` has the finer pixels), the nearest surface
/// wins, and the pixels nothing lands on are 0. When `source` is given, it receives for each
/// pixel of `to` the index of the `from` pixel that landed there (-1 for none).
std::vector<std::uint16_t> RegisterDepth(const std::uint16_t* depth_mm,
                                         const CameraIntrinsics& from,
                                         const Eigen::Isometry3d& to_from,
                                         const CameraIntrinsics& to,
                                         std::vector<int>* source = nullptr);

/// A Kinect v1's raw 11-bit disparity: z = 1 / (3.3309495161 - 0.0030711016 raw) metres
/// (N. Burrus' fit), 0.30 m at raw 0. 2047 and anything past 10 m (raw > 1052) is no return (0).
std::uint16_t KinectDisparityToMm(std::uint16_t raw);
/// The inverse, rounded to the nearest disparity: 2047 for 0 (no return) and for depths out
/// of the sensor's reach (nearer than raw 0, farther than 10 m).
std::uint16_t MmToKinectDisparity(std::uint16_t mm);
constexpr std::uint16_t kKinectNoDisparity = 2047;

}  // namespace saccade
