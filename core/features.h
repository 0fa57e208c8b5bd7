// Local geometry of a cloud: normals, radius neighbourhoods, SHOT local reference frames and
// SHOT descriptors (Tombari et al. 2010, ported from PCL 1.13's SHOTEstimation so that one
// neighbourhood per keypoint serves both the frame and the histogram).
#pragma once

#include "core/parallel.h"
#include "core/types.h"

#include <memory>
#include <optional>
#include <vector>

namespace saccade {

constexpr int kShotLength = 352;  // 32 spatial volumes x (10 cosine bins + 1), as PCL

/// Radius neighbourhoods over a search surface. Indices are into the cloud the search was made
/// for. Thread-safe for concurrent queries once constructed.
class NeighborSearch {
 public:
  virtual ~NeighborSearch() = default;
  /// Appends the surface points within `radius_m` of surface point `query` (itself included
  /// unless the window is sampled), with their squared distances. Clears both outputs first.
  virtual void Radius(int query, float radius_m, std::vector<int>* indices,
                      std::vector<float>* sqr_dists) const = 0;
};

/// Search on an organized (image-shaped) cloud: scans the pixel window that a sphere of the
/// radius covers at the query's depth. Only points with mask[i] != 0 are surface points; the
/// mask (size = cloud size) and cloud must outlive the search. A window reaching farther than
/// `max_half_window_px` from the query is sampled every few pixels, so that a wide support near
/// the camera holds about as many points as one of that half-width (0: every pixel).
std::unique_ptr<NeighborSearch> MakeOrganizedSearch(const Cloud& cloud,
                                                    const CameraIntrinsics& intrinsics,
                                                    const std::vector<std::uint8_t>& mask,
                                                    int max_half_window_px = 0);

/// Search over the masked points of any cloud with a kd-tree (built here, once).
std::unique_ptr<NeighborSearch> MakeKdTreeSearch(const Cloud& cloud,
                                                 const std::vector<std::uint8_t>& mask);

/// Estimates pinhole intrinsics from an organized cloud's own points (x = (u - cx) z / fx);
/// nullopt when the cloud is unorganized or has too few finite points.
std::optional<CameraIntrinsics> EstimateIntrinsics(const Cloud& cloud);

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

/// Principal axes of a point set (PCA): the mean, and the covariance's eigenvalues (variances,
/// ascending) with their unit eigenvectors (columns, same order).
struct PrincipalAxes {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d variances = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};
/// Precondition: `points` is not empty.
PrincipalAxes ComputePrincipalAxes(const std::vector<Eigen::Vector3f>& points);

/// SHOT descriptors of a set of keypoints, with their local reference frames.
struct Descriptors {
  std::vector<int> keypoint;         // index of each described keypoint in the cloud
  std::vector<Eigen::Matrix3f> lrf;  // rows: x, y, z axes of the local frame (camera frame)
  std::vector<float> shot;           // keypoint.size() x kShotLength, row-major, L2-normalized
  std::size_t size() const { return keypoint.size(); }
  const float* Row(std::size_t i) const { return shot.data() + i * kShotLength; }
};

struct DescribeOptions {
  float shot_radius_m = 0.02f;  // support radius of the histogram
  float lrf_radius_m = 0.015f;  // support radius of the local reference frame
  int min_neighbors = 5;        // fewer points in the support: no descriptor (as PCL)
};

/// The support of each keypoint: the surface points within the wider of the SHOT and LRF radii
/// (DescribeOptions), with their squared distances. Found once, they tell where descriptors will
/// read normals (SupportMask) before any normal is computed.
struct Supports {
  std::vector<std::vector<int>> indices;
  std::vector<std::vector<float>> sqr_dists;
};
Supports FindSupports(const Cloud& cloud, const std::vector<int>& keypoints,
                      const NeighborSearch& search, const DescribeOptions& options,
                      const ParallelFor& parallel_for = SerialFor);

/// A mask over the cloud (size `cloud_size`) of every point some support holds: the only points
/// whose normals a SHOT histogram reads.
std::vector<std::uint8_t> SupportMask(const Supports& supports, std::size_t cloud_size);

/// Describes the keypoints from their supports; keypoints whose frame or histogram is undefined
/// (too few neighbours, NaN normals everywhere, degenerate covariance) are left out, so no NaN
/// ever leaves this function. `normals` must be set on SupportMask(supports).
Descriptors DescribeKeypoints(const Cloud& cloud, const Normals& normals,
                              const std::vector<int>& keypoints, const Supports& supports,
                              const DescribeOptions& options,
                              const ParallelFor& parallel_for = SerialFor);
/// The same, finding the supports with `search`.
Descriptors DescribeKeypoints(const Cloud& cloud, const Normals& normals,
                              const std::vector<int>& keypoints, const NeighborSearch& search,
                              const DescribeOptions& options,
                              const ParallelFor& parallel_for = SerialFor);

/// The SHOT local reference frame of `center` from its neighbours (all within `radius_m`);
/// false when undefined. Exposed for tests.
bool ShotLocalFrame(const Cloud& cloud, int center, const std::vector<int>& neighbors,
                    const std::vector<float>& sqr_dists, float radius_m, Eigen::Matrix3f* lrf);

}  // namespace saccade
