// Re-rendering a capture: from its own viewpoint it is the capture again; from a moved camera
// each point lands where the new camera projects it, the nearer surface winning; a moved object
// moves and is labelled.
#include "core/sim/rerender.h"

#include "core/sim/scenario.h"

#include <gtest/gtest.h>

namespace saccade {
namespace {

const Cloud& Capture() {
  static const Cloud c = MakeDemoCase(/*seed=*/5).scene.cloud;
  return c;
}

TEST(RerenderCapture, FromItsOwnViewpointItIsTheCaptureAgain) {
  const Cloud out = RerenderCapture(Capture(), CameraIntrinsics{}, RerenderPose{});
  ASSERT_EQ(out.size(), Capture().size());
  std::size_t finite = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    ASSERT_EQ(FinitePoint(out[i]), FinitePoint(Capture()[i])) << "pixel " << i;
    if (!FinitePoint(out[i])) continue;
    ++finite;
    EXPECT_TRUE(out[i].getVector3fMap().isApprox(Capture()[i].getVector3fMap(), 1e-5f));
  }
  EXPECT_GT(finite, 50000u);  // the table and the objects on it
}

TEST(RerenderCapture, AMovedCameraSeesEachPointWhereItProjects) {
  RerenderPose pose;
  pose.X_WC = Eigen::Translation3f(0.05f, -0.02f, 0.1f) *
              Eigen::AngleAxisf(0.05f, Eigen::Vector3f::UnitY());
  const CameraIntrinsics k;
  const Cloud out = RerenderCapture(Capture(), k, pose);
  const Eigen::Isometry3f X_CW = pose.X_WC.inverse();
  // Every rendered pixel is some capture point seen from the new camera: its depth is that of a
  // capture point projecting within a pixel of it, and nothing nearer projects there.
  std::vector<float> nearest(out.size(), std::numeric_limits<float>::infinity());
  for (const PointT& w : Capture().points) {
    if (!FinitePoint(w)) continue;
    const Eigen::Vector3f p = X_CW * w.getVector3fMap();
    const Eigen::Vector2d uv = k.Project(p);
    const long u = std::lround(uv.x()), v = std::lround(uv.y());
    if (u < 0 || v < 0 || u >= k.width || v >= k.height) continue;
    float& n = nearest[std::size_t(v) * k.width + std::size_t(u)];
    n = std::min(n, p.z());
  }
  int checked = 0;
  for (std::size_t j = 0; j < out.size(); ++j) {
    if (!std::isfinite(nearest[j])) continue;
    ASSERT_TRUE(FinitePoint(out[j])) << "pixel " << j;
    EXPECT_LE(out[j].z, nearest[j] + 1e-6f) << "pixel " << j;  // nothing nearer was dropped
    ++checked;
  }
  EXPECT_GT(checked, 40000);
}

TEST(RerenderCapture, AMovedObjectMovesAndIsLabelled) {
  const CrossCaptureCase demo = MakeDemoCase(/*seed=*/5);
  RerenderPose pose;
  for (std::size_t i = 0; i < demo.scene.label.size(); ++i)
    if (demo.scene.label[i] == 1 && FinitePoint(demo.scene.cloud[i])) pose.object.push_back(int(i));
  ASSERT_GT(pose.object.size(), 500u);
  pose.object_motion_W = Eigen::Translation3f(0.1f, 0, 0);  // 10 cm to the right
  std::vector<std::uint8_t> labels;
  const Cloud out = RerenderCapture(demo.scene.cloud, CameraIntrinsics{}, pose, &labels);
  Eigen::Vector3f before = Eigen::Vector3f::Zero(), after = Eigen::Vector3f::Zero();
  for (int i : pose.object) before += demo.scene.cloud[std::size_t(i)].getVector3fMap();
  before /= float(pose.object.size());
  int labelled = 0;
  for (std::size_t j = 0; j < out.size(); ++j)
    if (labels[j]) after += out[j].getVector3fMap(), ++labelled;
  ASSERT_GT(labelled, 300);
  after /= float(labelled);
  EXPECT_NEAR(after.x() - before.x(), 0.1f, 0.01f);
  EXPECT_NEAR(after.z(), before.z(), 0.01f);
}

TEST(RerenderCapture, OtherObjectsStayAndAreLabelledApart) {
  const CrossCaptureCase demo = MakeDemoCase(/*seed=*/5);
  RerenderPose pose;
  pose.others.resize(1);
  for (std::size_t i = 0; i < demo.scene.label.size(); ++i) {
    if (!FinitePoint(demo.scene.cloud[i])) continue;
    if (demo.scene.label[i] == 1) pose.object.push_back(int(i));
    if (demo.scene.label[i] == 2) pose.others[0].push_back(int(i));
  }
  ASSERT_GT(pose.others[0].size(), 300u);
  pose.object_motion_W = Eigen::Translation3f(0.1f, 0, 0);
  std::vector<std::uint8_t> labels;
  const Cloud out = RerenderCapture(demo.scene.cloud, CameraIntrinsics{}, pose, &labels);
  // The other object's pixels are labelled 2 and show it where it was captured.
  int other = 0;
  for (std::size_t j = 0; j < out.size(); ++j) {
    if (labels[j] != 2) continue;
    EXPECT_EQ(demo.scene.label[j], 2u) << "pixel " << j;
    ++other;
  }
  EXPECT_GT(other, int(pose.others[0].size()) * 8 / 10);
}

}  // namespace
}  // namespace saccade
