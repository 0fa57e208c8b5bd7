#include "core/seeded_rand.h"

namespace saccade {

std::mutex& SeededRandMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace saccade
