#include "attention/attention.h"

#include <gtest/gtest.h>

namespace saccade {
namespace {

Detection At(float x, float y, float z) {
  Detection d;
  d.centroid_m = Eigen::Vector3f(x, y, z);
  return d;
}

TEST(Attention, FollowsTheDetectionNearestThePreviousFovea) {
  Attention a(AttentionOptions{}, Eigen::Vector3f(0, 0, 1));
  const Fixation f = a.Update(1, 0.0, {At(1, 0, 1), At(0.1f, 0, 1)});
  EXPECT_EQ(f.mode, AttentionMode::kTracking);
  EXPECT_EQ(f.target, 1);
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.1f, 0, 1)));
  EXPECT_EQ(f.growth_m, 0.0f);
}

TEST(Attention, GrowsWhileLostThenFallsBackToFullScanAndRecovers) {
  AttentionOptions o;
  o.growth_step = 0.25f;
  o.growth_max_m = 1.0f;
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  a.Update(1, 0.0, {At(0.2f, 0, 1)});
  float last = -1;
  int frame = 2;
  for (; frame < 6; ++frame) {
    const Fixation f = a.Update(frame, 0.0, {});
    EXPECT_EQ(f.mode, AttentionMode::kSearching);
    EXPECT_GT(f.growth_m, last);
    EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.2f, 0, 1)));  // stays where it was
    last = f.growth_m;
  }
  EXPECT_FLOAT_EQ(last, 1.0f);
  EXPECT_EQ(a.Update(frame++, 0.0, {}).mode, AttentionMode::kFullScan);
  const Fixation back = a.Update(frame, 0.0, {At(0.5f, 0, 1)});
  EXPECT_EQ(back.mode, AttentionMode::kTracking);
  EXPECT_EQ(back.growth_m, 0.0f);
}

TEST(AttentionOptions, RejectsBadValues) {
  AttentionOptions o;
  o.growth_step = 0;
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("growth_step"), std::string::npos);
}

}  // namespace
}  // namespace saccade
