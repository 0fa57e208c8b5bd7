// The C library's std::rand, seeded for one caller at a time: for third-party code that draws
// from it and takes no generator of its own (FLANN's k-means++ seeding). Our own code draws from
// a seeded std::mt19937 instead.
#pragma once

#include <cstdlib>
#include <mutex>

namespace saccade {

/// The lock every seeding of std::rand holds while it draws.
std::mutex& SeededRandMutex();

/// Calls `draw()` with std::rand seeded by `seed`, so that what it draws is the same on every
/// run. std::rand is one process-wide sequence: the seeding and `draw` are one critical
/// section, so two callers at once (a model switch while another model is described) each get
/// the seeded sequence. Returns what `draw` returns.
template <typename Draw>
auto WithSeededRand(unsigned seed, Draw&& draw) -> decltype(draw()) {
  std::lock_guard<std::mutex> lock(SeededRandMutex());
  std::srand(seed);
  return draw();
}

}  // namespace saccade
