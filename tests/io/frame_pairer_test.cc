// Depth and colour frames paired by timestamp (io/sources/frame_pairer.h), with frames as numbers.
#include "io/sources/frame_pairer.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace saccade {
namespace {

struct Recorder {
  std::vector<std::pair<int, int>> delivered;  // (depth, colour or -1)
  FramePairer<int, int> pairer{10, [this](const int& depth, const int* colour) {
                                 delivered.push_back({depth, colour ? *colour : -1});
                               }};
};

TEST(FramePairer, EachDepthFrameTakesTheNearestColourWhicheverComesFirst) {
  Recorder r;
  r.pairer.AddColour(100, 0);  // colour first
  r.pairer.AddDepth(1, 2);
  r.pairer.AddDepth(2, 33);  // depth first
  r.pairer.AddColour(133, 35);
  r.pairer.AddColour(166, 66);
  r.pairer.AddColour(165, 62);  // nearer to 63 than 66 is, and in time
  r.pairer.AddDepth(3, 63);
  EXPECT_EQ(r.delivered, (std::vector<std::pair<int, int>>{{1, 100}, {2, 133}, {3, 165}}));
  EXPECT_EQ(r.pairer.unpaired(), 0u);
}

TEST(FramePairer, ADepthFrameWhoseColourNeverComesIsDeliveredInOrderWithout) {
  Recorder r;
  r.pairer.AddDepth(1, 0);
  r.pairer.AddDepth(2, 33);
  EXPECT_TRUE(r.delivered.empty());  // both wait
  r.pairer.AddColour(233, 34);       // 2's colour; the colour stream is past 1's time
  EXPECT_EQ(r.delivered, (std::vector<std::pair<int, int>>{{1, -1}, {2, 233}}));
  EXPECT_EQ(r.pairer.unpaired(), 1u);
}

TEST(FramePairer, NoMoreThanThreeDepthFramesWaitAndFlushDeliversTheRest) {
  Recorder r;
  for (int i = 0; i < 5; ++i) r.pairer.AddDepth(i, 33 * i);  // no colour stream at all
  EXPECT_EQ(r.delivered, (std::vector<std::pair<int, int>>{{0, -1}, {1, -1}}));
  r.pairer.Flush();
  EXPECT_EQ(r.delivered.size(), 5u);
  EXPECT_EQ(r.delivered.back(), std::make_pair(4, -1));
  EXPECT_EQ(r.pairer.unpaired(), 5u);
  r.pairer.AddDepth(9, 1000);
  r.pairer.Clear();  // forgets without delivering
  r.pairer.Flush();
  EXPECT_EQ(r.delivered.size(), 5u);
}

}  // namespace
}  // namespace saccade
