// A model of several views written as one PCD and read back as its views.
#include "io/formats/cloud_io.h"
#include "io/sources/model_source.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace saccade {
namespace {

Cloud View(float x, const Eigen::Vector3f& origin, int n) {
  Cloud c;
  for (int i = 0; i < n; ++i) {
    PointT p;
    p.x = x;
    p.y = 0.001f * float(i);
    p.z = 0.5f;
    p.r = 200;
    p.g = std::uint8_t(i);
    c.push_back(p);
  }
  c.sensor_origin_ = origin.homogeneous();
  return c;
}

TEST(ModelViews, AreWrittenAsOnePcdAndReadBackAsTheirViews) {
  const std::string path = ::testing::TempDir() + "views_model.pcd";
  const std::vector<Cloud> views = {View(0.0f, {0, 0, 0}, 30), View(0.1f, {0.5f, 0, 0.5f}, 20),
                                    View(0.2f, {-0.5f, 0.1f, 0.5f}, 10)};
  std::string error;
  ASSERT_TRUE(SaveModelViews(path, views, &error)) << error;
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));
  const auto read = LoadModelViews(path, &error);
  ASSERT_TRUE(read) << error;
  ASSERT_EQ(read->size(), 3u);
  for (std::size_t v = 0; v < 3; ++v) {
    ASSERT_EQ((*read)[v].size(), views[v].size()) << v;
    EXPECT_TRUE((*read)[v].sensor_origin_.head<3>().isApprox(views[v].sensor_origin_.head<3>()))
        << v;
    EXPECT_EQ((*read)[v][5].getVector3fMap(), views[v][5].getVector3fMap()) << v;
    EXPECT_EQ((*read)[v][5].g, views[v][5].g) << v;
  }
  // Any reader of PCD files takes it as one cloud: every point, seen from all around.
  const auto merged = LoadModelCloud(path, &error);
  ASSERT_TRUE(merged) << error;
  EXPECT_EQ(merged->size(), 60u);

  // A plain PCD is one view; a file that is not a PCD says so.
  const std::string one = ::testing::TempDir() + "one_view.pcd";
  ASSERT_TRUE(SaveCloud(one, views[1], &error)) << error;
  const auto single = LoadModelViews(one, &error);
  ASSERT_TRUE(single) << error;
  ASSERT_EQ(single->size(), 1u);
  EXPECT_TRUE((*single)[0].sensor_origin_.head<3>().isApprox(views[1].sensor_origin_.head<3>()));
  const std::string junk = ::testing::TempDir() + "junk_views.pcd";
  std::ofstream(junk) << "not a cloud\n";
  EXPECT_FALSE(LoadModelViews(junk, &error));
  EXPECT_NE(error.find(junk), std::string::npos) << error;
}

}  // namespace
}  // namespace saccade
