// Values passed between Saccade's stages. Units are metres and seconds unless a name says
// otherwise; clouds are in the camera optical frame (x right, y down, z forward).
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace saccade {

/// The point type of every cloud Saccade handles (XYZ plus packed colour; colour may be unset).
using PointT = pcl::PointXYZRGBA;
using Cloud = pcl::PointCloud<PointT>;

/// Pinhole intrinsics of an organized depth frame, in pixels.
struct CameraIntrinsics {
  double fx = 525.0;
  double fy = 525.0;
  double cx = 319.5;
  double cy = 239.5;
  int width = 640;
  int height = 480;
};

/// An axis-aligned box [min, max] in some frame (which the owner names). Empty when any
/// max < min.
struct Box {
  Eigen::Vector3f min = Eigen::Vector3f::Zero();
  Eigen::Vector3f max = Eigen::Vector3f::Zero();

  bool Empty() const { return (max.array() < min.array()).any(); }
  /// Closed interval test: a point on a face is inside.
  bool Contains(const Eigen::Vector3f& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  /// True when `inner` lies entirely inside this box (an empty box lies inside any box).
  bool ContainsBox(const Box& inner) const {
    return inner.Empty() ||
           ((inner.min.array() >= min.array()).all() && (inner.max.array() <= max.array()).all());
  }
  Eigen::Vector3f Size() const { return max - min; }
};

/// One recognized instance of the model in a scene.
struct Detection {
  Eigen::Matrix4f model_to_scene = Eigen::Matrix4f::Identity();  // X_SM: model frame M in scene S
  int votes = 0;                                         // correspondences that agree on this pose
  Eigen::Vector3f centroid_m = Eigen::Vector3f::Zero();  // model centroid in the scene frame
  /// Set by verification (-1 when not verified): the share of the model's visible points that lie
  /// on the scene surface, the share of all its points that do, and the share of those whose
  /// colour agrees (-1 when not checked).
  float fitness = -1;
  float coverage = -1;
  float colour_agreement = -1;
  /// How likely the instance is to be the object, in [0, 1], from its verification figures
  /// (calibrated on the cross-capture benchmark, docs/RESULTS.md); -1 when not verified.
  float confidence = -1;
  /// (model keypoint index, scene keypoint index) pairs behind this instance.
  std::vector<std::pair<int, int>> correspondences;
};

}  // namespace saccade
