#include "core/frame.h"

#include <limits>

namespace saccade {

Cloud DepthToCloud(const std::uint16_t* depth_mm, const std::uint8_t* rgb,
                   const CameraIntrinsics& k) {
  Cloud cloud;
  cloud.width = static_cast<std::uint32_t>(k.width);
  cloud.height = static_cast<std::uint32_t>(k.height);
  cloud.is_dense = false;
  cloud.resize(static_cast<std::size_t>(k.width) * k.height);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
      PointT& p = cloud[i];
      if (rgb) {
        p.r = rgb[3 * i], p.g = rgb[3 * i + 1], p.b = rgb[3 * i + 2];
      } else {
        p.r = p.g = p.b = 0;
      }
      p.a = 255;
      if (depth_mm[i] == 0) {
        p.x = p.y = p.z = nan;
        continue;
      }
      p.getVector3fMap() = k.Unproject(u, v, depth_mm[i] * 0.001f);
    }
  }
  return cloud;
}

}  // namespace saccade
