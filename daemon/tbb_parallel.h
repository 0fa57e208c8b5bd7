// The ParallelFor that core algorithms get from the daemon: TBB, in an arena of fixed size.
#pragma once

#include "core/parallel.h"

namespace saccade {

/// A ParallelFor running on `threads` TBB workers (0: all cores). Thread-safe.
ParallelFor MakeTbbParallelFor(int threads = 0);

}  // namespace saccade
