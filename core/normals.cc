#include "core/normals.h"

#include <pcl/features/normal_3d.h>
#include <pcl/kdtree/kdtree_flann.h>
#include "core/check.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <unordered_map>

namespace saccade {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Normal of a neighbourhood by PCA: the eigenvector of the smallest eigenvalue, turned towards
// the viewpoint (the sensor that saw the points). NaN when fewer than 3 points.
Eigen::Vector3f PcaNormal(const Eigen::Vector3f* points, int n, const Eigen::Vector3f& at,
                          const Eigen::Vector3f& viewpoint = Eigen::Vector3f::Zero()) {
  if (n < 3) return Eigen::Vector3f::Constant(kNaN);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) mean += points[i].cast<double>();
  mean /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = points[i].cast<double>() - mean;
    cov.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(cov);
  Eigen::Vector3f normal = solver.eigenvectors().col(0).cast<float>();
  if (!normal.allFinite()) return Eigen::Vector3f::Constant(kNaN);
  if (normal.dot(viewpoint - at) < 0) normal = -normal;
  return normal;
}

}  // namespace

PrincipalAxes ComputePrincipalAxes(const std::vector<Eigen::Vector3f>& points) {
  SACCADE_CHECK(!points.empty(), "principal axes of no point");
  PrincipalAxes out;
  for (const auto& p : points) out.mean += p.cast<double>();
  out.mean /= double(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) {
    const Eigen::Vector3d d = p.cast<double>() - out.mean;
    cov.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov / double(points.size()));
  out.variances = solver.eigenvalues();
  out.axes = solver.eigenvectors();
  return out;
}

namespace {

// OrganizedNormals into `normals` (the cloud's size): the masked points' entries are set, the
// others left as they are.
void FillOrganizedNormals(const Cloud& cloud, const std::vector<std::uint8_t>& mask,
                          int k_neighbors, const ParallelFor& parallel_for, Normals* out) {
  Normals& normals = *out;
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  int half = 1;
  while ((2 * half + 1) * (2 * half + 1) < k_neighbors + 1) ++half;
  const int k = std::max(3, k_neighbors);
  parallel_for(static_cast<std::size_t>(h), [&](std::size_t row_begin, std::size_t row_end) {
    std::vector<std::pair<float, Eigen::Vector3f>> window;
    std::vector<Eigen::Vector3f> nearest;
    for (int v0 = static_cast<int>(row_begin); v0 < static_cast<int>(row_end); ++v0) {
      for (int u0 = 0; u0 < w; ++u0) {
        const int i = v0 * w + u0;
        if (!mask[i]) continue;
        const Eigen::Vector3f p = cloud[i].getVector3fMap();
        if (!p.allFinite()) continue;
        window.clear();
        for (int v = std::max(0, v0 - half); v <= std::min(h - 1, v0 + half); ++v) {
          for (int u = std::max(0, u0 - half); u <= std::min(w - 1, u0 + half); ++u) {
            const Eigen::Vector3f q = cloud[v * w + u].getVector3fMap();
            const float d2 = (q - p).squaredNorm();
            if (std::isfinite(d2)) window.emplace_back(d2, q);
          }
        }
        // The k nearest of the window, as a k-nearest-neighbour normal would use.
        if (static_cast<int>(window.size()) > k) {
          std::nth_element(window.begin(), window.begin() + k, window.end(),
                           [](const auto& a, const auto& b) { return a.first < b.first; });
          window.resize(k);
        }
        nearest.clear();
        for (const auto& e : window) nearest.push_back(e.second);
        normals[i] = PcaNormal(nearest.data(), static_cast<int>(nearest.size()), p);
      }
    }
  });
}

}  // namespace

Normals OrganizedNormals(const Cloud& cloud, const CameraIntrinsics& /*intrinsics*/,
                         const std::vector<std::uint8_t>& mask, int k_neighbors,
                         const ParallelFor& parallel_for) {
  Normals normals(cloud.size(), Eigen::Vector3f::Constant(kNaN));
  FillOrganizedNormals(cloud, mask, k_neighbors, parallel_for, &normals);
  return normals;
}

const Normals& SceneNormals::On(const Cloud& cloud, const CameraIntrinsics* intrinsics,
                                int k_neighbors, const std::vector<std::uint8_t>& where,
                                const ParallelFor& parallel_for) {
  SACCADE_CHECK(where.size() == cloud.size(), "a normals mask of another cloud's size");
  const bool organized = intrinsics != nullptr;
  if (cloud_ != &cloud || organized_ != organized || k_neighbors_ != k_neighbors) {
    cloud_ = &cloud;
    organized_ = organized;
    k_neighbors_ = k_neighbors;
    normals_.clear();
    done_.assign(cloud.size(), 0);
  }
  std::vector<std::uint8_t> todo(where.size(), 0);
  bool any = false;
  for (std::size_t i = 0; i < where.size(); ++i) {
    if (!where[i] || done_[i]) continue;
    todo[i] = done_[i] = 1;
    any = true;
  }
  if (!any) return normals_;
  if (normals_.empty()) normals_.assign(cloud.size(), Eigen::Vector3f::Constant(kNaN));
  if (organized) {
    FillOrganizedNormals(cloud, todo, k_neighbors, parallel_for, &normals_);
  } else {
    const Normals computed = KnnNormals(cloud, todo, k_neighbors);
    for (std::size_t i = 0; i < todo.size(); ++i)
      if (todo[i]) normals_[i] = computed[i];
  }
  return normals_;
}

Normals KnnNormals(const Cloud& cloud, const std::vector<std::uint8_t>& mask, int k_neighbors) {
  Normals normals(cloud.size(), Eigen::Vector3f::Constant(kNaN));
  // The search surface is every finite point at a distinct place (full resolution), the queries
  // only the masked. Points at the very same place are one: a k-d tree cannot split them, and a
  // cloud of many copies of one point would make every search visit them all.
  std::vector<int> first(cloud.size(), -1);  // each finite point's first copy
  auto distinct = std::make_shared<pcl::Indices>();
  {
    std::unordered_map<std::uint64_t, std::vector<int>> at;  // by a hash of the coordinates
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      if (!FinitePoint(cloud[i])) continue;
      const Eigen::Vector3f p = cloud[i].getVector3fMap();
      std::uint32_t bits[3];
      std::memcpy(bits, p.data(), sizeof bits);
      const std::uint64_t key = (std::uint64_t(bits[0]) * 0x9E3779B97F4A7C15ull) ^
                                (std::uint64_t(bits[1]) * 0xC2B2AE3D27D4EB4Full) ^ bits[2];
      std::vector<int>& same = at[key];
      for (int j : same)
        if (cloud[std::size_t(j)].getVector3fMap() == p) first[i] = j;
      if (first[i] >= 0) continue;
      first[i] = int(i);
      same.push_back(int(i));
      distinct->push_back(int(i));
    }
  }
  if (distinct->empty()) return normals;
  auto input = Cloud::ConstPtr(&cloud, [](const Cloud*) {});
  pcl::search::KdTree<PointT>::Ptr tree(new pcl::search::KdTree<PointT>);
  tree->setInputCloud(input, distinct);
  std::vector<int> nn;
  std::vector<float> d2;
  std::vector<Eigen::Vector3f> pts;
  const Eigen::Vector3f viewpoint = cloud.sensor_origin_.head<3>();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!mask[i] || first[i] < 0) continue;
    if (first[i] != int(i) && mask[std::size_t(first[i])]) {
      normals[i] = normals[std::size_t(first[i])];  // a copy of a point already done
      continue;
    }
    tree->nearestKSearch(cloud[i], k_neighbors, nn, d2);
    pts.clear();
    for (int j : nn) pts.push_back(cloud[j].getVector3fMap());
    normals[i] =
        PcaNormal(pts.data(), static_cast<int>(pts.size()), cloud[i].getVector3fMap(), viewpoint);
  }
  return normals;
}

}  // namespace saccade
