// The evaluation harness as a library: the runner on the synthetic Kinect's demo case, scoring,
// protocol (b)'s seeded offsets and (c)'s attention loop, and a bad cases file. cli_test.cc
// runs `saccade eval` itself.
#include "daemon/eval/evaluation.h"

#include "core/sim/scenario.h"

#include <gtest/gtest.h>

namespace saccade::eval {
namespace {

// One scene: the demo's second capture, the model cut from its first, the truth at the
// model's centroid carried by the true pose.
struct DemoScenes {
  DemoScenes() {
    const CrossCaptureCase demo = MakeDemoCase(/*seed=*/5);
    EvalModel m;
    m.cloud = demo.model;
    m.centre = *FiniteCentroid(demo.model);
    models.push_back(m);
    Scene s;
    s.frame.cloud = std::make_shared<const Cloud>(demo.scene.cloud);
    s.truth_m = demo.truth * m.centre;
    s.truth_pose = demo.truth.matrix();
    s.name = "demo";
    scenes.push_back(s);
  }
  std::vector<EvalModel> models;
  std::vector<Scene> scenes;
};

TEST(EvalRunner, FindsTheDemoTargetFromTheFoveaOnItAndAcquiresItFromAfar) {
  const DemoScenes d;
  const Runner runner(d.models, SerialFor, /*repeat=*/1);
  EvalConfiguration c;  // Saccade's defaults, foveated
  const std::vector<Eigen::Vector3f> starts = {d.scenes[0].truth_m, Eigen::Vector3f(0, 0, 1)};
  std::vector<std::vector<Trial>> trials;
  std::vector<std::vector<Acquisition>> acquisitions;
  std::string error;
  ASSERT_TRUE(runner.Run(
      c, d.scenes, starts.size(), [&](std::size_t k, std::size_t) { return starts[k]; }, &trials,
      &acquisitions, &error))
      << error;
  ASSERT_EQ(trials.size(), 2u);
  // On the object (protocol a): found in one frame, and nothing else.
  const Totals on = Score(trials[0], d.scenes, 0.08f);
  EXPECT_EQ(on.tp, 1);
  EXPECT_EQ(on.fp, 0);
  EXPECT_TRUE(trials[0][0].evidence.found);
  EXPECT_GT(trials[0][0].evidence.correct_correspondences, 0);  // the truth pose explains some
  EXPECT_EQ(acquisitions[0][0].frames, 1);
  // From (0, 0, 1) m the attention loop gets there in a few frames (protocol c).
  EXPECT_GT(acquisitions[1][0].frames, 0);
  EXPECT_LE(acquisitions[1][0].frames, 30);
}

TEST(EvalProtocols, OffObjectOffsetsAre15cmAndSeededByTheCase) {
  for (std::size_t i = 0; i < 50; ++i) {
    EXPECT_NEAR(OffObject(i).norm(), 0.15f, 1e-5f);
    EXPECT_TRUE(OffObject(i).isApprox(OffObject(i)));
  }
  EXPECT_FALSE(OffObject(0).isApprox(OffObject(1), 1e-3f));
  EXPECT_EQ(SweepOffsets().size(), 8u);
  EXPECT_FLOAT_EQ(SweepOffsets().back().x(), 0.35f);
}

TEST(EvalCases, AMissingCasesFileIsOneErrorNamingIt) {
  std::vector<EvalModel> models;
  std::vector<Scene> scenes;
  std::string error;
  EXPECT_FALSE(
      LoadCaseScenes("/nonexistent/cases.yaml", "/nonexistent", {}, 1, &models, &scenes, &error));
  EXPECT_NE(error.find("/nonexistent/cases.yaml"), std::string::npos) << error;
  EXPECT_TRUE(scenes.empty());
}

}  // namespace
}  // namespace saccade::eval
