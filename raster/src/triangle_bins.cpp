// Binning: each set-up triangle into the tiles its box touches (a copy or its id: tile_bins.hpp), in
// submission order: from the per-chunk counts setup made, an offset pass and a parallel fill, so the
// bins never depend on scheduling.
#include "tile_bins.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <utility>

namespace pbs::triangles {
namespace {

template <class Body>
void forEachChunk(const TriangleBatch& batch, Body body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch.chunkCount, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t c = r.begin(); c < r.end(); ++c) body(c);
                    });
}

template <class Body>
void forEachBinIndex(std::size_t count, Body body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 256), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b < r.end(); ++b) body(b);
  });
}

}  // namespace

void binTriangles(TriangleBatch& batch) {
  const std::size_t bins = binCount(batch);
  ScalableVector<BinCount>& counts = batch.tileCounts;  // [chunk][bin], counted by setup

  // Bin b holds chunk 0's triangles, then chunk 1's, …; counts become each chunk's write offsets.
  const std::size_t chunkCount = batch.chunkCount;
  ScalableVector<BinCount>& start = batch.binStart;
  start.assign(bins + 1, 0);
  forEachBinIndex(bins, [&](std::size_t b) {
    for (std::size_t c = 0; c < chunkCount; ++c) start[b + 1] += counts[c * bins + b];
  });
  for (std::size_t b = 0; b < bins; ++b) start[b + 1] += start[b];
  forEachBinIndex(bins, [&](std::size_t b) {
    BinCount offset = start[b];
    for (std::size_t c = 0; c < chunkCount; ++c) offset += std::exchange(counts[c * bins + b], offset);
  });
  batch.soleTriangles.resize(copiesPart(start[bins]));
  batch.sharedIds.resize(idsPart(start[bins]));
  forEachChunk(batch, [&](std::size_t c) {
    BinCount* offsets = counts.data() + c * bins;
    RasterTriangle* const soleTriangles = batch.soleTriangles.data();
    std::uint32_t* const sharedIds = batch.sharedIds.data();
    for (const RasterTriangle& t : batch.chunks[c].raster)
      forEachBin(batch, t, [&](int bin, BinCount unit) {
        if (unit == kSoleUnit)
          soleTriangles[copiesPart(offsets[bin])] = t;
        else
          sharedIds[idsPart(offsets[bin])] = t.id;
        offsets[bin] += unit;
      });
  });
}

}  // namespace pbs::triangles
