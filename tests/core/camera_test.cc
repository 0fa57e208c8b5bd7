// Camera geometry: projection and unprojection are inverses over many seeded random points.
#include "core/camera.h"

#include <gtest/gtest.h>

#include <random>

namespace saccade {
namespace {

TEST(CameraIntrinsics, UnprojectThenProjectReturnsThePixelAndTheDepth) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> focal(300, 900), pixel(0, 640), depth(0.3, 8);
  for (int trial = 0; trial < 1000; ++trial) {
    CameraIntrinsics k;
    k.fx = focal(rng), k.fy = focal(rng), k.cx = pixel(rng) / 2 + 160, k.cy = pixel(rng) / 2 + 80;
    const double u = pixel(rng), v = pixel(rng) * 0.75, z = depth(rng);
    const Eigen::Vector3f p = k.Unproject(u, v, z);
    EXPECT_FLOAT_EQ(p.z(), static_cast<float>(z));
    const Eigen::Vector2d uv = k.Project(p);
    // Float storage of the point: within a thousandth of a pixel.
    EXPECT_NEAR(uv.x(), u, 1e-3) << "trial " << trial;
    EXPECT_NEAR(uv.y(), v, 1e-3) << "trial " << trial;
  }
}

TEST(CameraIntrinsics, ThePrincipalPointLooksDownTheOpticalAxis) {
  const CameraIntrinsics k;
  EXPECT_TRUE(k.Unproject(k.cx, k.cy, 2.0).isApprox(Eigen::Vector3f(0, 0, 2)));
  EXPECT_TRUE(k.Project(Eigen::Vector3f(0, 0, 3)).isApprox(Eigen::Vector2d(k.cx, k.cy)));
  // Right and down in the image are +x and +y in the camera frame.
  EXPECT_GT(k.Unproject(k.cx + 10, k.cy, 1).x(), 0);
  EXPECT_GT(k.Unproject(k.cx, k.cy + 10, 1).y(), 0);
}

}  // namespace
}  // namespace saccade
