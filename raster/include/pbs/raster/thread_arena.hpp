// Runs parallel work with a chosen number of worker threads (the `--threads` option of every command).
#pragma once

#include <functional>

namespace pbs {

// Runs `work` inside a TBB arena of `threads` workers; 0 means all hardware threads.
// Results never depend on the count: parallel code in pbs partitions work deterministically.
void runWithThreads(int threads, const std::function<void()>& work);

// The number of threads `runWithThreads(threads, …)` uses.
int resolveThreadCount(int threads);

}  // namespace pbs
