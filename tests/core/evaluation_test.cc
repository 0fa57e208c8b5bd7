// The paper's scoring rule and its sphere-fit ground truth.
#include "core/eval/evaluation.h"
#include "core/sim/scenario.h"

#include <gtest/gtest.h>

#include <random>

namespace saccade {
namespace {

TEST(WilsonInterval, MatchesTheTextbookFiguresAndStaysInsideZeroOne) {
  const Interval a = WilsonInterval(83, 238);  // 35%: 29-41%
  EXPECT_NEAR(a.low, 0.291, 0.001);
  EXPECT_NEAR(a.high, 0.411, 0.001);
  const Interval none = WilsonInterval(0, 10), all = WilsonInterval(10, 10);
  EXPECT_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 0.278, 0.001);
  EXPECT_NEAR(all.low, 0.722, 0.001);
  EXPECT_EQ(all.high, 1.0);
  const Interval empty = WilsonInterval(0, 0);
  EXPECT_EQ(empty.low, 0.0);
  EXPECT_EQ(empty.high, 1.0);
}

TEST(SymmetricPoseDistance, ZeroForATurnThatMapsTheObjectOntoItselfNotForAShift) {
  std::vector<Eigen::Vector3f> ring;  // 12 points on a circle about z: a turn by 30 degrees
  for (int k = 0; k < 12; ++k)
    ring.emplace_back(0.1f * std::cos(k * float(EIGEN_PI) / 6),
                      0.1f * std::sin(k * float(EIGEN_PI) / 6), 0);
  const Eigen::Matrix4f I = Eigen::Matrix4f::Identity();
  Eigen::Matrix4f turn = I;
  turn.topLeftCorner<3, 3>() =
      Eigen::AngleAxisf(float(EIGEN_PI) / 6, Eigen::Vector3f::UnitZ()).matrix();
  EXPECT_NEAR(SymmetricPoseDistance(turn, I, ring), 0.0, 1e-6);
  Eigen::Matrix4f lift = I;
  lift(2, 3) = 0.01f;  // every point 1 cm off the ring's plane
  EXPECT_NEAR(SymmetricPoseDistance(lift, I, ring), 0.01, 1e-6);
  EXPECT_EQ(SymmetricPoseDistance(lift, I, {}), 0.0);
}

TEST(DiagnoseCase, NamesTheFirstStageThatLostTheTruth) {
  CaseEvidence e;
  e.correct_correspondences = 2;
  EXPECT_EQ(DiagnoseCase(e, true), CaseStage::kNoCorrectCorrespondence);
  EXPECT_EQ(DiagnoseCase(e, false), CaseStage::kNoHypothesis);  // no pose: matches unjudged
  e.correct_correspondences = 12;
  EXPECT_EQ(DiagnoseCase(e, true), CaseStage::kNoHypothesis);
  e.correct_correspondences = -1;  // matches not reported: judged by the hypotheses
  EXPECT_EQ(DiagnoseCase(e, true), CaseStage::kNoHypothesis);
  e.true_hypotheses = {Verdict::kNotChecked};
  EXPECT_EQ(DiagnoseCase(e, true), CaseStage::kNotVerified);
  e.true_hypotheses = {Verdict::kNotChecked, Verdict::kColour};
  EXPECT_EQ(DiagnoseCase(e, true), CaseStage::kRejected);
  e.true_hypotheses = {Verdict::kUnconfident, Verdict::kTakenByBetter};
  EXPECT_EQ(DiagnoseCase(e, true), CaseStage::kOutranked);
  e.found = true;
  EXPECT_EQ(DiagnoseCase(e, true), CaseStage::kFound);
}

TEST(ScoreScene, OneTruePositiveHoweverManyDetectionsLieWithinTheRadius) {
  const Eigen::Vector3f truth(0, 0, 1);
  const SceneScore s =
      ScoreScene({truth + Eigen::Vector3f(0.01f, 0, 0), truth + Eigen::Vector3f(0, 0.05f, 0),
                  truth + Eigen::Vector3f(0, 0, -0.07f)},
                 truth);
  EXPECT_EQ(s.true_positives, 1);
  EXPECT_EQ(s.false_positives, 0);
  EXPECT_NEAR(s.nearest_m, 0.01f, 1e-6f);
}

TEST(ScoreScene, JustInsideCountsAndJustOutsideIsAFalsePositive) {
  const Eigen::Vector3f truth(0.3f, -0.1f, 1.2f);
  const Eigen::Vector3f axis = Eigen::Vector3f(1, 2, 2).normalized();
  const SceneScore inside = ScoreScene({truth + axis * 0.0799f}, truth);
  EXPECT_EQ(inside.true_positives, 1);
  EXPECT_EQ(inside.false_positives, 0);
  const SceneScore outside = ScoreScene({truth + axis * 0.0801f}, truth);
  EXPECT_EQ(outside.true_positives, 0);
  EXPECT_EQ(outside.false_positives, 1);
  const SceneScore mixed = ScoreScene({truth, truth + axis * 0.5f, truth - axis * 0.2f}, truth);
  EXPECT_EQ(mixed.true_positives, 1);
  EXPECT_EQ(mixed.false_positives, 2);
  const SceneScore none = ScoreScene({}, truth);
  EXPECT_EQ(none.true_positives, 0);
  EXPECT_EQ(none.false_positives, 0);
  EXPECT_EQ(none.nearest_m, -1.0f);
}

TEST(FitSphere, RecoversTheBallOfEveryPaperProtocolSceneWithin5mm) {
  const Scenario s = *ScenarioPreset("paper-protocol");
  // As in the paper, the ball's size is known roughly: the clutter's balls (2-5 cm) are not it.
  SphereFitOptions options;
  options.min_radius_m = 0.06f;
  options.max_radius_m = 0.1f;
  for (int i = 0; i < s.frames; ++i) {
    const ScenarioFrame frame = RenderScenarioFrame(s, i, CameraIntrinsics{});
    const auto sphere = FitSphere(frame.rendered.cloud, options);
    ASSERT_TRUE(sphere) << "scene " << i;
    EXPECT_LT((sphere->centre_m - frame.truth.centroid_m).norm(), 0.005f)
        << "scene " << i << ": " << sphere->centre_m.transpose() << " r " << sphere->radius_m;
    EXPECT_NEAR(sphere->radius_m, 0.08f, 0.005f) << "scene " << i;
  }
}

TEST(FitSphere, SameSeedSameSphereAndNothingOnAPlane) {
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0, 0.001f);
  std::uniform_real_distribution<float> angle(0, 6.2831853f), height(-1, 1);
  Cloud ball;
  for (int i = 0; i < 2000; ++i) {
    const float a = angle(rng), zc = height(rng), rc = std::sqrt(1 - zc * zc);
    PointT p;
    p.getVector3fMap() =
        Eigen::Vector3f(0.1f, 0.2f, 1.0f) +
        (0.06f + noise(rng)) * Eigen::Vector3f(rc * std::cos(a), rc * std::sin(a), zc);
    ball.push_back(p);
  }
  const auto a = FitSphere(ball, SphereFitOptions{});
  const auto b = FitSphere(ball, SphereFitOptions{});
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->centre_m, b->centre_m);
  EXPECT_NEAR(a->radius_m, 0.06f, 0.002f);
  Cloud plane;
  for (int i = 0; i < 2000; ++i) {
    PointT p;
    p.getVector3fMap() = Eigen::Vector3f(height(rng), 0.3f + noise(rng), 1 + height(rng));
    plane.push_back(p);
  }
  const auto none = FitSphere(plane, SphereFitOptions{});
  // A plane holds no sphere within the radius range with more than a sliver of inliers.
  EXPECT_TRUE(!none || none->inliers < plane.size() / 10) << none->inliers;
  EXPECT_FALSE(FitSphere(Cloud{}, SphereFitOptions{}));
}

}  // namespace
}  // namespace saccade
