// The monotonic clock frames and latencies are stamped with (Frame::arrival_steady_ns).
#pragma once

#include <chrono>
#include <cstdint>

namespace saccade {

/// Nanoseconds on the monotonic clock, for latencies.
inline std::int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace saccade
