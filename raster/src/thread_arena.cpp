// Thread-count control through TBB task arenas (no hand-made pools).
#include "pbs/raster/thread_arena.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <optional>

namespace pbs {

int resolveThreadCount(int threads) { return threads > 0 ? threads : tbb::info::default_concurrency(); }

void runWithThreads(int threads, const std::function<void()>& work) {
  const int count = resolveThreadCount(threads);
  // TBB caps its workers at the core count; more threads than cores are asked for on purpose (to test
  // that results do not depend on the count), so the cap is raised for the duration of the work.
  std::optional<tbb::global_control> allowMore;
  if (count > tbb::info::default_concurrency()) allowMore.emplace(tbb::global_control::max_allowed_parallelism, count);
  tbb::task_arena arena(count);
  arena.execute(work);
}

}  // namespace pbs
