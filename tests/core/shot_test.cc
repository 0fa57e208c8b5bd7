// SHOT descriptors and local frames: no NaN ever leaves them.
#include "core/shot.h"

#include "support/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace saccade {
namespace {

using testing::BoxCorner;
using testing::Grid;

TEST(Describe, NaNPointsAndNormalsNeverProduceNaNDescriptors) {
  Cloud c = BoxCorner();
  for (std::size_t i = 0; i < c.size(); i += 7) c[i].x = std::numeric_limits<float>::quiet_NaN();
  std::vector<std::uint8_t> mask(c.size(), 1);
  Normals normals = KnnNormals(c, mask, 10);
  for (std::size_t i = 0; i < normals.size(); i += 3) normals[i].setConstant(NAN);
  std::vector<int> keypoints;
  for (int i = 0; i < static_cast<int>(c.size()); i += 40) keypoints.push_back(i);
  const auto search = MakeKdTreeSearch(c, mask);
  const Descriptors d = DescribeKeypoints(c, normals, keypoints, *search, DescribeOptions{});
  ASSERT_GT(d.size(), 0u);
  for (float v : d.shot) ASSERT_TRUE(std::isfinite(v));
  for (const auto& f : d.lrf) {
    ASSERT_TRUE(f.allFinite());
    EXPECT_NEAR(f.determinant(), 1.0f, 1e-3f);
  }
}

}  // namespace
}  // namespace saccade
