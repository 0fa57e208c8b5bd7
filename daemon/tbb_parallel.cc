#include "daemon/tbb_parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <memory>

namespace saccade {

ParallelFor TbbParallelFor() {
  return [](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
    if (n == 0) return;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  };
}

ParallelFor MakeTbbParallelFor(int threads) {
  auto arena =
      std::make_shared<tbb::task_arena>(threads > 0 ? threads : tbb::info::default_concurrency());
  const ParallelFor in_arena = TbbParallelFor();
  return
      [arena, in_arena](std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
        arena->execute([&] { in_arena(n, body); });
      };
}

}  // namespace saccade
