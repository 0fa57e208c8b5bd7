// The ParallelFor that core algorithms get from the daemon: TBB.
#pragma once

#include "core/parallel.h"

namespace saccade {

/// A ParallelFor running in whatever TBB arena calls it (inside a pipeline stage: the
/// pipeline's own). Thread-safe.
ParallelFor TbbParallelFor();

/// A ParallelFor running on `threads` TBB workers (0: all cores) in an arena of its own.
/// Thread-safe.
ParallelFor MakeTbbParallelFor(int threads = 0);

}  // namespace saccade
