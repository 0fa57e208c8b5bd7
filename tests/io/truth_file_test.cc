// Pose tables recorded by others (io/formats/truth_file.h): the rows a sequence's truth gives, and
// one line naming what is wrong with a bad one.
#include "io/formats/truth_file.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace saccade {
namespace {

const char kHeader[] = "frame,T00,T01,T02,T03,T10,T11,T12,T13,T20,T21,T22,T23,T30,T31,T32,T33\n";

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(ReadPoseTable, GivesEachFramesPose) {
  // Frame 0: a quarter turn about z and a translation; frame 2: the identity; no frame 1.
  const std::string path = Write("poses.csv", std::string(kHeader) +
                                                  "0,0,-1,0,0.1,1,0,0,0.2,0,0,1,0.5,0,0,0,1\n"
                                                  "2,1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1\n");
  std::map<int, Eigen::Isometry3f> poses;
  std::string error;
  ASSERT_TRUE(ReadPoseTable(path, &poses, &error)) << error;
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses.count(1), 0u);
  EXPECT_TRUE(poses.at(0).translation().isApprox(Eigen::Vector3f(0.1f, 0.2f, 0.5f)));
  EXPECT_TRUE((poses.at(0) * Eigen::Vector3f::UnitX()).isApprox(Eigen::Vector3f(0.1f, 1.2f, 0.5f)));
  EXPECT_TRUE(poses.at(2).matrix().isIdentity());
}

TEST(ReadPoseTable, SaysWhichLineIsWrong) {
  std::map<int, Eigen::Isometry3f> poses;
  std::string error;
  EXPECT_FALSE(ReadPoseTable(Write("h.csv", "frame,x\n"), &poses, &error));
  EXPECT_NE(error.find("h.csv: line 1: expected the header 'frame,T00"), std::string::npos)
      << error;
  EXPECT_FALSE(
      ReadPoseTable(Write("short.csv", std::string(kHeader) + "0,1,0,0\n"), &poses, &error));
  EXPECT_NE(error.find("short.csv: line 2: expected 17 numbers"), std::string::npos) << error;
  EXPECT_FALSE(ReadPoseTable(
      Write("scaled.csv", std::string(kHeader) + "0,2,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1\n"), &poses,
      &error));
  EXPECT_NE(error.find("scaled.csv: line 2: not a rigid transform"), std::string::npos) << error;
  EXPECT_FALSE(ReadPoseTable(
      Write("mirror.csv", std::string(kHeader) + "0,-1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1\n"), &poses,
      &error));
  EXPECT_NE(error.find("not a rigid transform"), std::string::npos) << error;
  EXPECT_FALSE(ReadPoseTable(
      Write("twice.csv", std::string(kHeader) + "3,1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1\n"
                                                "3,1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1\n"),
      &poses, &error));
  EXPECT_NE(error.find("twice.csv: line 3: frame 3 is given twice"), std::string::npos) << error;
  EXPECT_FALSE(ReadPoseTable(::testing::TempDir() + "absent.csv", &poses, &error));
  EXPECT_NE(error.find("absent.csv: cannot open"), std::string::npos) << error;
}

TEST(ReadPoseTable, ReadsTheVispCubesTruth) {
  const std::string path =
      std::string(SACCADE_SOURCE_DIR) + "/../shared/data/visp_rbt/truth_cube.csv";
  if (!std::ifstream(path)) GTEST_SKIP() << path << " is absent (../shared/data)";
  std::map<int, Eigen::Isometry3f> poses;
  std::string error;
  ASSERT_TRUE(ReadPoseTable(path, &poses, &error)) << error;
  EXPECT_EQ(poses.size(), 99u);
  EXPECT_TRUE(poses.at(0).translation().isApprox(
      Eigen::Vector3f(-0.045396f, 0.0475708f, 0.5017975f), 1e-5f));
}

}  // namespace
}  // namespace saccade
