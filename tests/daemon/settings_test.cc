// The shipped configuration files load strictly and say what they claim.
#include "daemon/settings.h"

#include "io/config/config.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>

namespace saccade {
namespace {

const std::string kConfigs = std::string(SACCADE_SOURCE_DIR) + "/configs/";

// Every recognition and fovea option (the structs compare every field their schema names).
void ExpectSameRecognitionAndFovea(const DaemonSettings& a, const DaemonSettings& b) {
  EXPECT_TRUE(a.recognition == b.recognition);
  EXPECT_TRUE(a.fovea == b.fovea);
}

TEST(DaemonSettings, ShippedFileHoldsSaccadesDefaults) {
  // Loaded over the paper's values, the file must bring back every built-in default.
  DaemonSettings s = PaperDefaults();
  std::string error;
  ASSERT_TRUE(LoadDaemonSettings(kConfigs + "saccaded.yaml", &s, &error)) << error;
  const DaemonSettings saccade;
  ExpectSameRecognitionAndFovea(s, saccade);
  EXPECT_TRUE(s.recognition.radii_from_model);  // the defaults fit the radii to the model
  EXPECT_EQ(s.fovea.finest_level, 2);
  // The service part is the built-in defaults, written out.
  EXPECT_EQ(s.bus.url, saccade.bus.url);
  EXPECT_TRUE(s.pipeline == saccade.pipeline);
  EXPECT_TRUE(s.attention == saccade.attention);
  EXPECT_TRUE(s.tracking == saccade.tracking);
  EXPECT_EQ(s.attention.max_targets, 1);  // tracks are re-checked where they are
  EXPECT_FALSE(s.attention.predict);      // off: the paper's behaviour
  EXPECT_TRUE(s.models.empty());          // the one thing a user must set
}

TEST(DaemonSettings, PaperFileHoldsTables1And2) {
  // Loaded over Saccade's defaults, configs/paper.yaml must bring back the paper's values.
  DaemonSettings s;
  RecognitionConfig config{s.recognition, s.fovea};
  std::string error;
  ASSERT_TRUE(LoadRecognitionConfig(kConfigs + "paper.yaml", &config, &error)) << error;
  s.recognition = config.recognition;
  s.fovea = config.fovea;
  const DaemonSettings paper = PaperDefaults();
  ExpectSameRecognitionAndFovea(s, paper);
  const RecognitionOptions& r = s.recognition;
  EXPECT_FALSE(r.radii_from_model);
  EXPECT_EQ(r.scene_normal_neighbors, 10);
  EXPECT_FLOAT_EQ(r.scene_keypoint_radius_m, 0.03f);
  EXPECT_FLOAT_EQ(r.scene_shot_radius_m, 0.02f);
  EXPECT_FLOAT_EQ(r.scene_lrf_radius_m, 0.015f);
  EXPECT_FLOAT_EQ(r.model_keypoint_radius_m, 0.01f);
  EXPECT_FLOAT_EQ(r.model_shot_radius_m, 0.02f);
  EXPECT_FLOAT_EQ(r.model_lrf_radius_m, 0.015f);
  EXPECT_FLOAT_EQ(r.max_descriptor_sqr_distance, 0.25f);
  EXPECT_FLOAT_EQ(r.hough_bin_m, 0.01f);
  EXPECT_EQ(r.hough_threshold, 5);
  EXPECT_EQ(s.fovea.finest_level, 3);  // Table 2
  EXPECT_TRUE(s.fovea.inner_size_m.isApprox(Eigen::Vector3f::Constant(0.5f)));
  EXPECT_TRUE(s.fovea.outer_size_m.isApprox(Eigen::Vector3f::Constant(3.0f)));
  EXPECT_TRUE(s.fovea.outer_min_corner_m.isApprox(Eigen::Vector3f(-2.9f, -1.9f, -1.3f)));
  EXPECT_FLOAT_EQ(s.fovea.outer_keypoint_radius_m, 0.08f);
  EXPECT_FLOAT_EQ(s.fovea.inner_keypoint_radius_m, 0.02f);
}

TEST(EvalConfigurations, EntriesStartFromTheFilesDefaults) {
  const std::string path = testing::TempDir() + "defaults.yaml";
  std::ofstream(path) << "defaults:\n"
                         "  recognition: {radii_from_model: false, hough_bin_m: 0.03}\n"
                         "  fovea: {finest_level: 3}\n"
                         "configurations:\n"
                         "  - {name: a, pipeline: plain}\n"
                         "  - {name: b, pipeline: foveated, recognition: {hough_bin_m: 0.05}}\n";
  std::vector<EvalConfiguration> configs;
  std::string error;
  ASSERT_TRUE(LoadEvalConfigurations(path, RecognitionConfig{}, &configs, &error)) << error;
  ASSERT_EQ(configs.size(), 2u);
  EXPECT_FALSE(configs[0].config.recognition.radii_from_model);
  EXPECT_FLOAT_EQ(configs[0].config.recognition.hough_bin_m, 0.03f);
  EXPECT_EQ(configs[0].config.fovea.finest_level, 3);
  EXPECT_FALSE(configs[1].config.recognition.radii_from_model);
  EXPECT_FLOAT_EQ(configs[1].config.recognition.hough_bin_m, 0.05f);  // its own key wins
  EXPECT_EQ(configs[1].config.fovea.finest_level, 3);
  // Nothing but defaults and configurations at the top.
  std::ofstream(path) << "defaults: {}\nconfigurations: []\nextra: 1\n";
  EXPECT_FALSE(LoadEvalConfigurations(path, RecognitionConfig{}, &configs, &error));
  EXPECT_NE(error.find("at most 'defaults'"), std::string::npos) << error;
}

TEST(EvalConfigurations, ShippedSaccadeRowsAreTheBuiltInDefaults) {
  // The rows named "saccade" in the shipped eval files measure the defaults, whatever the
  // file's own defaults section says.
  for (const char* file : {"paper-configs.yaml", "cross-capture-configs.yaml"}) {
    SCOPED_TRACE(file);
    std::vector<EvalConfiguration> configs;
    std::string error;
    ASSERT_TRUE(LoadEvalConfigurations(kConfigs + file, RecognitionConfig{}, &configs, &error))
        << error;
    const auto row = std::find_if(configs.begin(), configs.end(),
                                  [](const EvalConfiguration& c) { return c.name == "saccade"; });
    ASSERT_NE(row, configs.end());
    EXPECT_EQ(row->pipeline, EvalConfiguration::Pipeline::kFoveated);
    DaemonSettings measured;
    measured.recognition = row->config.recognition;
    measured.fovea = row->config.fovea;
    // Except saccaded's per-frame search budget: the evaluation searches each frame whole
    // (protocol (a) is the same with it, 171/212; its attention loop, protocol (c), is not
    // budgeted); make bench-track measures the budget.
    EXPECT_EQ(measured.recognition.max_scene_keypoints, 0);
    const DaemonSettings defaults;
    measured.recognition.max_scene_keypoints = defaults.recognition.max_scene_keypoints;
    ExpectSameRecognitionAndFovea(measured, defaults);
  }
}

TEST(DaemonSettings, ShippedFileDocumentsEveryRecognitionAndFoveaKey) {
  std::ifstream in(kConfigs + "saccaded.yaml");
  ASSERT_TRUE(in.good());
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Every key of every section, from the settings' own schema (a hand radius may be there
  // commented out: it is ignored under radii_from_model).
  DaemonSettings s;
  const ConfigSchema schema = SchemaOf(&s);
  for (const auto& [key, setter] : schema.top.setters)
    EXPECT_NE(text.find("\n" + key + ":"), std::string::npos) << key << " is not in the file";
  for (const auto& [section, keys] : schema.sections) {
    EXPECT_NE(text.find("\n" + section + ":"), std::string::npos) << section;
    for (const auto& [key, setter] : keys.setters) {
      if (section == "fovea" && key == "growth_m") continue;  // the attention loop's to set
      const bool set = text.find("\n  " + key + ":") != std::string::npos;
      const bool commented = text.find("\n  # " + key + ":") != std::string::npos;
      EXPECT_TRUE(set || commented) << section << "." << key << " is not in the file";
    }
  }
}

TEST(DaemonSettings, DemoFileLoadsAndNamesAModel) {
  DaemonSettings s = PaperDefaults();
  std::string error;
  ASSERT_TRUE(LoadDaemonSettings(kConfigs + "demo.yaml", &s, &error)) << error;
  ASSERT_EQ(s.models.size(), 1u);
  EXPECT_EQ(s.service.summary, ServiceOptions::Summary::kLine);
  EXPECT_TRUE(s.IsValid(&error)) << error;
}

TEST(DaemonSettings, RobotFrameRotationMustBeAUnitQuaternion) {
  const std::string path = testing::TempDir() + "robot.yaml";
  std::ofstream(path) << "robot_frame:\n  enabled: true\n  rotation: [2, 0, 0, 0]\n";
  DaemonSettings s = PaperDefaults();
  std::string error;
  EXPECT_FALSE(LoadDaemonSettings(path, &s, &error));
  EXPECT_NE(error.find("robot_frame: rotation must be a unit quaternion"), std::string::npos)
      << error;
  std::ofstream(path) << "robot_frame:\n  enabled: true\n  translation_m: [0.1, 0, 0.5]\n"
                         "  rotation: [0.7071068, 0, 0, 0.7071068]\n";
  ASSERT_TRUE(LoadDaemonSettings(path, &s, &error)) << error;
  const Eigen::Vector3f p = s.bus.robot.RobotFromCamera() * Eigen::Vector3f(1, 0, 0);
  EXPECT_TRUE(p.isApprox(Eigen::Vector3f(0.1f, 1.0f, 0.5f), 1e-5f)) << p.transpose();
}

TEST(DaemonSettings, GrowthIsAttentionsAndRenamedKeysSayTheirNewName) {
  const std::string path = testing::TempDir() + "growth.yaml";
  std::ofstream(path) << "fovea:\n  growth_m: [0.1, 0.1, 0.1]\n";
  DaemonSettings s;
  std::string error;
  EXPECT_FALSE(LoadDaemonSettings(path, &s, &error));
  EXPECT_NE(error.find("key 'fovea.growth_m': set by the attention loop"), std::string::npos)
      << error;
  std::ofstream(path) << "fovea:\n  keypoint_radius_m_m: 0.02\n";
  EXPECT_FALSE(LoadDaemonSettings(path, &s, &error));
  EXPECT_NE(error.find("unknown key (it is now 'inner_keypoint_radius_m')"), std::string::npos)
      << error;
}

TEST(DaemonSettings, AHandRadiusUnderFittedRadiiIsWarnedAboutAndLoads) {
  const std::string path = testing::TempDir() + "radii.yaml";
  std::ofstream(path) << "recognition:\n  radii_from_model: true\n  model_shot_radius_m: 0.03\n";
  DaemonSettings s;
  std::string error;
  testing::internal::CaptureStderr();
  EXPECT_TRUE(LoadDaemonSettings(path, &s, &error)) << error;
  std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("key 'recognition.model_shot_radius_m' is ignored while radii_from_model"),
            std::string::npos)
      << err;
  // With hand radii it is used, and nothing is said.
  std::ofstream(path) << "recognition:\n  radii_from_model: false\n  model_shot_radius_m: 0.03\n";
  testing::internal::CaptureStderr();
  EXPECT_TRUE(LoadDaemonSettings(path, &s, &error)) << error;
  err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(err.find("ignored"), std::string::npos) << err;
  EXPECT_FLOAT_EQ(s.recognition.model_shot_radius_m, 0.03f);
}

}  // namespace
}  // namespace saccade
