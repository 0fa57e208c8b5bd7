// Correspondence grouping on hand-made matches: known motions recovered as proper rotations,
// consensus among random matches, too few votes.
#include "core/grouping.h"

#include "core/eval/pose_scoring.h"
#include "core/recognition.h"
#include "support/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace saccade {
namespace {

using testing::BoxCorner;
using testing::Grid;

TEST(HoughGroup, RecoversAKnownRigidMotionAsAProperRotation) {
  const Cloud model = BoxCorner();
  std::vector<std::uint8_t> mask(model.size(), 1);
  const Normals normals = KnnNormals(model, mask, 10);
  std::vector<int> all(model.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const auto kp = VoxelRepresentatives(model, all, 0.01f);
  const auto search = MakeKdTreeSearch(model, mask);
  const Descriptors md = DescribeKeypoints(model, normals, kp, *search, DescribeOptions{});

  Eigen::Affine3f X(Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1, 2, 3).normalized()));
  X.translation() = Eigen::Vector3f(0.3f, -0.2f, 0.9f);
  Cloud scene = model;
  for (auto& p : scene.points) p.getVector3fMap() = X * p.getVector3fMap();
  Descriptors sd = md;  // the same keypoints, moved: frames rotate with the cloud
  for (auto& f : sd.lrf) f = f * X.linear().transpose();
  std::vector<std::pair<int, int>> corr;
  for (int i = 0; i < static_cast<int>(md.size()); ++i) corr.emplace_back(i, i);
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& p : model.points) centroid += p.getVector3fMap();
  centroid /= static_cast<float>(model.size());
  const auto found = HoughGroup(md, model, centroid, sd, scene, corr, RecognitionOptions{});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_TRUE(found[0].model_to_scene.isApprox(X.matrix(), 1e-3f));
  const Eigen::Matrix3f R = found[0].model_to_scene.topLeftCorner<3, 3>();
  EXPECT_NEAR(R.determinant(), 1.0f, 1e-4f);
  EXPECT_EQ(found[0].votes, static_cast<int>(md.size()));
}

// Matches whose local frames agree on one pose, among matches that agree on nothing: the
// consensus is found, at that pose, with the agreeing matches as its votes.
TEST(ConsensusGroup, FindsThePoseTheAgreeingFramesGiveAmongRandomMatches) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.1f, 0.1f);
  const auto random_rotation = [&] {
    return Eigen::Quaternionf(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
  };
  Eigen::Affine3f X(Eigen::AngleAxisf(1.1f, Eigen::Vector3f(-1, 2, 1).normalized()));
  X.translation() = Eigen::Vector3f(0.2f, 0.1f, 1.1f);
  Cloud model, scene;
  Descriptors md, sd;
  std::vector<std::pair<int, int>> corr;
  const int kAgreeing = 9, kRandom = 60;
  for (int i = 0; i < kAgreeing + kRandom; ++i) {
    PointT p;
    p.getVector3fMap() = Eigen::Vector3f(u(rng), u(rng), u(rng));
    model.push_back(p);
    const Eigen::Matrix3f L = random_rotation();  // rows: the model keypoint's frame
    md.keypoint.push_back(i);
    md.lrf.push_back(L);
    PointT q = p;
    if (i < kAgreeing) {
      q.getVector3fMap() = X * p.getVector3fMap();
      // The frame turned with the object, a little off as frames from another view are.
      sd.lrf.push_back(L * X.linear().transpose() *
                       Eigen::AngleAxisf(0.02f, Eigen::Vector3f::UnitX()).matrix());
    } else {
      q.getVector3fMap() = Eigen::Vector3f(u(rng), u(rng), 1 + u(rng));
      sd.lrf.push_back(random_rotation());
    }
    scene.push_back(q);
    sd.keypoint.push_back(i);
    corr.emplace_back(i, i);
  }
  RecognitionOptions o;
  o.pose_inlier_threshold_m = 0.01f;
  const std::vector<Detection> found =
      ConsensusGroup(md, model, Eigen::Vector3f::Zero(), sd, scene, corr, o);
  ASSERT_FALSE(found.empty());
  EXPECT_TRUE(found[0].model_to_scene.isApprox(X.matrix(), 1e-3f)) << found[0].model_to_scene;
  EXPECT_EQ(found[0].votes, kAgreeing);
  for (std::size_t k = 1; k < found.size(); ++k) EXPECT_LT(found[k].votes, kAgreeing);
  // Merged with a Hough hypothesis at the same place, the pose is proposed once.
  Detection hough = found[0];
  hough.votes = 20;
  const std::vector<Detection> merged = MergeHypotheses({hough}, found, 0.02f);
  EXPECT_EQ(merged.size(), found.size());
  EXPECT_EQ(merged[0].votes, 20);
}

// Matches agree with a pose wherever on the model they lie, its farthest points included, and
// however far off the other matches lie: only scene points farther from the pose's centroid than
// the model reaches are left untried.
TEST(ConsensusGroup, CountsMatchesAtTheModelsFarthestPointsAmongFarClutter) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  Eigen::Affine3f X(Eigen::AngleAxisf(0.6f, Eigen::Vector3f(1, 1, 0).normalized()));
  X.translation() = Eigen::Vector3f(-0.3f, 0.2f, 1.4f);
  const Eigen::Vector3f centre(0.05f, -0.02f, 0.01f);
  Cloud model, scene;
  Descriptors md, sd;
  std::vector<std::pair<int, int>> corr;
  const int kAgreeing = 12, kClutter = 300;
  for (int i = 0; i < kAgreeing + kClutter; ++i) {
    PointT p, q;
    // Every agreeing model point 15 cm from the centroid: the model's reach.
    p.getVector3fMap() = centre + 0.15f * Eigen::Vector3f(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Matrix3f L = Eigen::Matrix3f::Identity();
    if (i < kAgreeing) {
      q.getVector3fMap() = X * p.getVector3fMap();
      sd.lrf.push_back(L * X.linear().transpose());
    } else {
      // Clutter over a 4 m room, its frames agreeing with nothing in particular.
      q.getVector3fMap() = 2.0f * Eigen::Vector3f(u(rng), u(rng), 1 + u(rng));
      sd.lrf.push_back(
          Eigen::AngleAxisf(3 * u(rng), Eigen::Vector3f(u(rng), u(rng), u(rng)).normalized())
              .toRotationMatrix());
    }
    model.push_back(p);
    scene.push_back(q);
    md.keypoint.push_back(i);
    md.lrf.push_back(L);
    sd.keypoint.push_back(i);
    corr.emplace_back(i, i);
  }
  RecognitionOptions o;
  o.pose_inlier_threshold_m = 0.01f;
  const std::vector<Detection> found = ConsensusGroup(md, model, centre, sd, scene, corr, o);
  ASSERT_FALSE(found.empty());
  EXPECT_TRUE(found[0].model_to_scene.isApprox(X.matrix(), 1e-3f)) << found[0].model_to_scene;
  EXPECT_EQ(found[0].votes, kAgreeing);
}

// A cube's 24 turns onto itself about its centre, its frame's axes onto each other.
std::vector<Eigen::Matrix3f> CubeTurns() {
  std::vector<Eigen::Matrix3f> out;
  for (const Eigen::Matrix4f& m : CubeRotations()) out.push_back(m.topLeftCorner<3, 3>());
  return out;
}

// A symmetric model's right matches each come from whichever of its turns the descriptor found
// nearest: 24 matches of a cube, each to the scene image of a different turn of its point. They
// vote for one centre, but no single pose explains them unless grouping knows the turns; with
// them, both groupings give one instance of every match, at a pose the cube cannot tell from X.
TEST(Grouping, ASymmetricModelsMatchesThroughItsTurnsAreOneInstance) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-0.04f, 0.04f);
  const std::vector<Eigen::Matrix3f> turns = CubeTurns();
  ASSERT_EQ(turns.size(), 24u);
  Eigen::Affine3f X(Eigen::AngleAxisf(0.9f, Eigen::Vector3f(1, -2, 1).normalized()));
  X.translation() = Eigen::Vector3f(-0.095f, 0.055f, 0.705f);  // a Hough cell's centre
  Cloud model, scene;
  Descriptors md, sd;
  std::vector<std::pair<int, int>> corr;
  for (int i = 0; i < 24; ++i) {
    PointT p;
    p.getVector3fMap() = Eigen::Vector3f(u(rng), u(rng), u(rng));
    model.push_back(p);
    const Eigen::Matrix3f L =
        Eigen::AngleAxisf(u(rng) * 40, Eigen::Vector3f(u(rng), u(rng), 1).normalized()).matrix();
    md.keypoint.push_back(i);
    md.lrf.push_back(L);
    // The scene shows the point's turn k: there its frame is L turned by k, then moved by X.
    const Eigen::Matrix3f& k = turns[std::size_t(i)];
    PointT q;
    q.getVector3fMap() = X * (k * p.getVector3fMap());
    scene.push_back(q);
    sd.keypoint.push_back(i);
    sd.lrf.push_back(L * k.transpose() * X.linear().transpose());
    corr.emplace_back(i, i);
  }
  RecognitionOptions o;
  o.hough_bin_m = 0.01f;
  o.pose_inlier_threshold_m = 0.005f;
  const Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  EXPECT_TRUE(HoughGroup(md, model, centre, sd, scene, corr, o).empty());
  for (const Detection& d : ConsensusGroup(md, model, centre, sd, scene, corr, o))
    EXPECT_LT(d.votes, 4);
  const auto as_cube = [&](const Detection& d) {
    float least = 1e9f;  // the rotation error, least over the turns
    for (const Eigen::Matrix3f& k : turns)
      least = std::min(least, Eigen::AngleAxisf(d.model_to_scene.topLeftCorner<3, 3>().transpose() *
                                                X.linear() * k)
                                  .angle());
    return least;
  };
  for (const auto& found : {HoughGroup(md, model, centre, sd, scene, corr, o, turns),
                            ConsensusGroup(md, model, centre, sd, scene, corr, o, turns)}) {
    ASSERT_FALSE(found.empty());
    EXPECT_EQ(found[0].votes, 24);
    EXPECT_LT(as_cube(found[0]), 1e-3f);
    EXPECT_LT((found[0].centroid_m - X.translation()).norm(), 1e-4f);
  }
}

TEST(HoughGroup, TooFewVotesGiveNoInstance) {
  const Cloud model = BoxCorner();
  std::vector<std::uint8_t> mask(model.size(), 1);
  const Normals normals = KnnNormals(model, mask, 10);
  const auto search = MakeKdTreeSearch(model, mask);
  const Descriptors md =
      DescribeKeypoints(model, normals, {0, 500, 1000}, *search, DescribeOptions{});
  std::vector<std::pair<int, int>> corr;
  for (int i = 0; i < static_cast<int>(md.size()); ++i) corr.emplace_back(i, i);
  EXPECT_TRUE(HoughGroup(md, model, Eigen::Vector3f::Zero(), md, model, corr, RecognitionOptions{})
                  .empty());
}

}  // namespace
}  // namespace saccade
