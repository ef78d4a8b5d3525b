// Vectors for the rasterizers' working memory, which every draw call allocates anew.
#pragma once

#include <tbb/scalable_allocator.h>

#include <cstddef>
#include <new>
#include <utility>
#include <vector>

namespace pbs {

// TBB's scalable allocator keeps freed large blocks for reuse: with the default one every draw
// call page-faults its buffers in afresh (about a fifth of the time of a bunny view, thousands of
// faults per drawPoints call).
template <class T>
using ScalableVector = std::vector<T, tbb::scalable_allocator<T>>;

// The same allocator, but growing a vector leaves the new elements default-initialised: floats
// are then left unwritten, for the code that fills them in place, instead of zeroed first.
template <class T>
struct UninitializedAllocator : tbb::scalable_allocator<T> {
  using tbb::scalable_allocator<T>::scalable_allocator;
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T>
using UninitializedVector = std::vector<T, UninitializedAllocator<T>>;

// At least n elements, growing without shrinking, for a buffer reused from chunk to chunk and batch
// to batch that its user fills before reading. Growth writes nothing: zeroing the point bins that
// every drawPoints call allocates anew cost about 6 instructions a point.
template <class T>
T* sized(UninitializedVector<T>& buffer, std::size_t n) {
  if (buffer.size() < n) buffer.resize(n);
  return buffer.data();
}

}  // namespace pbs
