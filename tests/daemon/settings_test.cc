// The shipped configuration files load strictly and say what they claim.
#include "daemon/settings.h"

#include "io/config.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

namespace saccade {
namespace {

const std::string kConfigs = std::string(SACCADE_SOURCE_DIR) + "/configs/";

TEST(DaemonSettings, ShippedFileHoldsThePaperDefaults) {
  DaemonSettings s = PaperDefaults();
  std::string error;
  ASSERT_TRUE(LoadDaemonSettings(kConfigs + "saccaded.yaml", &s, &error)) << error;
  const DaemonSettings paper = PaperDefaults();
  const RecognitionOptions& r = s.recognition;
  const RecognitionOptions table1;
  EXPECT_EQ(r.scene_normal_neighbors, table1.scene_normal_neighbors);
  EXPECT_FLOAT_EQ(r.scene_keypoint_radius_m, 0.03f);
  EXPECT_FLOAT_EQ(r.scene_shot_radius_m, 0.02f);
  EXPECT_FLOAT_EQ(r.scene_lrf_radius_m, 0.015f);
  EXPECT_FLOAT_EQ(r.model_keypoint_radius_m, 0.01f);
  EXPECT_FLOAT_EQ(r.model_shot_radius_m, 0.02f);
  EXPECT_FLOAT_EQ(r.model_lrf_radius_m, 0.015f);
  EXPECT_FLOAT_EQ(r.max_descriptor_sqr_distance, 0.25f);
  EXPECT_FLOAT_EQ(r.hough_bin_m, 0.01f);
  EXPECT_EQ(r.hough_threshold, 5);
  EXPECT_EQ(s.fovea.levels_m, 3);  // Table 2
  EXPECT_TRUE(s.fovea.inner_size_m.isApprox(Eigen::Vector3f::Constant(0.5f)));
  EXPECT_TRUE(s.fovea.outer_size_m.isApprox(Eigen::Vector3f::Constant(3.0f)));
  EXPECT_TRUE(s.fovea.outer_min_corner_m.isApprox(Eigen::Vector3f(-2.9f, -1.9f, -1.3f)));
  EXPECT_FLOAT_EQ(s.fovea.keypoint_radius_0_m, 0.08f);
  EXPECT_FLOAT_EQ(s.fovea.keypoint_radius_m_m, 0.02f);
  // The service part is the built-in defaults, written out.
  EXPECT_EQ(s.bus.url, paper.bus.url);
  EXPECT_EQ(s.frames_in_flight, paper.frames_in_flight);
  EXPECT_EQ(s.attention.growth_max_m, paper.attention.growth_max_m);
  EXPECT_EQ(s.attention.max_targets, 1);
  EXPECT_FALSE(s.attention.predict);  // off: the paper's behaviour
  EXPECT_TRUE(s.models.empty());      // the one thing a user must set
}

TEST(DaemonSettings, ShippedFileDocumentsEveryRecognitionAndFoveaKey) {
  std::ifstream in(kConfigs + "saccaded.yaml");
  ASSERT_TRUE(in.good());
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  RecognitionOptions r;
  FoveaOptions f;
  for (const ConfigKeys& keys : {RecognitionKeys(&r), FoveaKeys(&f)})
    for (const auto& [key, setter] : keys.setters)
      EXPECT_NE(text.find("\n  " + key + ":"), std::string::npos) << key << " is not in the file";
}

TEST(DaemonSettings, DemoFileLoadsAndNamesAModel) {
  DaemonSettings s = PaperDefaults();
  std::string error;
  ASSERT_TRUE(LoadDaemonSettings(kConfigs + "demo.yaml", &s, &error)) << error;
  ASSERT_EQ(s.models.size(), 1u);
  EXPECT_EQ(s.summary, "line");
  EXPECT_TRUE(s.IsValid(&error)) << error;
}

TEST(DaemonSettings, RobotFrameRotationMustBeAUnitQuaternion) {
  const std::string path = testing::TempDir() + "robot.yaml";
  std::ofstream(path) << "robot_frame:\n  enabled: true\n  rotation: [2, 0, 0, 0]\n";
  DaemonSettings s = PaperDefaults();
  std::string error;
  EXPECT_FALSE(LoadDaemonSettings(path, &s, &error));
  EXPECT_NE(error.find("robot_frame.rotation"), std::string::npos) << error;
  std::ofstream(path) << "robot_frame:\n  enabled: true\n  translation_m: [0.1, 0, 0.5]\n"
                         "  rotation: [0.7071068, 0, 0, 0.7071068]\n";
  ASSERT_TRUE(LoadDaemonSettings(path, &s, &error)) << error;
  const Eigen::Vector3f p = s.bus.robot_from_camera * Eigen::Vector3f(1, 0, 0);
  EXPECT_TRUE(p.isApprox(Eigen::Vector3f(0.1f, 1.0f, 0.5f), 1e-5f)) << p.transpose();
}

}  // namespace
}  // namespace saccade
