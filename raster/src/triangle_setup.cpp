// Triangle setup: per source triangle, clipping where needed, snapping, culling, the pixel box,
// the depth plane and the attribute planes of its shading record, and the bin counts.
// Parallel over chunks of source triangles; each chunk's output keeps submission order.
#include "homogeneous_clip.hpp"
#include "pbs/raster/simd_clones.hpp"
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

// Screen-space barycentrics of vertices 1 and 2 as planes over pixel offsets, so an attribute
// is a0 + λ1·(a1 − a0) + λ2·(a2 − a0).
struct Barycentrics {
  double c[2], x[2], y[2];
};

PBS_CLONE_INLINE AttributePlane<double> deltaPlane(const Barycentrics& l, double a0, double a1, double a2) {
  const double d1 = a1 - a0, d2 = a2 - a0;
  return {a0 + l.c[0] * d1 + l.c[1] * d2, l.x[0] * d1 + l.x[1] * d2, l.y[0] * d1 + l.y[1] * d2};
}

// Four float lanes holding an attribute of up to four components: one SSE register instead of a
// scalar operation per component; each lane sees the same operations in the same order as a
// component would, so the planes keep their bits.
typedef float Float4 __attribute__((vector_size(4 * sizeof(float))));

template <int N>
PBS_CLONE_INLINE Float4 toLanes(const glm::vec<N, float>& v) {
  Float4 lanes{};
  for (int i = 0; i < N; ++i) lanes[i] = v[i];
  return lanes;
}

// Lane by lane: a memcpy of three lanes goes through the stack, and the reload of the third waits
// on store forwarding.
template <int N>
PBS_CLONE_INLINE void storeLanes(float* out, const Float4& lanes) {
  for (int i = 0; i < N; ++i) out[i] = lanes[i];
}

// The plane of a/w from the vertices' attributes a and their 1/w. Attributes travel in float:
// relative to positionOrigin and to vertex 0, a float plane keeps far more digits than the float
// channel it fills.
template <int N>
PBS_CLONE_INLINE void storeAttribute(float* out, const AttributePlane<glm::vec2>& l, const glm::vec<N, float>& a0,
                                     const glm::vec<N, float>& a1, const glm::vec<N, float>& a2, float w0, float w1,
                                     float w2) {
  const Float4 p0 = toLanes(a0) * w0, p1 = toLanes(a1) * w1, p2 = toLanes(a2) * w2;
  const Float4 d1 = p1 - p0, d2 = p2 - p0;
  storeLanes<N>(out, p0 + d1 * l.c.x + d2 * l.c.y);
  storeLanes<N>(out + N, d1 * l.x.x + d2 * l.x.y);
  storeLanes<N>(out + 2 * N, d1 * l.y.x + d2 * l.y.y);
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

  [[gnu::always_inline]] void emit(const SourceTriangle& source, const ProjectedVertex* v0, const ProjectedVertex* v1,
                                   const ProjectedVertex* v2) {
    // Tested first: in a scene of distant instances most triangles cover no pixel centre, and
    // leave here cheaply.
    const PixelBox box = trianglePixelBox(*v0, *v1, *v2);
    if (box.empty()) return;
    const std::int32_t px0 = box.x0, py0 = box.y0, px1 = box.x1, py1 = box.y1;

    std::int64_t area2 = (std::int64_t(v1->x) - v0->x) * (std::int64_t(v2->y) - v0->y) -
                         (std::int64_t(v1->y) - v0->y) * (std::int64_t(v2->x) - v0->x);
    if (area2 == 0) return;
    const TriangleSpan& span = batch_.spans[source.span];
    // Negative area is counter-clockwise in clip space (y up): a front face unless mirrored.
    const bool front = (area2 < 0) != span.mirrored;
    if (span.cullBackFaces && !front) return;
    if (area2 < 0) {
      std::swap(v1, v2);
      area2 = -area2;
    }

    // λ of vertex 1 is the edge function of edge 2 → 0 over twice the area, λ of vertex 2 that of
    // edge 0 → 1 (exact in int64 up to the division), as planes from the box's first pixel centre.
    const std::int64_t half = kSubpixelScale / 2;
    const std::int64_t ox = px0 * kSubpixelScale + half, oy = py0 * kSubpixelScale + half;
    const double inverseArea = 1.0 / double(area2);
    Barycentrics l;
    const ProjectedVertex* edgeStart[2] = {v2, v0};
    const ProjectedVertex* edgeEnd[2] = {v0, v1};
    for (int i = 0; i < 2; ++i) {
      const ProjectedVertex& a = *edgeStart[i];
      const ProjectedVertex& b = *edgeEnd[i];
      const std::int64_t edgeA = std::int64_t(a.y) - b.y, edgeB = std::int64_t(b.x) - a.x;
      l.c[i] = double(edgeA * (ox - a.x) + edgeB * (oy - a.y)) * inverseArea;
      l.x[i] = double(edgeA * kSubpixelScale) * inverseArea;
      l.y[i] = double(edgeB * kSubpixelScale) * inverseArea;
    }
    const AttributePlane<double> depth = deltaPlane(l, v0->depth, v1->depth, v2->depth);
    const std::uint32_t local = std::uint32_t(chunk_.raster.size());
    const RasterTriangle& raster = chunk_.raster.emplace_back(RasterTriangle{{v0->x, v1->x, v2->x},
                                                                             {v0->y, v1->y, v2->y},
                                                                             std::uint16_t(px0),
                                                                             std::uint16_t(py0),
                                                                             std::uint16_t(px1),
                                                                             std::uint16_t(py1),
                                                                             float(depth.c),
                                                                             float(depth.x),
                                                                             float(depth.y),
                                                                             packTriangleId(chunkIndex_, local)});
    forEachBin(batch_, raster, [&](int bin, BinCount unit) { binCounts_[bin] += unit; });
    appendRecord(source, span, l, v0, v1, v2, std::uint16_t(px0), std::uint16_t(py0));
  }

 private:
  [[gnu::always_inline]] void appendRecord(const SourceTriangle& source, const TriangleSpan& span,
                                           const Barycentrics& l, const ProjectedVertex* v0, const ProjectedVertex* v1,
                                           const ProjectedVertex* v2, std::uint16_t px0, std::uint16_t py0) {
    const ShadingLayout& layout = batch_.layoutOf(span);
    const std::size_t at = chunk_.shading.size();
    if (batch_.uniformStride == 0) chunk_.recordStart.push_back(std::uint32_t(at));
    chunk_.shading.resize(at + layout.stride);
    float* const record = chunk_.shading.data() + at;
    storeHeader(record, ShadingHeader{source.span, source.primitive, px0, py0, span.flatColor});
    // 1/w and a/w are affine in the window, so dividing one by the other is perspective-correct.
    // Where w ≡ 1 the plane is exactly 1, so the division changes nothing and can be skipped.
    if (layout.inverseW != ShadingLayout::kAbsent) {
      const AttributePlane<double> q =
          span.affine ? AttributePlane<double>{1.0, 0.0, 0.0} : deltaPlane(l, v0->invW, v1->invW, v2->invW);
      storePlane<1>(record + layout.inverseW, {glm::vec1(float(q.c)), glm::vec1(float(q.x)), glm::vec1(float(q.y))});
    }
    const AttributePlane<glm::vec2> lf{
        {float(l.c[0]), float(l.c[1])}, {float(l.x[0]), float(l.x[1])}, {float(l.y[0]), float(l.y[1])}};
    const float w0 = float(v0->invW), w1 = float(v1->invW), w2 = float(v2->invW);
    if (layout.position != ShadingLayout::kAbsent)
      storeAttribute<3>(record + layout.position, lf, v0->world, v1->world, v2->world, w0, w1, w2);
    if (layout.normal != ShadingLayout::kAbsent) {
      storeAttribute<3>(record + layout.normal, lf, v0->normal, v1->normal, v2->normal, w0, w1, w2);
      storeVector(record + layout.normal + 9, faceNormal(source, span.mirrored));
    }
    if (layout.uv != ShadingLayout::kAbsent)
      storeAttribute<2>(record + layout.uv, lf, v0->uv, v1->uv, v2->uv, w0, w1, w2);
  }

  static glm::vec3 faceNormal(const SourceTriangle& source, bool mirrored) {
    const glm::vec3 a = source.vertex[1]->world - source.vertex[0]->world;
    const glm::vec3 b = source.vertex[2]->world - source.vertex[0]->world;
    // A mirroring transform turns the object's counter-clockwise winding clockwise in the world.
    return glm::cross(a, b) * (mirrored ? -1.0f : 1.0f);
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
  for (int i = 1; i + 1 < count; ++i) writer.emit(source, &clipped[0], &clipped[i], &clipped[i + 1]);
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
      writer.emit(source(), v0, v1, v2);
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
      writer.emit(source, &projected[0], &projected[1], &projected[2]);
    else
      emitClipped(batch, writer, source);
  }
}

PBS_AVX2_CLONES
void setupChunk(TriangleBatch& batch, std::uint32_t chunkIndex) {
  TriangleChunk& chunk = batch.chunks[chunkIndex];
  chunk.raster.clear();
  chunk.shading.clear();
  chunk.recordStart.clear();
  chunk.raster.reserve(kChunkTriangles);
  if (batch.uniformStride == 0) chunk.recordStart.reserve(kChunkTriangles);
  chunk.shading.reserve(std::size_t(kChunkTriangles) * batch.maxStride());
  std::fill_n(batch.tileCounts.data() + chunkIndex * binCount(batch), binCount(batch), BinCount(0));
  ChunkWriter writer(batch, chunkIndex);

  const std::uint32_t begin = chunkIndex * kChunkTriangles;
  const std::uint32_t end = std::min(begin + kChunkTriangles, batch.triangleCount);
  const auto spanAfter =
      std::upper_bound(batch.spans.begin(), batch.spans.end(), begin,
                       [](std::uint32_t position, const TriangleSpan& span) { return position < span.batchStart; });
  // Spans are consecutive in the batch: walk those the chunk overlaps, each in one loop.
  for (std::uint32_t s = std::uint32_t(spanAfter - batch.spans.begin()) - 1, position = begin; position < end; ++s) {
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
  batch.layouts[1] = shadingLayout(batch, true);
  bool anyFlat = false, anyTextured = false;
  for (const TriangleSpan& span : batch.spans) (span.texture ? anyTextured : anyFlat) = true;
  batch.uniformStride = anyFlat && anyTextured ? 0 : batch.layouts[anyTextured].stride;
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
