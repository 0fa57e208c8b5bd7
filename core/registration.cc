#include "core/registration.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace saccade {

namespace {
// N. Burrus' fit of the Kinect v1's disparity: 1 / z = kOffset - kScale * raw.
constexpr double kScale = 0.0030711016;
constexpr double kOffset = 3.3309495161;
constexpr double kFarthestMm = 10000.0;

// floor() for the pixel range of a footprint, without a library call (x within int's range).
int Floor(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i);
}
}  // namespace

Eigen::Isometry3d ColourFromDepth(const double t[3], const double r[3]) {
  const Eigen::Vector3d rv(r[0], r[1], r[2]);
  Eigen::Isometry3d depth_from_colour = Eigen::Isometry3d::Identity();
  if (rv.norm() > 0)
    depth_from_colour.linear() = Eigen::AngleAxisd(rv.norm(), rv.normalized()).matrix();
  depth_from_colour.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  return depth_from_colour.inverse();
}

ColourCalibration NominalKinectCalibration() {
  ColourCalibration c;
  c.depth.fx = c.depth.fy = 580.0;
  c.colour.fx = c.colour.fy = 525.0;
  // The colour camera sits at +25 mm in the depth frame: a depth-frame point is 25 mm further
  // left (-x) as the colour camera sees it.
  c.colour_from_depth = Eigen::Translation3d(-0.025, 0.0, 0.0);
  return c;
}

std::vector<std::uint16_t> RegisterDepth(const std::uint16_t* depth_mm,
                                         const CameraIntrinsics& from,
                                         const Eigen::Isometry3d& to_from,
                                         const CameraIntrinsics& to, std::vector<int>* source) {
  const std::size_t n = static_cast<std::size_t>(to.width) * to.height;
  std::vector<std::uint16_t> out(n, 0);
  if (source) source->assign(n, -1);
  // A pixel's ray turned into `to`'s frame, R (x_n, y_n, 1), from a part per column and a part
  // per row (computed once each).
  const Eigen::Matrix3d& r = to_from.linear();
  const Eigen::Vector3d t = to_from.translation();
  std::vector<Eigen::Vector3d> column(static_cast<std::size_t>(from.width));
  for (int u = 0; u < from.width; ++u) column[u] = r.col(0) * ((u - from.cx) / from.fx);
  // Half a pixel of `from`, measured in pixels of `to` at unit depth ratio.
  const double half_u = 0.5 * to.fx / from.fx, half_v = 0.5 * to.fy / from.fy;
  for (int v = 0; v < from.height; ++v) {
    const Eigen::Vector3d row = r.col(1) * ((v - from.cy) / from.fy) + r.col(2);
    for (int u = 0; u < from.width; ++u) {
      const int i = v * from.width + u;
      if (depth_mm[i] == 0) continue;
      const double z = depth_mm[i] * 0.001;
      const Eigen::Vector3d q = (column[u] + row) * z + t;
      if (!(q.z() > 0)) continue;
      const double inverse_z = 1.0 / q.z();
      const double x = to.fx * q.x() * inverse_z + to.cx, y = to.fy * q.y() * inverse_z + to.cy;
      if (!(std::abs(x) < 1e6 && std::abs(y) < 1e6)) continue;  // far outside (grazing)
      // A twentieth of a pixel more, so that neighbours' footprints overlap despite rounding.
      // (At most 8 pixels: a footprint wider than that is a grazing surface, not a pixel.)
      const double su = std::min(half_u * z * inverse_z + 0.05, 8.0);
      const double sv = std::min(half_v * z * inverse_z + 0.05, 8.0);
      // The target pixels whose centres lie within the footprint; at least the nearest one.
      int u0 = -Floor(su - x), u1 = Floor(x + su);
      int v0 = -Floor(sv - y), v1 = Floor(y + sv);
      if (u0 > u1) u0 = u1 = Floor(x + 0.5);
      if (v0 > v1) v0 = v1 = Floor(y + 0.5);
      u0 = std::max(u0, 0), v0 = std::max(v0, 0);
      u1 = std::min(u1, to.width - 1), v1 = std::min(v1, to.height - 1);
      const double mm = q.z() * 1000.0 + 0.5;
      if (mm < 1 || mm >= std::numeric_limits<std::uint16_t>::max()) continue;
      const auto z_to = static_cast<std::uint16_t>(mm);
      for (int tv = v0; tv <= v1; ++tv) {
        for (int tu = u0; tu <= u1; ++tu) {
          const std::size_t k = static_cast<std::size_t>(tv) * to.width + tu;
          if (out[k] != 0 && out[k] <= z_to) continue;  // a nearer surface is already there
          out[k] = z_to;
          if (source) (*source)[k] = i;
        }
      }
    }
  }
  return out;
}

std::uint16_t KinectDisparityToMm(std::uint16_t raw) {
  if (raw >= kKinectNoDisparity) return 0;
  const double inverse_z = kOffset - kScale * raw;
  if (!(inverse_z * kFarthestMm >= 1000.0)) return 0;  // past 10 m, or behind the sensor
  return static_cast<std::uint16_t>(std::lround(1000.0 / inverse_z));
}

std::uint16_t MmToKinectDisparity(std::uint16_t mm) {
  if (mm == 0 || mm > kFarthestMm) return kKinectNoDisparity;
  const double raw = std::round((kOffset - 1000.0 / mm) / kScale);
  if (raw < 0) return kKinectNoDisparity;  // nearer than the sensor sees
  return static_cast<std::uint16_t>(std::min(raw, 1052.0));
}

}  // namespace saccade
