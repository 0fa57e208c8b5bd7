// Depth seen from the colour camera, and the Kinect v1's disparity.
#include "core/registration.h"

#include <gtest/gtest.h>

namespace saccade {
namespace {

TEST(Registration, TheSameCameraSeesTheSameDepth) {
  CameraIntrinsics k;
  k.width = 8, k.height = 6, k.cx = 3.5, k.cy = 2.5, k.fx = k.fy = 10;
  std::vector<std::uint16_t> depth(48);
  for (std::size_t i = 0; i < depth.size(); ++i) depth[i] = i % 5 ? 1000 + 10 * i : 0;
  std::vector<int> source;
  EXPECT_EQ(RegisterDepth(depth.data(), k, Eigen::Isometry3d::Identity(), k, &source), depth);
  for (std::size_t i = 0; i < depth.size(); ++i)
    EXPECT_EQ(source[i], depth[i] ? static_cast<int>(i) : -1);
}

TEST(Registration, APlaneMovesByTheBaselineDisparityAndTheNearerSurfaceWins) {
  CameraIntrinsics k;  // 525 px, 640x480
  std::vector<std::uint16_t> depth(640 * 480, 2000);
  // A 20 x 20 px box at 1 m in front of the 2 m wall.
  for (int v = 230; v < 250; ++v)
    for (int u = 310; u < 330; ++u) depth[v * 640 + u] = 1000;
  const Eigen::Isometry3d colour_from_depth(Eigen::Translation3d(-0.025, 0, 0));
  const auto seen = RegisterDepth(depth.data(), k, colour_from_depth, k);
  // The box shifts left by 525 * 0.025 / 1.0 = 13.1 px, the wall by 6.6 px.
  EXPECT_EQ(seen[240 * 640 + 310 - 13], 1000);
  EXPECT_EQ(seen[240 * 640 + 329 - 13], 1000);
  // Right of the box the colour camera sees wall that the box hid from the depth camera: no
  // depth there (0), then the wall.
  EXPECT_EQ(seen[240 * 640 + 318], 0);
  EXPECT_EQ(seen[240 * 640 + 326], 2000);
  EXPECT_EQ(seen[100 * 640 + 100], 2000);
  // The wall's right edge leaves a strip the depth camera did not see.
  EXPECT_EQ(seen[100 * 640 + 639], 0);
}

TEST(Registration, FinerColourPixelsDoNotTear) {
  CameraIntrinsics depth_k, colour_k;
  depth_k.fx = depth_k.fy = 580 * 0.5, depth_k.width = 320, depth_k.height = 240;
  depth_k.cx = 159.5, depth_k.cy = 119.5;
  std::vector<std::uint16_t> depth(320 * 240, 1500);
  const auto seen = RegisterDepth(depth.data(), depth_k, Eigen::Isometry3d::Identity(), colour_k);
  int holes = 0;
  // Inside the depth camera's narrower field of view (u 30-609, v 22-457).
  for (int v = 30; v < 450; ++v)
    for (int u = 40; u < 600; ++u) holes += seen[v * 640 + u] == 0;
  EXPECT_EQ(holes, 0);
}

TEST(Registration, KinectDisparityRoundTripsWithinOneStep) {
  EXPECT_EQ(KinectDisparityToMm(kKinectNoDisparity), 0);
  EXPECT_EQ(MmToKinectDisparity(0), kKinectNoDisparity);
  EXPECT_EQ(MmToKinectDisparity(200), kKinectNoDisparity);  // nearer than the sensor sees
  EXPECT_EQ(KinectDisparityToMm(0), 300);
  for (int mm = 400; mm <= 8000; mm += 7) {
    const std::uint16_t raw = MmToKinectDisparity(static_cast<std::uint16_t>(mm));
    ASSERT_LT(raw, 1053);
    const int back = KinectDisparityToMm(raw);
    // Half a disparity step: dz = z^2 * 0.0030711016 / 2 (in metres).
    const double half_step_mm = 1e-3 * mm * mm * 0.0030711016 / 2 + 1;
    EXPECT_NEAR(back, mm, half_step_mm) << mm;
  }
}

}  // namespace
}  // namespace saccade
