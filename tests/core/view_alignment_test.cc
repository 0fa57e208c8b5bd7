// Captures of one object put into one frame: the chain that leaves out an alignment no loop
// agrees with, and a real alignment of two mOSD captures against the benchmark's truth.
#include "core/view_alignment.h"

#include "core/recognition.h"
#include "io/formats/cloud_io.h"
#include "support/mosd_truth.h"
#include "support/test_data.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <limits>

namespace saccade {
namespace {

Eigen::Matrix4f Pose(float angle_z, const Eigen::Vector3f& t) {
  Eigen::Affine3f a =
      Eigen::Translation3f(t) * Eigen::AngleAxisf(angle_z, Eigen::Vector3f::UnitZ());
  return a.matrix();
}

// A capture: a few points around `at`, in its own frame.
Cloud Blob(const Eigen::Vector3f& at) {
  Cloud c;
  for (int i = 0; i < 4; ++i) {
    PointT p;
    p.getVector3fMap() = at + Eigen::Vector3f(0.01f * float(i), 0.0f, 0.0f);
    c.push_back(p);
  }
  return c;
}

TEST(ChainViews, LeavesOutAnAlignmentNoLoopAgreesWith) {
  // Four captures; capture i's points into the reference's (0) frame by truth[i].
  const std::vector<Eigen::Matrix4f> truth = {Eigen::Matrix4f::Identity(), Pose(0.5f, {0.1f, 0, 0}),
                                              Pose(1.0f, {0, 0.1f, 0}),
                                              Pose(-0.7f, {0.05f, 0.05f, 0.02f})};
  std::vector<Cloud> clouds;
  for (int i = 0; i < 4; ++i) clouds.push_back(Blob({0.0f, 0.0f, 0.5f + 0.1f * float(i)}));
  std::vector<const Cloud*> captures;
  for (const Cloud& c : clouds) captures.push_back(&c);
  std::vector<std::vector<ViewAlignment>> pairs(4, std::vector<ViewAlignment>(4));
  for (std::size_t a = 0; a < 4; ++a) {
    for (std::size_t b = 0; b < 4; ++b) {
      if (a == b) continue;
      pairs[a][b].found = true;
      pairs[a][b].overlap = 0.5f;
      pairs[a][b].pose = truth[b].inverse() * truth[a];
    }
  }
  // Capture 1 aligned wrongly to the reference, with the most overlap of all, both ways: alone,
  // the biggest overlap would place it there.
  pairs[1][0].pose = Pose(2.5f, {0.3f, -0.2f, 0.1f});
  pairs[1][0].overlap = 0.99f;
  pairs[0][1].found = false;
  std::vector<int> parent;
  const auto poses = ChainViews(pairs, captures, std::vector<bool>(4, true), 0, &parent);
  for (std::size_t i = 0; i < 4; ++i) {
    ASSERT_TRUE(poses[i]) << i;
    EXPECT_TRUE(poses[i]->isApprox(truth[i], 1e-4f)) << i << "\n" << *poses[i];
  }
  EXPECT_NE(parent[1], 0);  // reached through a capture whose loops agree
  EXPECT_EQ(parent[0], -1);
  EXPECT_LT(LoopDisagreement(pairs, poses, captures), 1.0f);
  EXPECT_GT(LoopDisagreement(pairs, poses, captures), 0.1f);  // the wrong one, out of the chain

  // Left out of `use`, a capture is not placed, and no loop passes through it. (With three
  // captures left and one wrong alignment, every loop disagrees: nothing outvotes it.)
  std::vector<bool> use(4, true);
  use[2] = false;
  const auto without = ChainViews(pairs, captures, use, 0);
  EXPECT_FALSE(without[2]);
  ASSERT_TRUE(without[1] && without[3]);
  EXPECT_TRUE(without[3]->isApprox(truth[3], 1e-4f));

  // The views placed: points into the reference frame, the sensor origin with them.
  const std::vector<Cloud> views = PlaceViews(captures, without);
  ASSERT_EQ(views.size(), 3u);
  EXPECT_TRUE(views[2].sensor_origin_.head<3>().isApprox(truth[3].topRightCorner<3, 1>()));
  const Eigen::Vector3f moved = (truth[3] * clouds[3][0].getVector3fMap().homogeneous()).head<3>();
  EXPECT_TRUE(views[2][0].getVector3fMap().isApprox(moved, 1e-5f));
}

// The coffee can's object (4) in mOSD captures test36 and test38, organized (the rest NaN).
Cloud CutCan(const std::string& relative) {
  std::string error;
  auto labelled = LoadLabelledCloud(testing::DataPath(relative), &error);
  EXPECT_TRUE(labelled) << error;
  if (!labelled) return {};
  Cloud c = labelled->cloud;
  for (std::size_t i = 0; i < c.size(); ++i)
    if (labelled->labels[i] / 10 != 4)
      c[i].x = c[i].y = c[i].z = std::numeric_limits<float>::quiet_NaN();
  return c;
}

TEST(AlignViews, PutsOneRealCaptureOfACanOnAnother) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test36.pcd");
  const Cloud a = CutCan("mosd_xcap/test/test36.pcd"), b = CutCan("mosd_xcap/test/test38.pcd");
  const Eigen::Matrix4f truth = testing::CoffeeCanTest36InTest38();
  std::string error;
  const AlignmentOptions options;
  const auto described = DescribeModel(a, options.recognition, &error);
  ASSERT_TRUE(described) << error;
  const ViewAlignment aligned = AlignViews(*described, b, options);
  ASSERT_TRUE(aligned.found) << aligned.overlap << " " << aligned.seen_through;
  EXPECT_GT(aligned.overlap, 0.8f);
  EXPECT_LT(aligned.rmse_m, 0.003f);
  EXPECT_LT(aligned.seen_through, 0.02f);
  const Eigen::Vector3f centroid = *FiniteCentroid(a);
  EXPECT_LT(ComparePoses(aligned.pose, truth, centroid).translation_m, 0.01);
  // The same can turned a quarter turn about the camera's axis and moved 10 cm is seen through.
  const Eigen::Matrix4f off = Pose(1.57f, {0.1f, 0, 0}) * aligned.pose;
  EXPECT_LT(Overlap(a, off, b, options.inlier_distance_m).first, 0.3f);
}

}  // namespace
}  // namespace saccade
