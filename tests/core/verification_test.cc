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

// A 10 cm square of points 1 m ahead, 5 mm apart, against scenes that differ only around it.
TEST(ContinuedShare, APatchOfAWallHasNoOutlineAndAnObjectHasOne) {
  const CameraIntrinsics k;
  std::vector<Eigen::Vector3f> square;
  for (float x = -0.05f; x <= 0.05f; x += 0.005f)
    for (float y = -0.05f; y <= 0.05f; y += 0.005f) square.emplace_back(x, y, 1.0f);
  // The scene: the square's own depth where it projects, `around` elsewhere (NaN: no return).
  const auto scene = [&](float around) {
    Cloud c(k.width, k.height);
    const Eigen::Vector2d lo = k.Project({-0.05f, -0.05f, 1}), hi = k.Project({0.05f, 0.05f, 1});
    for (int v = 0; v < k.height; ++v)
      for (int u = 0; u < k.width; ++u) {
        const bool on = u >= lo.x() && u <= hi.x() && v >= lo.y() && v <= hi.y();
        const float z = on ? 1.0f : around;
        c.at(u, v).getVector3fMap() = k.Unproject(u, v, 1.0f) * (std::isfinite(z) ? z : NAN);
      }
    return c;
  };
  const float tolerance = 0.016f;
  EXPECT_FLOAT_EQ(ContinuedShare(square, 0.005f, scene(1.0f), k, tolerance), 1.0f);   // a wall
  EXPECT_FLOAT_EQ(ContinuedShare(square, 0.005f, scene(1.5f), k, tolerance), 0.0f);   // seen past
  EXPECT_FLOAT_EQ(ContinuedShare(square, 0.005f, scene(NAN), k, tolerance), 0.0f);    // nothing
  EXPECT_FLOAT_EQ(ContinuedShare(square, 0.005f, scene(0.6f), k, tolerance), -1.0f);  // in front
  EXPECT_FLOAT_EQ(ContinuedShare({}, 0.005f, scene(1.0f), k, tolerance), -1.0f);
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
