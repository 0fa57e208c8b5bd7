// Model acquisition (paper §5.8.1): cut an object out of a capture. Drop what is too far,
// remove dominant planes (the table, walls) with RANSAC, and split the rest into Euclidean
// clusters; the object is one of the clusters.
#pragma once

#include "core/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

struct SegmentationOptions {
  float z_max_m = 1.5f;  // points with z beyond this are dropped first
  /// Planes are removed, largest first, until at least this fraction of the points left after
  /// the z cut is gone (F_points).
  float plane_fraction = 0.5f;
  float plane_distance_m = 0.01f;  // a point within this of a plane belongs to it
  /// A plane must hold at least this fraction of the points after the z cut (and min_points).
  float min_plane_fraction = 0.05f;
  int max_planes = 8;                // stop removing planes after this many
  int plane_iterations = 500;        // RANSAC hypotheses per plane
  float cluster_distance_m = 0.01f;  // d_cluster: neighbours closer than this join a cluster
  int min_points = 200;              // smaller clusters are dropped
  std::uint32_t seed = 1;            // the same cloud and seed give the same segmentation

  /// False with `error` naming the field when a value is out of range.
  bool IsValid(std::string* error) const;
};

struct Plane {
  Eigen::Vector4f coefficients = Eigen::Vector4f::Zero();  // n.x, n.y, n.z, d with n.p + d = 0
  std::size_t inliers = 0;                                 // points it removed
};

struct Cluster {
  std::vector<int> indices;  // into the input cloud, ascending
  Eigen::Vector3f centroid_m = Eigen::Vector3f::Zero();
  Box box;  // axis-aligned bounds, camera frame
};

struct Segmentation {
  std::size_t finite_points = 0;  // finite points of the input
  std::size_t kept_points = 0;    // after the z cut
  std::vector<Plane> planes;      // in the order they were removed
  std::vector<Cluster> clusters;  // largest first (ties: nearer the camera first)
};

/// Segments `scene`. False with `error` (what went wrong, with the numbers) when the cloud has no
/// finite point, z_max removes every point, no plane is found, or no cluster of min_points is
/// left. Deterministic for a given seed.
bool Segment(const Cloud& scene, const SegmentationOptions& options, Segmentation* out,
             std::string* error);

/// The points of `indices`, as an unorganized cloud (the cloud's sensor origin kept).
Cloud ExtractPoints(const Cloud& cloud, const std::vector<int>& indices);

}  // namespace saccade
