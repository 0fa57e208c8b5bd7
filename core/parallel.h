// A parallel-for that core algorithms accept from their caller, so core itself stays free of
// threads: the daemon passes one backed by TBB, tests and plain callers run serially.
#pragma once

#include <cstddef>
#include <functional>

namespace saccade {

/// Calls body(begin, end) over sub-ranges covering [0, n), possibly concurrently. The body must
/// only write to disjoint outputs per index.
using ParallelFor =
    std::function<void(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body)>;

/// The serial ParallelFor: one call covering the whole range.
inline void SerialFor(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
  if (n > 0) body(0, n);
}

}  // namespace saccade
