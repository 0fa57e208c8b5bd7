// Hypothesis verification without ../shared/data: the synthetic Kinect's demo case (a model of
// the target cut from one capture, searched in another among clutter) with the true pose
// nudged and three wrong ones. recognition_test.cc has the same on the real milk scene.
#include "core/verification.h"

#include "core/recognition.h"
#include "core/sim/scenario.h"

#include <gtest/gtest.h>

namespace saccade {
namespace {

TEST(VerifyInstances, OnTheSyntheticKinectKeepsTheTruePoseAndSaysWhyTheOthersWentOut) {
  const CrossCaptureCase demo = MakeDemoCase(/*seed=*/5);
  std::string error;
  const auto model = DescribeModel(demo.model, RecognitionOptions{}, &error);
  ASSERT_TRUE(model) << error;
  const Cloud& scene = demo.scene.cloud;
  const Eigen::Vector3f c = model->centroid();
  // X_CO moved by `t` (camera frame) and turned by R about the model's centroid.
  const auto posed = [&](const Eigen::Matrix3f& R, const Eigen::Vector3f& t) {
    const Eigen::Affine3f about_centre = Eigen::Translation3f(c) * R * Eigen::Translation3f(-c);
    Detection d;
    d.model_to_scene = (Eigen::Translation3f(t) * demo.truth * about_centre).matrix();
    d.centroid_m = (Eigen::Affine3f(d.model_to_scene) * c);
    d.votes = 10;
    return d;
  };
  const Eigen::Matrix3f I = Eigen::Matrix3f::Identity();
  const Eigen::Matrix3f upside_down =
      Eigen::AngleAxisf(float(EIGEN_PI), Eigen::Vector3f::UnitZ()).matrix();
  const std::vector<Detection> hypotheses = {
      posed(I, {0.3f, 0, 0}),         // beside the target, on the table
      posed(upside_down, {0, 0, 0}),  // in place, upside down
      posed(I, {0, 0, -0.1f}),        // 10 cm in front of what the sensor saw
      posed(I, {0.01f, 0, 0}),        // the truth, 1 cm off: ICP pulls it back
  };
  std::vector<Verdict> verdicts;
  const std::vector<Detection> kept =
      VerifyInstances(model->verification(), c, scene, CameraIntrinsics{}, hypotheses,
                      RecognitionOptions{}.verify, SerialFor, &verdicts);
  ASSERT_EQ(kept.size(), 1u);
  const PoseError e = ComparePoses(kept[0].model_to_scene, demo.truth.matrix(), c);
  EXPECT_LT(e.translation_m, 0.005);
  EXPECT_LT(e.rotation_deg, 3.0);
  EXPECT_GT(kept[0].confidence, 0.5f);
  ASSERT_EQ(verdicts.size(), hypotheses.size());
  EXPECT_EQ(verdicts[3], Verdict::kKept);
  for (int i = 0; i < 3; ++i) EXPECT_NE(verdicts[i], Verdict::kKept) << "hypothesis " << i;
  EXPECT_EQ(verdicts[2], Verdict::kNoFit) << VerdictName(verdicts[2]);  // in front of the surface
}

// A 10 cm square 1 m ahead (points `step_m` apart, camera frame) and an organized frame that
// sees it there and `around` elsewhere (NaN: no return).
std::vector<Eigen::Vector3f> Square(float step_m) {
  std::vector<Eigen::Vector3f> square;
  for (float x = -0.05f; x <= 0.05f; x += step_m)
    for (float y = -0.05f; y <= 0.05f; y += step_m) square.emplace_back(x, y, 1.0f);
  return square;
}

Cloud SquareScene(const CameraIntrinsics& k, float around) {
  Cloud c(k.width, k.height);
  const Eigen::Vector2d lo = k.Project({-0.05f, -0.05f, 1}), hi = k.Project({0.05f, 0.05f, 1});
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const bool on = u >= lo.x() && u <= hi.x() && v >= lo.y() && v <= hi.y();
      const float z = on ? 1.0f : around;
      c.at(u, v).getVector3fMap() = k.Unproject(u, v, 1.0f) * (std::isfinite(z) ? z : NAN);
    }
  return c;
}

TEST(ContinuedShare, APatchOfAWallHasNoOutlineAndAnObjectHasOne) {
  const CameraIntrinsics k;
  const std::vector<Eigen::Vector3f> square = Square(0.005f);
  const float tolerance = 0.016f;
  EXPECT_FLOAT_EQ(ContinuedShare(square, 0.005f, SquareScene(k, 1.0f), k, tolerance), 1.0f);
  EXPECT_FLOAT_EQ(ContinuedShare(square, 0.005f, SquareScene(k, 1.5f), k, tolerance), 0.0f);
  EXPECT_FLOAT_EQ(ContinuedShare(square, 0.005f, SquareScene(k, NAN), k, tolerance), 0.0f);
  // Something in front all around: nothing to count.
  EXPECT_FLOAT_EQ(ContinuedShare(square, 0.005f, SquareScene(k, 0.6f), k, tolerance), -1.0f);
  EXPECT_FLOAT_EQ(ContinuedShare({}, 0.005f, SquareScene(k, 1.0f), k, tolerance), -1.0f);
}

// A plate fits a wall as well as it fits itself: verification keeps the plate held up in front
// of a far wall and drops the same fit on a wall (no outline), whatever its confidence.
TEST(VerifyInstances, DropsAFitWithoutAnOutlineOfItsOwn) {
  const CameraIntrinsics k;
  Cloud plate;
  std::vector<Eigen::Vector3f> normals;
  for (const Eigen::Vector3f& p : Square(0.0025f)) {
    PointT q;
    q.getVector3fMap() = p - Eigen::Vector3f(0, 0, 1);  // the plate's own frame
    plate.push_back(q);
    normals.emplace_back(0, 0, -1);
  }
  const VerificationModel model = MakeVerificationModel(plate, normals, 600);
  EXPECT_GT(model.spacing_m, 0.002f);
  Detection on;
  on.model_to_scene(2, 3) = 1.0f;  // 1 m ahead, where the scenes show it
  on.votes = 20;
  const VerificationOptions options;
  for (const float around : {1.5f, 1.0f}) {
    std::vector<Verdict> verdicts;
    const auto kept = VerifyInstances(model, Eigen::Vector3f::Zero(), SquareScene(k, around), k,
                                      {on}, options, SerialFor, &verdicts);
    ASSERT_EQ(verdicts.size(), 1u);
    if (around > 1.0f) {
      ASSERT_EQ(kept.size(), 1u) << VerdictName(verdicts[0]);
      // Not 0: the model's subset leaves gaps wider than the cells in places (every third
      // point of each row), and the frame shows the plate in them.
      EXPECT_LT(kept[0].continued, 0.3f);
    } else {
      EXPECT_TRUE(kept.empty());
      EXPECT_EQ(verdicts[0], Verdict::kNoOutline) << VerdictName(verdicts[0]);
    }
  }
}

TEST(InstanceConfidence, RisesWithEachFigureAndStaysAProbability) {
  Detection d;
  d.votes = 10, d.fitness = 0.9f, d.coverage = 0.7f, d.colour_agreement = 0.6f;
  const float base = InstanceConfidence(d, 1.0f);
  EXPECT_GT(base, 0.0f);
  EXPECT_LT(base, 1.0f);
  Detection more = d;
  more.colour_agreement = 0.9f;
  EXPECT_GT(InstanceConfidence(more, 1.0f), base);
  more = d;
  more.votes = 40;
  EXPECT_GT(InstanceConfidence(more, 1.0f), base);
  EXPECT_LT(InstanceConfidence(d, 0.5f), base);  // a weaker second instance of the frame
  Detection grey = d;
  grey.colour_agreement = -1;  // no colour measured: the model without colour answers
  const float g = InstanceConfidence(grey, 1.0f);
  EXPECT_GT(g, 0.0f);
  EXPECT_LT(g, 1.0f);
}

TEST(TextureAgreement, SaysWhetherAPrintedPatternLinesUpAndNothingOnAPlainSurface) {
  // A stripe pattern of 60 points; the scene sees it brighter (another exposure), shifted by
  // half a stripe (a pose slid along the print), or as a plain grey surface.
  Cloud model, brighter, shifted, plain;
  std::vector<int> index;
  const auto grey = [](int level) {
    PointT p;
    p.r = p.g = p.b = std::uint8_t(level);
    return p;
  };
  for (int i = 0; i < 60; ++i) {
    const bool dark = (i / 5) % 2 == 0, dark_shifted = ((i + 5) / 5) % 2 == 0;
    model.push_back(grey(dark ? 40 : 200));
    brighter.push_back(grey(dark ? 90 : 250));
    shifted.push_back(grey(dark_shifted ? 40 : 200));
    plain.push_back(grey(120 + i % 3));
    index.push_back(i);
  }
  EXPECT_NEAR(TextureAgreement(model, index, brighter, index), 1.0f, 1e-4f);
  EXPECT_LT(TextureAgreement(model, index, shifted, index), -0.9f);
  EXPECT_EQ(TextureAgreement(model, index, plain, index), -1.0f);  // nothing to compare
  const std::vector<int> few(index.begin(), index.begin() + 10);
  EXPECT_EQ(TextureAgreement(model, few, brighter, few), -1.0f);  // too few pairs
}

}  // namespace
}  // namespace saccade
