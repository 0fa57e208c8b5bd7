// core/seeded_rand.h: std::rand seeded for one caller at a time.
#include "core/seeded_rand.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <thread>
#include <vector>

namespace saccade {
namespace {

std::array<int, 8> EightDraws() {
  std::array<int, 8> out{};
  for (int& x : out) x = std::rand();
  return out;
}

TEST(SeededRand, TheSameSeedDrawsTheSameSequenceAndAnotherSeedAnother) {
  const auto a = WithSeededRand(7, EightDraws);
  std::srand(12345);  // someone else reseeds between the two
  (void)std::rand();
  const auto b = WithSeededRand(7, EightDraws);
  const auto c = WithSeededRand(8, EightDraws);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(SeededRand, CallersAtOnceEachGetTheSeededSequence) {
  const auto expected = WithSeededRand(7, EightDraws);
  std::vector<std::array<int, 8>> got(8);
  std::vector<std::thread> threads;
  for (auto& g : got) threads.emplace_back([&g] { g = WithSeededRand(7, EightDraws); });
  for (auto& t : threads) t.join();
  for (const auto& g : got) EXPECT_EQ(g, expected);
}

}  // namespace
}  // namespace saccade
