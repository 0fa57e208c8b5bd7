#include "core/shot.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace saccade {
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
