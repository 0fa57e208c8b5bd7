// Model description: radii fitted to the model, and bad models as errors.
#include "core/model.h"

#include "support/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace saccade {
namespace {

using testing::BoxCorner;
using testing::Grid;

TEST(FitRadii, FollowTheModelsSizeAndPointSpacing) {
  const ModelScale scale = MeasureModel(Grid(0.3f, 0.2f, 0.005f));
  EXPECT_NEAR(scale.size_m, std::hypot(0.3f, 0.2f), 1e-4f);
  EXPECT_NEAR(scale.spacing_m, 0.005f, 1e-4f);
  const RecognitionOptions base;
  const RecognitionOptions fitted = FitRadii(base, scale);
  EXPECT_NEAR(fitted.model_shot_radius_m, scale.size_m / 6, 1e-5f);
  EXPECT_EQ(fitted.scene_shot_radius_m, fitted.model_shot_radius_m);
  EXPECT_NEAR(fitted.model_lrf_radius_m, 0.75f * fitted.model_shot_radius_m, 1e-5f);
  EXPECT_NEAR(fitted.model_keypoint_radius_m, fitted.model_shot_radius_m / 4, 1e-5f);
  EXPECT_NEAR(fitted.hough_bin_m, fitted.model_shot_radius_m / 2, 1e-5f);
  EXPECT_TRUE(fitted.IsValid(nullptr));
  EXPECT_EQ(fitted.hough_threshold, base.hough_threshold);  // only radii change

  // Twice the object at half the density: every radius doubles.
  const RecognitionOptions twice = FitRadii(base, MeasureModel(Grid(0.6f, 0.4f, 0.01f)));
  EXPECT_NEAR(twice.model_shot_radius_m, 2 * fitted.model_shot_radius_m, 1e-4f);
  EXPECT_NEAR(twice.hough_bin_m, 2 * fitted.hough_bin_m, 1e-4f);

  // A small, sparse model: the support holds eight point spacings whatever its size.
  const RecognitionOptions sparse = FitRadii(base, MeasureModel(Grid(0.06f, 0.04f, 0.004f)));
  EXPECT_NEAR(sparse.model_shot_radius_m, 8 * 0.004f, 1e-4f);

  // Nothing to measure: the radii stay as given.
  const RecognitionOptions none = FitRadii(base, MeasureModel(Cloud{}));
  EXPECT_EQ(none.model_shot_radius_m, base.model_shot_radius_m);
}

TEST(DescribeModel, EmptyOrAllNaNModelIsAnError) {
  Cloud c;
  PointT p;
  p.x = p.y = p.z = NAN;
  c.push_back(p);
  std::string error;
  EXPECT_FALSE(DescribeModel(c, RecognitionOptions{}, &error));
  EXPECT_NE(error.find("no finite point"), std::string::npos);
}

}  // namespace
}  // namespace saccade

namespace saccade {
namespace {

// A capture of one point copied over every pixel (a stuck sensor, a crafted file) once made
// every neighbour search visit all 307,200 copies (minutes for one frame): copies are one place.
TEST(KnnNormals, CopiesOfOnePlaceAreSearchedAsOne) {
  Cloud same;
  PointT p;
  p.x = 0.1f, p.y = 0.2f, p.z = 1.0f;
  same.points.assign(307200, p);
  same.width = 640, same.height = 480;
  const Normals none = KnnNormals(same, std::vector<std::uint8_t>(same.size(), 1), 10);
  ASSERT_EQ(none.size(), same.size());
  EXPECT_FALSE(none.front().allFinite());  // one place: no plane through it
  EXPECT_FALSE(none.back().allFinite());

  // A plane at z = 1 m with every point there three times: the plane's normal, facing the
  // sensor at the origin, on every copy.
  Cloud plane;
  for (int copy = 0; copy < 3; ++copy)
    for (int v = 0; v < 20; ++v)
      for (int u = 0; u < 20; ++u) {
        PointT q;
        q.x = 0.005f * float(u), q.y = 0.005f * float(v), q.z = 1.0f;
        plane.push_back(q);
      }
  std::vector<std::uint8_t> mask(plane.size(), 1);
  mask[5] = 0;  // a copy whose first is not asked for still gets its own normal
  const Normals n = KnnNormals(plane, mask, 10);
  for (std::size_t i = 0; i < plane.size(); ++i) {
    if (!mask[i]) continue;
    ASSERT_TRUE(n[i].allFinite()) << i;
    EXPECT_TRUE(n[i].isApprox(Eigen::Vector3f(0, 0, -1), 1e-4f)) << i << " " << n[i].transpose();
  }
}

}  // namespace
}  // namespace saccade
