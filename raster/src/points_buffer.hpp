// The working memory of drawPoints: buffers that only grow, reused from chunk to chunk and tile to tile.
#pragma once

#include "scalable_vectors.hpp"

#include <cstddef>

namespace pbs::points {

// Grows without shrinking, so a buffer reused across batches is zero-filled at most once per element.
template <class T>
T* sized(ScalableVector<T>& buffer, std::size_t n) {
  if (buffer.size() < n) buffer.resize(n);
  return buffer.data();
}

}  // namespace pbs::points
