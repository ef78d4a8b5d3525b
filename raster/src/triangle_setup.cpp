// Triangle setup: per source triangle, clipping where needed, snapping, culling, the pixel box,
// the depth plane, where its shading record is to be made from, and the bin counts.
// Parallel over chunks of source triangles; each chunk's output keeps submission order.
#include "homogeneous_clip.hpp"
#include "pbs/raster/simd_clones.hpp"
#include "shading_records.hpp"
#include "tile_bins.hpp"
#include "triangle_batch.hpp"
#include "window_snap.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

namespace pbs::triangles {
namespace {

// The source triangle: what identifies it in the ids channel, and its vertices' world positions
// for the face normal.
struct SourceTriangle {
  std::uint32_t span;
  std::uint32_t primitive;
  std::uint32_t index[3];
  const ProjectedVertex* vertex[3];
};

// Whether the pixel box meets one of the rectangles.
[[gnu::always_inline]] inline bool meetsAny(const PixelBox& box, std::span<const PixelRect> rects) {
  for (const PixelRect& r : rects)
    if (box.x0 <= r.x1 && r.x0 <= box.x1 && box.y0 <= r.y1 && r.y0 <= box.y1) return true;
  return false;
}

class ChunkWriter {
 public:
  ChunkWriter(TriangleBatch& batch, std::uint32_t chunkIndex)
      : batch_(batch),
        chunk_(batch.chunks[chunkIndex]),
        chunkIndex_(chunkIndex),
        binCounts_(batch.tileCounts.data() + chunkIndex * binCount(batch)) {}

  // Inlined into setupChunk, so that it is compiled for each of its clones.
  [[gnu::always_inline]] PixelBox trianglePixelBox(const ProjectedVertex& v0, const ProjectedVertex& v1,
                                                   const ProjectedVertex& v2) const {
    const CoordinateRange x = rangeOf(v0.x, v1.x, v2.x), y = rangeOf(v0.y, v1.y, v2.y);
    return pixelBox(batch_.framebuffer, x.min, y.min, x.max, y.max);
  }

  // v0, v1, v2: the source's vertices, or where it was clipped (`clipped`) those of a triangle of its fan.
  [[gnu::always_inline]] void emit(const SourceTriangle& source, const ProjectedVertex* v0, const ProjectedVertex* v1,
                                   const ProjectedVertex* v2, bool clipped) {
    // Tested first: in a scene of distant instances most triangles cover no pixel centre, and
    // leave here cheaply.
    const PixelBox box = trianglePixelBox(*v0, *v1, *v2);
    if (box.empty()) return;
    const std::int32_t px0 = box.x0, py0 = box.y0, px1 = box.x1, py1 = box.y1;

    std::int64_t area2 = doubleArea(*v0, *v1, *v2);
    if (area2 == 0) return;
    const TriangleSpan& span = batch_.spans[source.span];
    // Negative area is counter-clockwise in clip space (y up): a front face unless mirrored.
    const bool front = (area2 < 0) != span.mirrored;
    if (!(front ? span.drawsFront : span.drawsBack) && !meetsAny(box, front ? span.frontWithin : span.backWithin))
      return;
    const bool swapped = area2 < 0;
    if (swapped) {
      std::swap(v1, v2);
      area2 = -area2;
    }

    const Barycentrics l = barycentrics(*v0, *v1, *v2, px0, py0, area2);
    const AttributePlane<double> depth = deltaPlane(l, v0->depth, v1->depth, v2->depth);
    const std::uint32_t local = std::uint32_t(chunk_.raster.size());
    const std::uint32_t spanOffset = source.span - chunk_.firstSpan;
    const bool recordNow = clipped || spanOffset >= 1u << kSourcePositionBits;
    const std::uint32_t sourceAt =
        recordNow
            ? kStoredRecord | std::uint32_t(chunk_.storedRecords.size())
            : sourceWord(span.batchStart + (source.primitive - span.firstPrimitive) - chunkIndex_ * kChunkTriangles,
                         spanOffset, swapped);
    const RasterTriangle& raster = chunk_.raster.emplace_back(RasterTriangle{{v0->x, v1->x, v2->x},
                                                                             {v0->y, v1->y, v2->y},
                                                                             std::uint16_t(px0),
                                                                             std::uint16_t(py0),
                                                                             std::uint16_t(px1),
                                                                             std::uint16_t(py1),
                                                                             float(depth.c),
                                                                             float(depth.x),
                                                                             float(depth.y),
                                                                             packTriangleId(chunkIndex_, local),
                                                                             sourceAt});
    forEachBin(batch_, raster, [&](int bin, BinCount unit) { binCounts_[bin] += unit; });
    if (recordNow) storeRecord(source, span, l, *v0, *v1, *v2, std::uint16_t(px0), std::uint16_t(py0));
  }

 private:
  // The records of clipped triangles are made now, as their vertices are not the source's; so are those
  // of triangles whose span lies too far from the chunk's first to be named in RasterTriangle::source.
  void storeRecord(const SourceTriangle& source, const TriangleSpan& span, const Barycentrics& l,
                   const ProjectedVertex& v0, const ProjectedVertex& v1, const ProjectedVertex& v2, std::uint16_t px0,
                   std::uint16_t py0) {
    const std::size_t at = chunk_.storedRecords.size();
    chunk_.storedRecords.resize(at + batch_.layoutOf(span).stride);
    const glm::vec3 face = faceNormal(*source.vertex[0], *source.vertex[1], *source.vertex[2], span.mirrored);
    writeShadingRecord(batch_, source.span, source.primitive, face, l, v0, v1, v2, px0, py0,
                       chunk_.storedRecords.data() + at);
  }

  const TriangleBatch& batch_;
  TriangleChunk& chunk_;
  std::uint32_t chunkIndex_;
  BinCount* binCounts_;
};

bool isFinite(const glm::dvec4& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && std::isfinite(c.w);
}

// A source triangle that leaves near, far or the guard band: clipped, snapped, fanned from the
// polygon's first vertex (as the reference pipeline does); attributes follow the barycentrics.
void emitClipped(const TriangleBatch& batch, ChunkWriter& writer, const SourceTriangle& source) {
  const TriangleSpan& span = batch.spans[source.span];
  const ClipVertex triangle[3] = {{clipPosition(span, source.index[0]), {1.0, 0.0, 0.0}},
                                  {clipPosition(span, source.index[1]), {0.0, 1.0, 0.0}},
                                  {clipPosition(span, source.index[2]), {0.0, 0.0, 1.0}}};
  if (!(isFinite(triangle[0].clip) && isFinite(triangle[1].clip) && isFinite(triangle[2].clip))) return;
  ClipVertex polygon[kMaxClipVertices];
  const int count = clipTriangle(triangle, batch.guardX, batch.guardY, polygon);
  ProjectedVertex clipped[kMaxClipVertices];
  const ProjectedVertex* const* s = source.vertex;
  for (int i = 0; i < count; ++i) {
    // w > 0 holds after near and far clipping for any projection that keeps the eye outside the
    // volume; a polygon touching w = 0 has no window position.
    if (!(polygon[i].clip.w > 0.0)) return;
    const WindowVertex window = snapToWindow(batch.camera, polygon[i].clip);
    const glm::vec3 b(polygon[i].barycentric);
    clipped[i] = {window.depth,
                  window.invW,
                  window.x,
                  window.y,
                  b.x * s[0]->world + b.y * s[1]->world + b.z * s[2]->world,
                  b.x * s[0]->normal + b.y * s[1]->normal + b.z * s[2]->normal,
                  b.x * s[0]->uv + b.y * s[1]->uv + b.z * s[2]->uv,
                  true};
  }
  for (int i = 1; i + 1 < count; ++i) writer.emit(source, &clipped[0], &clipped[i], &clipped[i + 1], true);
}

// Triangles first … end − 1 of a span whose vertices the batch has cached: the common case, kept
// lean. The cached range spans every index of the span within the vertex array, so one unsigned
// comparison per index both finds its vertex and skips indices past the array.
PBS_CLONE_INLINE void setupCached(const TriangleBatch& batch, ChunkWriter& writer, std::uint32_t spanIndex,
                                  std::uint32_t first, std::uint32_t end) {
  const TriangleSpan& span = batch.spans[spanIndex];
  const std::uint32_t* indices = span.draw->indices.data() + span.firstIndex;
  const ProjectedVertex* cache = batch.vertices.data() + span.cacheOffset;
  // Cached vertices are read in index order, not memory order: fetch a few triangles ahead.
  constexpr std::uint32_t kAhead = 8;
  for (std::uint32_t local = first; local < end; ++local) {
    const std::uint32_t* triangle = indices + std::size_t(local) * 3;
    if (local + kAhead < span.count)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t ahead = triangle[kAhead * 3 + k] - span.firstVertex;
        if (ahead < span.vertexCount) __builtin_prefetch(cache + ahead);
      }
    const std::uint32_t c0 = triangle[0] - span.firstVertex, c1 = triangle[1] - span.firstVertex,
                        c2 = triangle[2] - span.firstVertex;
    if (c0 >= span.vertexCount || c1 >= span.vertexCount || c2 >= span.vertexCount) continue;
    const ProjectedVertex *v0 = cache + c0, *v1 = cache + c1, *v2 = cache + c2;
    ProjectedVertex complete[3];
    if (span.deferAttributes) {
      // Only triangles that may cover a pixel centre get their vertices' attributes.
      if (v0->inside && v1->inside && v2->inside && writer.trianglePixelBox(*v0, *v1, *v2).empty()) continue;
      complete[0] = *v0, complete[1] = *v1, complete[2] = *v2;
      for (int k = 0; k < 3; ++k) completeVertex(batch, span, triangle[k], complete[k]);
      v0 = &complete[0], v1 = &complete[1], v2 = &complete[2];
    }
    // Built in each branch, so that the common early exit of emit need not build it at all.
    const auto source = [&] {
      return SourceTriangle{
          spanIndex, span.firstPrimitive + local, {triangle[0], triangle[1], triangle[2]}, {v0, v1, v2}};
    };
    if (v0->inside && v1->inside && v2->inside)
      writer.emit(source(), v0, v1, v2, false);
    else
      emitClipped(batch, writer, source());
  }
}

// The same for a span whose index range was too wide to cache: vertices projected per triangle.
void setupUncached(const TriangleBatch& batch, ChunkWriter& writer, std::uint32_t spanIndex, std::uint32_t first,
                   std::uint32_t end) {
  const TriangleSpan& span = batch.spans[spanIndex];
  const TriangleDraw& draw = *span.draw;
  ProjectedVertex projected[3];
  for (std::uint32_t local = first; local < end; ++local) {
    const std::uint32_t* triangle = draw.indices.data() + span.firstIndex + std::size_t(local) * 3;
    if (triangle[0] >= draw.positions.size() || triangle[1] >= draw.positions.size() ||
        triangle[2] >= draw.positions.size())
      continue;
    for (int k = 0; k < 3; ++k) projected[k] = projectVertex(batch, span, triangle[k]);
    const SourceTriangle source{spanIndex,
                                span.firstPrimitive + local,
                                {triangle[0], triangle[1], triangle[2]},
                                {&projected[0], &projected[1], &projected[2]}};
    if (projected[0].inside && projected[1].inside && projected[2].inside)
      writer.emit(source, &projected[0], &projected[1], &projected[2], false);
    else
      emitClipped(batch, writer, source);
  }
}

PBS_AVX2_CLONES
void setupChunk(TriangleBatch& batch, std::uint32_t chunkIndex) {
  TriangleChunk& chunk = batch.chunks[chunkIndex];
  chunk.raster.clear();
  chunk.storedRecords.clear();
  chunk.raster.reserve(kChunkTriangles);
  std::fill_n(batch.tileCounts.data() + chunkIndex * binCount(batch), binCount(batch), BinCount(0));

  const std::uint32_t begin = chunkIndex * kChunkTriangles;
  const std::uint32_t end = std::min(begin + kChunkTriangles, batch.triangleCount);
  const auto spanAfter =
      std::upper_bound(batch.spans.begin(), batch.spans.end(), begin,
                       [](std::uint32_t position, const TriangleSpan& span) { return position < span.batchStart; });
  chunk.firstSpan = std::uint32_t(spanAfter - batch.spans.begin()) - 1;
  ChunkWriter writer(batch, chunkIndex);
  // Spans are consecutive in the batch: walk those the chunk overlaps, each in one loop.
  for (std::uint32_t s = chunk.firstSpan, position = begin; position < end; ++s) {
    const TriangleSpan& span = batch.spans[s];
    const std::uint32_t first = position - span.batchStart;
    const std::uint32_t last = std::min(span.count, end - span.batchStart);
    if (span.vertexCount > 0)
      setupCached(batch, writer, s, first, last);
    else
      setupUncached(batch, writer, s, first, last);
    position = span.batchStart + last;
  }
}

// The layout of the records of flat (sampled = false) or textured spans.
ShadingLayout shadingLayout(const TriangleBatch& batch, bool sampled) {
  const Framebuffer& framebuffer = batch.framebuffer;
  const bool perspective =
      std::any_of(batch.spans.begin(), batch.spans.end(), [](const TriangleSpan& span) { return !span.affine; });
  ShadingLayout layout;
  const auto add = [&](std::uint32_t& offset, std::uint32_t floats) {
    offset = layout.stride;
    layout.stride += floats;
  };
  // Untextured colour is flat per triangle (in the header); every other channel interpolates,
  // positions and uvs over w where some span has a perspective projection (normals are
  // normalised anyway, and 1/w > 0 does not turn them).
  if (perspective && (framebuffer.has(kChannelPosition) || sampled)) add(layout.inverseW, 3);
  if (framebuffer.has(kChannelPosition)) add(layout.position, 9);
  if (framebuffer.has(kChannelNormal)) add(layout.normal, 12);
  if (sampled) add(layout.uv, 6);
  return layout;
}

}  // namespace

void setupTriangles(TriangleBatch& batch) {
  batch.layouts[0] = shadingLayout(batch, false);
  // A batch whose spans sample no texture gives its textured layout no plane of texture coordinates: its records
  // are no longer than its flat ones, and the resolve sees at once that nothing is sampled.
  const bool samples = std::any_of(batch.spans.begin(), batch.spans.end(),
                                   [](const TriangleSpan& span) { return span.texture != nullptr; });
  batch.layouts[1] = samples ? shadingLayout(batch, true) : batch.layouts[0];
  const std::uint32_t chunkCount = (batch.triangleCount + kChunkTriangles - 1) / kChunkTriangles;
  batch.chunkCount = chunkCount;
  if (batch.chunks.size() < chunkCount) batch.chunks.resize(chunkCount);
  batch.tileCounts.resize(chunkCount * binCount(batch));
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, chunkCount, 1),
                    [&](const tbb::blocked_range<std::uint32_t>& r) {
                      for (std::uint32_t c = r.begin(); c < r.end(); ++c) setupChunk(batch, c);
                    });
}

}  // namespace pbs::triangles
