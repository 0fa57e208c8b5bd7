#include "core/features.h"

#include <pcl/features/normal_3d.h>
#include <pcl/kdtree/kdtree_flann.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace saccade {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

bool Finite(const PointT& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

class OrganizedSearch final : public NeighborSearch {
 public:
  OrganizedSearch(const Cloud& cloud, const CameraIntrinsics& k,
                  const std::vector<std::uint8_t>& mask, int max_half_window_px)
      : cloud_(cloud), k_(k), mask_(mask), max_half_(max_half_window_px) {}

  void Radius(int query, float r, std::vector<int>* indices,
              std::vector<float>* sqr_dists) const override {
    indices->clear();
    sqr_dists->clear();
    const int w = static_cast<int>(cloud_.width), h = static_cast<int>(cloud_.height);
    const Eigen::Vector3f q = cloud_[query].getVector3fMap();
    // The sphere's image footprint is widest at its nearest depth.
    const float z_near = std::max(q.z() - r, 0.05f);
    const int hu = static_cast<int>(std::ceil(r * k_.fx / z_near)) + 1;
    const int hv = static_cast<int>(std::ceil(r * k_.fy / z_near)) + 1;
    // A window wider than the limit is sampled every `step` pixels, so that the support holds
    // about as many points as the limit's window would. The samples lie on one image-wide grid
    // (multiples of `step`), not on one through each query: neighbouring keypoints then share
    // their samples, and normals are needed only on that grid (SupportMask).
    const int step = max_half_ > 0 ? (std::max(hu, hv) + max_half_ - 1) / max_half_ : 1;
    const int u0 = query % w, v0 = query / w;
    const auto first = [step](int at, int half) {
      return (std::max(0, at - half) + step - 1) / step * step;
    };
    const int u_lo = first(u0, hu), u_hi = std::min(w - 1, u0 + hu);
    const int v_lo = first(v0, hv), v_hi = std::min(h - 1, v0 + hv);
    const float r2 = r * r;
    for (int v = v_lo; v <= v_hi; v += step) {
      const int row = v * w;
      for (int u = u_lo; u <= u_hi; u += step) {
        const int i = row + u;
        if (!mask_[i]) continue;
        const float d2 = (cloud_[i].getVector3fMap() - q).squaredNorm();
        if (d2 <= r2) {  // NaN compares false
          indices->push_back(i);
          sqr_dists->push_back(d2);
        }
      }
    }
  }

 private:
  const Cloud& cloud_;
  const CameraIntrinsics k_;
  const std::vector<std::uint8_t>& mask_;
  const int max_half_;  // 0: every pixel of the window
};

class KdTreeSearch final : public NeighborSearch {
 public:
  KdTreeSearch(const Cloud& cloud, const std::vector<std::uint8_t>& mask) : cloud_(cloud) {
    auto kept = std::make_shared<pcl::Indices>();
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (mask[i] && Finite(cloud[i])) kept->push_back(static_cast<int>(i));
    // The tree shares the cloud without owning it: the caller keeps it alive.
    tree_.setInputCloud(Cloud::ConstPtr(&cloud, [](const Cloud*) {}), kept);
  }

  void Radius(int query, float r, std::vector<int>* indices,
              std::vector<float>* sqr_dists) const override {
    indices->clear();
    sqr_dists->clear();
    pcl::Indices found;
    tree_.radiusSearch(cloud_[query], r, found, *sqr_dists);
    indices->assign(found.begin(), found.end());
  }

 private:
  const Cloud& cloud_;
  pcl::KdTreeFLANN<PointT> tree_;
};

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

std::unique_ptr<NeighborSearch> MakeOrganizedSearch(const Cloud& cloud,
                                                    const CameraIntrinsics& intrinsics,
                                                    const std::vector<std::uint8_t>& mask,
                                                    int max_half_window_px) {
  return std::make_unique<OrganizedSearch>(cloud, intrinsics, mask, max_half_window_px);
}

std::unique_ptr<NeighborSearch> MakeKdTreeSearch(const Cloud& cloud,
                                                 const std::vector<std::uint8_t>& mask) {
  return std::make_unique<KdTreeSearch>(cloud, mask);
}

std::optional<CameraIntrinsics> EstimateIntrinsics(const Cloud& cloud) {
  if (cloud.height <= 1 || cloud.width <= 1) return std::nullopt;
  // Least squares of u = fx * (x/z) + cx and v = fy * (y/z) + cy over a sample of pixels.
  double su = 0, sa = 0, saa = 0, sau = 0, sv = 0, sb = 0, sbb = 0, sbv = 0;
  int n = 0;
  for (std::uint32_t v = 0; v < cloud.height; v += 3) {
    for (std::uint32_t u = 0; u < cloud.width; u += 3) {
      const auto& p = cloud.at(u, v);
      if (!Finite(p) || p.z <= 0) continue;
      const double a = p.x / p.z, b = p.y / p.z;
      su += u, sa += a, saa += a * a, sau += a * u;
      sv += v, sb += b, sbb += b * b, sbv += b * v;
      ++n;
    }
  }
  if (n < 100) return std::nullopt;
  const double da = n * saa - sa * sa, db = n * sbb - sb * sb;
  if (std::abs(da) < 1e-12 || std::abs(db) < 1e-12) return std::nullopt;
  CameraIntrinsics k;
  k.fx = (n * sau - sa * su) / da;
  k.cx = (su - k.fx * sa) / n;
  k.fy = (n * sbv - sb * sv) / db;
  k.cy = (sv - k.fy * sb) / n;
  k.width = static_cast<int>(cloud.width);
  k.height = static_cast<int>(cloud.height);
  if (!(k.fx > 1 && k.fy > 1)) return std::nullopt;
  return k;
}

Normals OrganizedNormals(const Cloud& cloud, const CameraIntrinsics& /*intrinsics*/,
                         const std::vector<std::uint8_t>& mask, int k_neighbors,
                         const ParallelFor& parallel_for) {
  Normals normals(cloud.size(), Eigen::Vector3f::Constant(kNaN));
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
  return normals;
}

Normals KnnNormals(const Cloud& cloud, const std::vector<std::uint8_t>& mask, int k_neighbors) {
  Normals normals(cloud.size(), Eigen::Vector3f::Constant(kNaN));
  auto input = Cloud::ConstPtr(&cloud, [](const Cloud*) {});
  auto indices = std::make_shared<pcl::Indices>();
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (mask[i] && Finite(cloud[i])) indices->push_back(static_cast<int>(i));
  if (indices->empty()) return normals;
  // The search surface is every finite point (full resolution), the queries only the masked.
  auto finite = std::make_shared<pcl::Indices>();
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (Finite(cloud[i])) finite->push_back(static_cast<int>(i));
  pcl::search::KdTree<PointT>::Ptr tree(new pcl::search::KdTree<PointT>);
  tree->setInputCloud(input, finite);
  std::vector<int> nn;
  std::vector<float> d2;
  std::vector<Eigen::Vector3f> pts;
  const Eigen::Vector3f viewpoint = cloud.sensor_origin_.head<3>();
  for (int i : *indices) {
    tree->nearestKSearch(cloud[i], k_neighbors, nn, d2);
    pts.clear();
    for (int j : nn) pts.push_back(cloud[j].getVector3fMap());
    normals[i] =
        PcaNormal(pts.data(), static_cast<int>(pts.size()), cloud[i].getVector3fMap(), viewpoint);
  }
  return normals;
}

bool ShotLocalFrame(const Cloud& cloud, int center, const std::vector<int>& neighbors,
                    const std::vector<float>& sqr_dists, float radius_m, Eigen::Matrix3f* lrf) {
  const Eigen::Vector3f c = cloud[center].getVector3fMap();
  thread_local std::vector<Eigen::Vector3d> vij;
  vij.clear();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  double sum = 0.0;
  const float r2 = radius_m * radius_m;
  for (std::size_t i = 0; i < neighbors.size(); ++i) {
    if (sqr_dists[i] > r2) continue;
    const Eigen::Vector3f p = cloud[neighbors[i]].getVector3fMap();
    if (p == c) continue;
    const Eigen::Vector3d d = (p - c).cast<double>();
    const double weight = radius_m - std::sqrt(static_cast<double>(sqr_dists[i]));
    cov.noalias() += weight * d * d.transpose();
    sum += weight;
    vij.push_back(d);
  }
  const int n = static_cast<int>(vij.size());
  if (n < 5 || sum <= 0.0) return false;
  cov /= sum;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  if (!solver.eigenvalues().allFinite()) return false;
  Eigen::Vector3d x = solver.eigenvectors().col(2);
  Eigen::Vector3d z = solver.eigenvectors().col(0);
  // Sign disambiguation: each axis points to where most neighbours lie (ties: the median five).
  auto disambiguate = [&](Eigen::Vector3d* axis) {
    int plus = 0;
    for (const auto& d : vij)
      if (d.dot(*axis) >= 0) ++plus;
    plus = 2 * plus - n;
    if (plus == 0) {
      const int points = 5, median = n / 2;
      for (int i = -points / 2; i <= points / 2; ++i)
        if (vij[median - i].dot(*axis) > 0) ++plus;
      if (plus < points / 2 + 1) *axis = -*axis;
    } else if (plus < 0) {
      *axis = -*axis;
    }
  };
  disambiguate(&x);
  disambiguate(&z);
  lrf->row(0) = x.cast<float>().transpose();
  lrf->row(2) = z.cast<float>().transpose();
  lrf->row(1) = lrf->row(2).cross(lrf->row(0));
  return lrf->allFinite();
}

namespace {

constexpr double kRad45 = 0.78539816339744830961566084581988;
constexpr double kRad90 = 1.5707963267948966192313216916398;
constexpr double kRad135 = 2.3561944901923449288469825374596;
constexpr double kRadPi78 = 2.7488935718910690836548129603691;
constexpr int kShapeBins = 10;  // cosine bins; each volume has kShapeBins + 1 slots
constexpr int kSectors = 32;

// The SHOT histogram of one keypoint (PCL's interpolateSingleChannel); false when undefined.
bool ShotHistogram(const Cloud& cloud, const Normals& normals, int center,
                   const Eigen::Matrix3f& lrf, const std::vector<int>& neighbors,
                   const std::vector<float>& sqr_dists, float radius, float* shot) {
  std::fill(shot, shot + kShotLength, 0.0f);
  const Eigen::Vector3f c = cloud[center].getVector3fMap();
  const Eigen::Vector3f ax = lrf.row(0), ay = lrf.row(1), az = lrf.row(2);
  const double r12 = radius / 2.0, r34 = radius * 3.0 / 4.0, r14 = radius / 4.0;
  const float r2 = radius * radius;
  int used = 0;
  for (std::size_t i = 0; i < neighbors.size(); ++i) {
    if (sqr_dists[i] > r2) continue;
    const Eigen::Vector3f& normal = normals[neighbors[i]];
    if (!normal.allFinite()) continue;
    double cosine = std::clamp(static_cast<double>(normal.dot(az)), -1.0, 1.0);
    double bin_distance = ((1.0 + cosine) * kShapeBins) / 2;
    const double distance = std::sqrt(static_cast<double>(sqr_dists[i]));
    if (std::abs(distance) < 1e-15) continue;
    const Eigen::Vector3f delta = cloud[neighbors[i]].getVector3fMap() - c;
    double x = delta.dot(ax), y = delta.dot(ay), z = delta.dot(az);
    if (std::abs(y) < 1e-30) y = 0;
    if (std::abs(x) < 1e-30) x = 0;
    if (std::abs(z) < 1e-30) z = 0;
    const unsigned bit4 = ((y > 0) || ((y == 0.0) && (x < 0))) ? 1 : 0;
    const unsigned bit3 = ((x > 0) || ((x == 0.0) && (y > 0))) ? !bit4 : bit4;
    int desc_index = static_cast<int>((bit4 << 3) + (bit3 << 2)) << 1;
    if ((x * y > 0) || (x == 0.0))
      desc_index += (std::abs(x) >= std::abs(y)) ? 0 : 4;
    else
      desc_index += (std::abs(x) > std::abs(y)) ? 4 : 0;
    desc_index += z > 0 ? 1 : 0;
    desc_index += (distance > r12) ? 2 : 0;

    const int step_index = static_cast<int>(std::floor(bin_distance + 0.5));
    const int volume_index = desc_index * (kShapeBins + 1);
    bin_distance -= step_index;
    double weight = 1 - std::abs(bin_distance);
    if (bin_distance > 0)
      shot[volume_index + ((step_index + 1) % kShapeBins)] += static_cast<float>(bin_distance);
    else
      shot[volume_index + ((step_index - 1 + kShapeBins) % kShapeBins)] +=
          -static_cast<float>(bin_distance);

    // Radial interpolation between the inner and outer shells.
    if (distance > r12) {
      const double rd = (distance - r34) / r12;
      if (distance > r34) {
        weight += 1 - rd;
      } else {
        weight += 1 + rd;
        shot[(desc_index - 2) * (kShapeBins + 1) + step_index] -= static_cast<float>(rd);
      }
    } else {
      const double rd = (distance - r14) / r12;
      if (distance < r14) {
        weight += 1 + rd;
      } else {
        weight += 1 - rd;
        shot[(desc_index + 2) * (kShapeBins + 1) + step_index] += static_cast<float>(rd);
      }
    }

    // Elevation interpolation between the upper and lower hemispheres.
    const double inclination = std::acos(std::clamp(z / distance, -1.0, 1.0));
    if (inclination > kRad90 || (std::abs(inclination - kRad90) < 1e-30 && z <= 0)) {
      const double id = (inclination - kRad135) / kRad90;
      if (inclination > kRad135) {
        weight += 1 - id;
      } else {
        weight += 1 + id;
        shot[(desc_index + 1) * (kShapeBins + 1) + step_index] -= static_cast<float>(id);
      }
    } else {
      const double id = (inclination - kRad45) / kRad90;
      if (inclination < kRad45) {
        weight += 1 + id;
      } else {
        weight += 1 - id;
        shot[(desc_index - 1) * (kShapeBins + 1) + step_index] += static_cast<float>(id);
      }
    }

    // Azimuth interpolation between neighbouring sectors.
    if (y != 0.0 || x != 0.0) {
      const double azimuth = std::atan2(y, x);
      const int sel = desc_index >> 2;
      double ad = (azimuth - (-kRadPi78 + kRad45 * sel)) / kRad45;
      ad = std::max(-0.5, std::min(ad, 0.5));
      if (ad > 0) {
        weight += 1 - ad;
        const int j = (desc_index + 4) % kSectors;
        shot[j * (kShapeBins + 1) + step_index] += static_cast<float>(ad);
      } else {
        const int j = (desc_index - 4 + kSectors) % kSectors;
        weight += 1 + ad;
        shot[j * (kShapeBins + 1) + step_index] -= static_cast<float>(ad);
      }
    }
    shot[volume_index + step_index] += static_cast<float>(weight);
    ++used;
  }
  if (used == 0) return false;
  double norm = 0;
  for (int j = 0; j < kShotLength; ++j) norm += static_cast<double>(shot[j]) * shot[j];
  norm = std::sqrt(norm);
  if (!(norm > 0) || !std::isfinite(norm)) return false;
  const float inv = static_cast<float>(1.0 / norm);
  for (int j = 0; j < kShotLength; ++j) shot[j] *= inv;
  return true;
}

}  // namespace

Supports FindSupports(const Cloud& cloud, const std::vector<int>& keypoints,
                      const NeighborSearch& search, const DescribeOptions& options,
                      const ParallelFor& parallel_for) {
  Supports out;
  out.indices.resize(keypoints.size());
  out.sqr_dists.resize(keypoints.size());
  const float radius = std::max(options.shot_radius_m, options.lrf_radius_m);
  parallel_for(keypoints.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (cloud[keypoints[i]].getVector3fMap().allFinite())
        search.Radius(keypoints[i], radius, &out.indices[i], &out.sqr_dists[i]);
  });
  return out;
}

std::vector<std::uint8_t> SupportMask(const Supports& supports, std::size_t cloud_size) {
  std::vector<std::uint8_t> mask(cloud_size, 0);
  for (const auto& support : supports.indices)
    for (int j : support) mask[j] = 1;
  return mask;
}

Descriptors DescribeKeypoints(const Cloud& cloud, const Normals& normals,
                              const std::vector<int>& keypoints, const Supports& supports,
                              const DescribeOptions& options, const ParallelFor& parallel_for) {
  const std::size_t n = keypoints.size();
  std::vector<Eigen::Matrix3f> lrfs(n);
  std::vector<float> shots(n * kShotLength);
  std::vector<std::uint8_t> ok(n, 0);
  parallel_for(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const int kp = keypoints[i];
      const auto& nn = supports.indices[i];
      const auto& d2 = supports.sqr_dists[i];
      if (static_cast<int>(nn.size()) < options.min_neighbors) continue;
      if (!ShotLocalFrame(cloud, kp, nn, d2, options.lrf_radius_m, &lrfs[i])) continue;
      ok[i] = ShotHistogram(cloud, normals, kp, lrfs[i], nn, d2, options.shot_radius_m,
                            shots.data() + i * kShotLength);
    }
  });
  Descriptors out;
  for (std::size_t i = 0; i < n; ++i) {
    if (!ok[i]) continue;
    out.keypoint.push_back(keypoints[i]);
    out.lrf.push_back(lrfs[i]);
    out.shot.insert(out.shot.end(), shots.begin() + i * kShotLength,
                    shots.begin() + (i + 1) * kShotLength);
  }
  return out;
}

Descriptors DescribeKeypoints(const Cloud& cloud, const Normals& normals,
                              const std::vector<int>& keypoints, const NeighborSearch& search,
                              const DescribeOptions& options, const ParallelFor& parallel_for) {
  return DescribeKeypoints(cloud, normals, keypoints,
                           FindSupports(cloud, keypoints, search, options, parallel_for), options,
                           parallel_for);
}

}  // namespace saccade
