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
