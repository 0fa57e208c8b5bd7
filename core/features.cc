#include "core/features.h"

#include <algorithm>
#include <cmath>

namespace saccade {
std::optional<CameraIntrinsics> EstimateIntrinsics(const Cloud& cloud) {
  if (cloud.height <= 1 || cloud.width <= 1) return std::nullopt;
  // Least squares of u = fx * (x/z) + cx and v = fy * (y/z) + cy over a sample of pixels.
  double su = 0, sa = 0, saa = 0, sau = 0, sv = 0, sb = 0, sbb = 0, sbv = 0;
  int n = 0;
  for (std::uint32_t v = 0; v < cloud.height; v += 3) {
    for (std::uint32_t u = 0; u < cloud.width; u += 3) {
      const auto& p = cloud.at(u, v);
      if (!FinitePoint(p) || p.z <= 0) continue;
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

}  // namespace saccade
