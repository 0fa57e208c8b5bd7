// SHOT descriptors with their local reference frames (Tombari et al. 2010, ported from PCL
// 1.13's SHOTEstimation so that one neighbourhood per keypoint serves both the frame and the
// histogram).
#pragma once

#include "core/neighbor_search.h"
#include "core/normals.h"
#include "core/parallel.h"
#include "core/types.h"

#include <cstdint>
#include <vector>

namespace saccade {

constexpr int kShotLength = 352;  // 32 spatial volumes x (10 cosine bins + 1), as PCL

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
