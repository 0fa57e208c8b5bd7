// Surface normals (organized pixel windows or k nearest neighbours) and principal axes.
#pragma once

#include "core/camera.h"
#include "core/parallel.h"
#include "core/types.h"

#include <cstdint>
#include <vector>

namespace saccade {

/// Per-point unit normals (NaN where not computed), oriented towards the camera origin.
using Normals = std::vector<Eigen::Vector3f>;

/// Normals of the masked points of an organized cloud from a small pixel window of its
/// full-resolution grid: the window is the smallest square holding `k_neighbors` pixels, and
/// only neighbours close in 3D (no depth jumps) count.
Normals OrganizedNormals(const Cloud& cloud, const CameraIntrinsics& intrinsics,
                         const std::vector<std::uint8_t>& mask, int k_neighbors,
                         const ParallelFor& parallel_for = SerialFor);

/// Normals of the masked points from their k nearest neighbours in the whole cloud, oriented
/// towards the cloud's sensor_origin_ (where the sensor was, in the cloud's frame).
Normals KnnNormals(const Cloud& cloud, const std::vector<std::uint8_t>& mask, int k_neighbors);

/// One frame's normals, each computed the first time a mask asks for it and kept: a frame
/// described at several radii (a library's) computes each normal once. A point's normal does
/// not depend on which other points are asked for, so they are the normals one call would give.
/// Lives for one search of one frame; a call with another cloud, kind or k starts afresh.
class SceneNormals {
 public:
  /// The normals of `cloud`, set on `where` (and on whatever was asked for before): from its
  /// pixel windows (OrganizedNormals) when `intrinsics` is given, else from k nearest neighbours.
  const Normals& On(const Cloud& cloud, const CameraIntrinsics* intrinsics, int k_neighbors,
                    const std::vector<std::uint8_t>& where, const ParallelFor& parallel_for);

 private:
  const Cloud* cloud_ = nullptr;
  bool organized_ = false;
  int k_neighbors_ = 0;
  Normals normals_;
  std::vector<std::uint8_t> done_;
};

/// Principal axes of a point set (PCA): the mean, and the covariance's eigenvalues (variances,
/// ascending) with their unit eigenvectors (columns, same order).
struct PrincipalAxes {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d variances = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};
/// Precondition: `points` is not empty.
PrincipalAxes ComputePrincipalAxes(const std::vector<Eigen::Vector3f>& points);

}  // namespace saccade
