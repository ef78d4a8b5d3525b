// Thread-count control through TBB task arenas (no hand-made pools, no global state).
#include "pbs/raster/thread_arena.hpp"

#include <tbb/info.h>
#include <tbb/task_arena.h>

namespace pbs {

int resolveThreadCount(int threads) {
  return threads > 0 ? threads : tbb::info::default_concurrency();
}

void runWithThreads(int threads, const std::function<void()>& work) {
  tbb::task_arena arena(resolveThreadCount(threads));
  arena.execute(work);
}

}  // namespace pbs
