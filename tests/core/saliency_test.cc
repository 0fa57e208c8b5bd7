// Saliency for the saccade fallback: objects on a table stand out, the table and walls do not.
#include "core/saliency.h"
#include "core/sim/scenario.h"

#include <gtest/gtest.h>

namespace saccade {
namespace {

TEST(Saliency, TheLoneTargetIsTheMostSalientRegion) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    Scenario s = *ScenarioPreset("static");
    s.seed = seed;
    s.clutter.clear();
    s.target_motion.start_xz_m = {0.1f * static_cast<float>(seed) - 0.2f, 1.0f};
    const ScenarioFrame frame = RenderScenarioFrame(s, 0, CameraIntrinsics{});
    const auto regions = SalientRegions(frame.rendered.cloud, SaliencyOptions{});
    ASSERT_FALSE(regions.empty());
    EXPECT_LT((regions.front() - frame.truth.centroid_m).norm(), 0.15f) << "seed " << seed;
  }
}

TEST(Saliency, AFlatWallHasNoneAndAnUnorganizedCloudGivesNone) {
  Cloud wall(64, 48);
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u)
      wall.at(u, v).getVector3fMap() = Eigen::Vector3f(u, v, 2000) / 1000;
  SaliencyOptions o;
  o.stride_px = 4;
  // The wall's border samples face no return beyond the image: only in-image edges count.
  EXPECT_TRUE(SalientRegions(wall, o).empty());
  Cloud flat;
  flat.push_back(PointT{});
  EXPECT_TRUE(SalientRegions(flat, o).empty());
}

}  // namespace
}  // namespace saccade
