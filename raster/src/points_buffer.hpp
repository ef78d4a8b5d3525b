// The working memory of drawPoints: buffers that only grow, reused from chunk to chunk and tile to tile.
#pragma once

#include <tbb/scalable_allocator.h>

#include <cstddef>
#include <vector>

namespace pbs::points {

// TBB's scalable allocator keeps freed large blocks for reuse: with the default one every drawPoints call
// page-faults its bins (12 bytes a point of a batch, 12 MB at 2^20 points) in afresh, thousands of faults a call.
template <class T>
using Buffer = std::vector<T, tbb::scalable_allocator<T>>;

// Grows without shrinking, so a buffer reused across batches is zero-filled at most once per element.
template <class T>
T* sized(Buffer<T>& buffer, std::size_t n) {
  if (buffer.size() < n) buffer.resize(n);
  return buffer.data();
}

}  // namespace pbs::points
