#include "core/segmentation.h"

#include "core/fail.h"
#include "core/features.h"

#include <pcl/common/io.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace saccade {

bool SegmentationOptions::IsValid(std::string* error) const {
  if (!(z_max_m > 0)) return Fail(error, "z_max must be > 0 m");
  if (!(plane_fraction >= 0 && plane_fraction < 1))
    return Fail(error, "plane_fraction must be in [0, 1)");
  if (!(min_plane_fraction > 0 && min_plane_fraction < 1))
    return Fail(error, "min_plane_fraction must be in (0, 1)");
  if (!(plane_distance_m > 0)) return Fail(error, "plane_distance must be > 0 m");
  if (max_planes < 0) return Fail(error, "max_planes must be >= 0");
  if (plane_iterations < 1) return Fail(error, "plane_iterations must be >= 1");
  if (!(cluster_distance_m > 0)) return Fail(error, "cluster_distance must be > 0 m");
  if (min_points < 1) return Fail(error, "min_points must be >= 1");
  return true;
}

namespace {

Eigen::Vector3f At(const Cloud& cloud, int i) { return cloud[i].getVector3fMap(); }

float Distance(const Eigen::Vector4f& plane, const Eigen::Vector3f& p) {
  return std::abs(plane.head<3>().dot(p) + plane[3]);
}

// The least-squares plane through the points (normal = least-variance direction).
Eigen::Vector4f FitPlane(const Cloud& cloud, const std::vector<int>& indices) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(indices.size());
  for (int i : indices) points.push_back(At(cloud, i));
  const PrincipalAxes pca = ComputePrincipalAxes(points);
  const Eigen::Vector3d n = pca.axes.col(0);
  return Eigen::Vector4f(float(n.x()), float(n.y()), float(n.z()), float(-n.dot(pca.mean)));
}

std::vector<int> Inliers(const Cloud& cloud, const std::vector<int>& points,
                         const Eigen::Vector4f& plane, float distance_m) {
  std::vector<int> inliers;
  for (int i : points)
    if (Distance(plane, At(cloud, i)) <= distance_m) inliers.push_back(i);
  return inliers;
}

// The largest plane among `points` by RANSAC: hypotheses from 3-point samples ranked on an even
// subset of at most 20,000 points, the best refit on all its inliers.
Plane LargestPlane(const Cloud& cloud, const std::vector<int>& points,
                   const SegmentationOptions& options, std::mt19937* rng) {
  constexpr std::size_t kRankPoints = 20000;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / kRankPoints);
  std::vector<int> subset;
  for (std::size_t k = 0; k < points.size(); k += stride) subset.push_back(points[k]);
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  Eigen::Vector4f best = Eigen::Vector4f::Zero();
  std::size_t best_count = 0;
  for (int it = 0; it < options.plane_iterations; ++it) {
    const Eigen::Vector3f a = At(cloud, points[pick(*rng)]), b = At(cloud, points[pick(*rng)]),
                          c = At(cloud, points[pick(*rng)]);
    Eigen::Vector3f n = (b - a).cross(c - a);
    if (n.norm() < 1e-9f) continue;
    n.normalize();
    const Eigen::Vector4f plane(n.x(), n.y(), n.z(), -n.dot(a));
    std::size_t count = 0;
    for (int i : subset) count += Distance(plane, At(cloud, i)) <= options.plane_distance_m;
    if (count > best_count) best_count = count, best = plane;
  }
  Plane out;
  if (best_count < 3) return out;
  std::vector<int> inliers = Inliers(cloud, points, best, options.plane_distance_m);
  out.coefficients = FitPlane(cloud, inliers);
  out.inliers = Inliers(cloud, points, out.coefficients, options.plane_distance_m).size();
  return out;
}

Cluster MakeCluster(const Cloud& cloud, std::vector<int> indices) {
  Cluster c;
  std::sort(indices.begin(), indices.end());
  c.box.min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  c.box.max = -c.box.min;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i : indices) {
    const Eigen::Vector3f p = At(cloud, i);
    sum += p.cast<double>();
    c.box.min = c.box.min.cwiseMin(p);
    c.box.max = c.box.max.cwiseMax(p);
  }
  c.centroid_m = (sum / double(indices.size())).cast<float>();
  c.indices = std::move(indices);
  return c;
}

}  // namespace

bool Segment(const Cloud& scene, const SegmentationOptions& options, Segmentation* out,
             std::string* error) {
  if (!options.IsValid(error)) return false;
  *out = Segmentation{};
  std::vector<int> points;
  for (int i = 0; i < int(scene.size()); ++i) {
    const Eigen::Vector3f p = At(scene, i);
    if (!p.allFinite()) continue;
    ++out->finite_points;
    if (p.z() <= options.z_max_m) points.push_back(i);
  }
  if (out->finite_points == 0) return Fail(error, "the cloud has no finite point");
  out->kept_points = points.size();
  if (points.empty())
    return Fail(error, "z_max " + std::to_string(options.z_max_m) + " m removes all " +
                           std::to_string(out->finite_points) + " points");

  // Remove planes, largest first, until plane_fraction of the kept points is gone.
  std::mt19937 rng(options.seed);
  const std::size_t min_plane = std::max<std::size_t>(
      std::size_t(options.min_points), std::size_t(options.min_plane_fraction * points.size()));
  std::size_t removed = 0;
  while (int(out->planes.size()) < options.max_planes &&
         double(removed) < options.plane_fraction * double(out->kept_points) &&
         points.size() >= min_plane) {
    const Plane plane = LargestPlane(scene, points, options, &rng);
    if (plane.inliers < min_plane) break;
    std::vector<int> rest;
    for (int i : points)
      if (Distance(plane.coefficients, At(scene, i)) > options.plane_distance_m) rest.push_back(i);
    removed += points.size() - rest.size();
    points = std::move(rest);
    out->planes.push_back(plane);
  }
  if (out->planes.empty() && options.plane_fraction > 0)
    return Fail(error, "no plane of at least " + std::to_string(min_plane) + " points among " +
                           std::to_string(out->kept_points) + " (is there a table in view?)");

  // Euclidean clusters of what is left.
  if (points.size() >= std::size_t(options.min_points)) {
    Cloud::Ptr rest(new Cloud);
    pcl::copyPointCloud(scene, points, *rest);
    pcl::search::KdTree<PointT>::Ptr tree(new pcl::search::KdTree<PointT>);
    tree->setInputCloud(rest);
    std::vector<pcl::PointIndices> found;
    pcl::EuclideanClusterExtraction<PointT> extract;
    extract.setClusterTolerance(options.cluster_distance_m);
    extract.setMinClusterSize(options.min_points);
    extract.setMaxClusterSize(std::numeric_limits<int>::max());
    extract.setSearchMethod(tree);
    extract.setInputCloud(rest);
    extract.extract(found);
    for (const pcl::PointIndices& f : found) {
      std::vector<int> indices;
      indices.reserve(f.indices.size());
      for (int k : f.indices) indices.push_back(points[k]);
      out->clusters.push_back(MakeCluster(scene, std::move(indices)));
    }
  }
  std::sort(out->clusters.begin(), out->clusters.end(), [](const Cluster& a, const Cluster& b) {
    if (a.indices.size() != b.indices.size()) return a.indices.size() > b.indices.size();
    return a.centroid_m.norm() < b.centroid_m.norm();
  });
  if (out->clusters.empty())
    return Fail(error, "no cluster of at least " + std::to_string(options.min_points) +
                           " points left after removing " + std::to_string(out->planes.size()) +
                           " plane(s) (" + std::to_string(points.size()) + " points remain)");
  return true;
}

Cloud ExtractPoints(const Cloud& cloud, const std::vector<int>& indices) {
  Cloud out;
  pcl::copyPointCloud(cloud, indices, out);
  return out;
}

}  // namespace saccade
