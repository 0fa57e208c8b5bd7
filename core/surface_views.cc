#include "core/surface_views.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace saccade {

std::vector<Eigen::Vector3f> SphereDirections(int n) {
  std::vector<Eigen::Vector3f> out;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = n == 1 ? 0 : 1 - 2 * (i + 0.5) / n;
    const double r = std::sqrt(std::max(0.0, 1 - y * y));
    out.emplace_back(float(r * std::cos(golden * i)), float(y), float(r * std::sin(golden * i)));
  }
  return out;
}

Eigen::Matrix4f LookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target) {
  const Eigen::Vector3f z = (target - eye).normalized();
  const Eigen::Vector3f a =
      std::abs(z.y()) < 0.9f ? Eigen::Vector3f::UnitY() : Eigen::Vector3f::UnitX();
  const Eigen::Vector3f x = a.cross(z).normalized();
  Eigen::Matrix4f pose = Eigen::Matrix4f::Identity();
  pose.block<3, 1>(0, 0) = x;
  pose.block<3, 1>(0, 1) = z.cross(x);
  pose.block<3, 1>(0, 2) = z;
  pose.block<3, 1>(0, 3) = eye;
  return pose;
}

float ViewDistance(float radius_m, const CameraIntrinsics& k, float at_least_m) {
  const float fit =
      radius_m * float(std::max(k.fx, k.fy)) / (0.45f * float(std::min(k.width, k.height)));
  return std::max(at_least_m, fit + radius_m);
}

SurfaceView RenderSurface(const Cloud& surface, const std::vector<Eigen::Vector3f>& normals,
                          const CameraIntrinsics& k, const Eigen::Matrix4f& camera_to_surface,
                          float disc_radius_m, float noise_at_1m_m, unsigned seed) {
  const Eigen::Matrix4f to_camera = camera_to_surface.inverse();
  const Eigen::Matrix3f rotation = to_camera.topLeftCorner<3, 3>();
  const std::size_t pixels = std::size_t(k.width) * std::size_t(k.height);
  std::vector<float> depth(pixels, std::numeric_limits<float>::infinity());
  std::vector<int> winner(pixels, -1);
  const float r2 = disc_radius_m * disc_radius_m;
  for (std::size_t i = 0; i < surface.size(); ++i) {
    if (!FinitePoint(surface[i]) || !normals[i].allFinite()) continue;
    const Eigen::Vector3f p = (to_camera * surface[i].getVector3fMap().homogeneous()).head<3>();
    if (!(p.z() > disc_radius_m)) continue;
    const Eigen::Vector3f n = rotation * normals[i];
    const Eigen::Vector2d centre = k.Project(p);
    const double reach_u = k.fx * disc_radius_m / (p.z() - disc_radius_m) + 1;
    const double reach_v = k.fy * disc_radius_m / (p.z() - disc_radius_m) + 1;
    const int u0 = std::max(0, int(std::ceil(centre.x() - reach_u)));
    const int u1 = std::min(k.width - 1, int(std::floor(centre.x() + reach_u)));
    const int v0 = std::max(0, int(std::ceil(centre.y() - reach_v)));
    const int v1 = std::min(k.height - 1, int(std::floor(centre.y() + reach_v)));
    const float plane = n.dot(p);
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        const Eigen::Vector3f ray = k.Unproject(u, v, 1.0);  // z = 1
        const float along = n.dot(ray);
        if (std::abs(along) < 1e-3f) continue;  // the disc seen edge-on
        const float z = plane / along;
        if (!(z > 0) || (z * ray - p).squaredNorm() > r2) continue;
        const std::size_t at = std::size_t(v) * std::size_t(k.width) + std::size_t(u);
        if (z < depth[at]) depth[at] = z, winner[at] = int(i);
      }
  }
  SurfaceView out;
  std::mt19937 random(seed);
  std::normal_distribution<float> normal(0, 1);
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const std::size_t at = std::size_t(v) * std::size_t(k.width) + std::size_t(u);
      if (winner[at] < 0) continue;
      float z = depth[at];
      if (noise_at_1m_m > 0) z += noise_at_1m_m * z * z * normal(random);
      PointT q = surface[std::size_t(winner[at])];
      q.getVector3fMap() = k.Unproject(u, v, z);
      out.points.push_back(q);
      out.source.push_back(winner[at]);
    }
  out.points.width = std::uint32_t(out.points.size());
  out.points.height = 1;
  return out;
}

}  // namespace saccade
