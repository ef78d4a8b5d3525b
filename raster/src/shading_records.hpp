// A triangle's shading record (triangle_records.hpp) and the barycentric planes it is made of. Setup
// makes the record of a clipped triangle at once, from its clipped vertices; every other record is
// made by the tile stage for the triangles that won a pixel once all are in (shadingRecord), as
// most triangles of a capture lose every pixel (the back faces of a closed mesh, those behind): for
// them setup writes nothing. Both ways run the same code on the same inputs, so the bits agree.
#pragma once

#include "pbs/raster/simd_clones.hpp"
#include "triangle_batch.hpp"

#include <cstdint>
#include <utility>

namespace pbs::triangles {

// Screen-space barycentrics of vertices 1 and 2 as planes over pixel offsets from the box's first pixel
// (px0, py0), so an attribute is a0 + λ1·(a1 − a0) + λ2·(a2 − a0). λ of vertex 1 is the edge function of
// edge 2 → 0 over twice the area, λ of vertex 2 that of edge 0 → 1 (exact in int64 up to the division).
// The vertices in raster order: twice their signed area, area2, is positive.
struct Barycentrics {
  double c[2], x[2], y[2];
};

PBS_CLONE_INLINE Barycentrics barycentrics(const ProjectedVertex& v0, const ProjectedVertex& v1,
                                           const ProjectedVertex& v2, std::int32_t px0, std::int32_t py0,
                                           std::int64_t area2) {
  const std::int64_t half = kSubpixelScale / 2;
  const std::int64_t ox = px0 * kSubpixelScale + half, oy = py0 * kSubpixelScale + half;
  const double inverseArea = 1.0 / double(area2);
  Barycentrics l;
  const ProjectedVertex* edgeStart[2] = {&v2, &v0};
  const ProjectedVertex* edgeEnd[2] = {&v0, &v1};
  for (int i = 0; i < 2; ++i) {
    const ProjectedVertex& a = *edgeStart[i];
    const ProjectedVertex& b = *edgeEnd[i];
    const std::int64_t edgeA = std::int64_t(a.y) - b.y, edgeB = std::int64_t(b.x) - a.x;
    l.c[i] = double(edgeA * (ox - a.x) + edgeB * (oy - a.y)) * inverseArea;
    l.x[i] = double(edgeA * kSubpixelScale) * inverseArea;
    l.y[i] = double(edgeB * kSubpixelScale) * inverseArea;
  }
  return l;
}

// Twice the signed area of the snapped triangle; negative is counter-clockwise in clip space (y up).
PBS_CLONE_INLINE std::int64_t doubleArea(const ProjectedVertex& v0, const ProjectedVertex& v1,
                                         const ProjectedVertex& v2) {
  return (std::int64_t(v1.x) - v0.x) * (std::int64_t(v2.y) - v0.y) -
         (std::int64_t(v1.y) - v0.y) * (std::int64_t(v2.x) - v0.x);
}

PBS_CLONE_INLINE AttributePlane<double> deltaPlane(const Barycentrics& l, double a0, double a1, double a2) {
  const double d1 = a1 - a0, d2 = a2 - a0;
  return {a0 + l.c[0] * d1 + l.c[1] * d2, l.x[0] * d1 + l.x[1] * d2, l.y[0] * d1 + l.y[1] * d2};
}

namespace records {

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

}  // namespace records

// The face normal from the source triangle's vertices in the mesh's order.
PBS_CLONE_INLINE glm::vec3 faceNormal(const ProjectedVertex& a, const ProjectedVertex& b, const ProjectedVertex& c,
                                      bool mirrored) {
  // A mirroring transform turns the object's counter-clockwise winding clockwise in the world.
  return glm::cross(b.world - a.world, c.world - a.world) * (mirrored ? -1.0f : 1.0f);
}

// Writes the record of a triangle of `span` (at batch.spans[spanIndex]) with vertices v0, v1, v2 in
// raster order, its barycentrics l from pixel (px0, py0), into `record` (its span's layout).
PBS_CLONE_INLINE void writeShadingRecord(const TriangleBatch& batch, std::uint32_t spanIndex, std::uint32_t primitive,
                                         const glm::vec3& face, const Barycentrics& l, const ProjectedVertex& v0,
                                         const ProjectedVertex& v1, const ProjectedVertex& v2, std::uint16_t px0,
                                         std::uint16_t py0, float* record) {
  const TriangleSpan& span = batch.spans[spanIndex];
  const ShadingLayout& layout = batch.layoutOf(span);
  storeHeader(record, ShadingHeader{spanIndex, primitive, px0, py0, span.flatColor});
  // 1/w and a/w are affine in the window, so dividing one by the other is perspective-correct.
  // Where w ≡ 1 the plane is exactly 1, so the division changes nothing and can be skipped.
  if (layout.inverseW != ShadingLayout::kAbsent) {
    const AttributePlane<double> q =
        span.affine ? AttributePlane<double>{1.0, 0.0, 0.0} : deltaPlane(l, v0.invW, v1.invW, v2.invW);
    storePlane<1>(record + layout.inverseW, {glm::vec1(float(q.c)), glm::vec1(float(q.x)), glm::vec1(float(q.y))});
  }
  const AttributePlane<glm::vec2> lf{
      {float(l.c[0]), float(l.c[1])}, {float(l.x[0]), float(l.x[1])}, {float(l.y[0]), float(l.y[1])}};
  const float w0 = float(v0.invW), w1 = float(v1.invW), w2 = float(v2.invW);
  if (layout.position != ShadingLayout::kAbsent)
    records::storeAttribute<3>(record + layout.position, lf, v0.world, v1.world, v2.world, w0, w1, w2);
  if (layout.normal != ShadingLayout::kAbsent) {
    records::storeAttribute<3>(record + layout.normal, lf, v0.normal, v1.normal, v2.normal, w0, w1, w2);
    storeVector(record + layout.normal + 9, face);
  }
  if (layout.uv != ShadingLayout::kAbsent)
    records::storeAttribute<2>(record + layout.uv, lf, v0.uv, v1.uv, v2.uv, w0, w1, w2);
}

// Where a set-up triangle comes from (RasterTriangle::source): its stored record, or its span and
// indices for making the record again.
struct TriangleSource {
  const float* stored;  // its record where setup made it, else null and the rest is set
  std::uint32_t spanIndex;
  std::uint32_t local;  // within its span
  const TriangleSpan* span;
  const std::uint32_t* indices;  // its three
};

PBS_CLONE_INLINE TriangleSource sourceOf(const TriangleBatch& batch, const RasterTriangle& t) {
  const std::uint32_t chunkIndex = idChunk(t.id);
  const TriangleChunk& chunk = batch.chunks[chunkIndex];
  if (t.source & kStoredRecord)
    return {chunk.storedRecords.data() + (t.source & ~kStoredRecord), 0, 0, nullptr, nullptr};
  const std::uint32_t spanIndex = chunk.firstSpan + sourceSpanOffset(t.source);
  const TriangleSpan& span = batch.spans[spanIndex];
  const std::uint32_t local = chunkIndex * kChunkTriangles + sourcePosition(t.source) - span.batchStart;
  return {nullptr, spanIndex, local, &span, span.draw->indices.data() + span.firstIndex + std::size_t(local) * 3};
}

// The cached vertex of a span that keeps its vertices' attributes, else null.
PBS_CLONE_INLINE const ProjectedVertex* cachedVertex(const TriangleBatch& batch, const TriangleSpan& span,
                                                     std::uint32_t index) {
  return span.vertexCount > 0 && !span.deferAttributes
             ? batch.vertices.data() + span.cacheOffset + (index - span.firstVertex)
             : nullptr;
}

// The record of set-up triangle t from its source: a stored one copied, any other computed from its
// vertices as setup saw them (cached; completed where the span defers attributes; projected again where
// it has no cache).
PBS_CLONE_INLINE void shadingRecord(const TriangleBatch& batch, const RasterTriangle& t, const TriangleSource& source,
                                    float* record) {
  if (source.stored != nullptr) {
    const std::uint32_t stride = batch.layoutOf(batch.spans[loadHeader(source.stored).span]).stride;
    for (std::uint32_t i = 0; i < stride; ++i) record[i] = source.stored[i];
    return;
  }
  const TriangleSpan& span = *source.span;
  const ProjectedVertex* v[3];
  ProjectedVertex made[3];
  for (int k = 0; k < 3; ++k) {
    v[k] = cachedVertex(batch, span, source.indices[k]);
    if (v[k] != nullptr) continue;
    if (span.vertexCount == 0) {
      made[k] = projectVertex(batch, span, source.indices[k]);
    } else {
      made[k] = batch.vertices[span.cacheOffset + (source.indices[k] - span.firstVertex)];
      completeVertex(batch, span, source.indices[k], made[k]);
    }
    v[k] = &made[k];
  }
  const glm::vec3 face = faceNormal(*v[0], *v[1], *v[2], span.mirrored);
  if (t.source & kSwappedSource) std::swap(v[1], v[2]);
  const Barycentrics l = barycentrics(*v[0], *v[1], *v[2], t.minX, t.minY, doubleArea(*v[0], *v[1], *v[2]));
  writeShadingRecord(batch, source.spanIndex, span.firstPrimitive + source.local, face, l, *v[0], *v[1], *v[2], t.minX,
                     t.minY, record);
}

// Fetches the first thing shadingRecord reads of a source: its stored record, or its indices.
PBS_CLONE_INLINE void prefetchIndices(const TriangleBatch& batch, const TriangleSource& source) {
  if (source.stored == nullptr) {
    __builtin_prefetch(source.indices);
    return;
  }
  for (std::uint32_t line = 0; line < batch.maxStride(); line += 16) __builtin_prefetch(source.stored + line);
}

// Fetches the cached vertices a source's indices name, once the indices are in.
PBS_CLONE_INLINE void prefetchVertices(const TriangleBatch& batch, const TriangleSource& source) {
  if (source.stored != nullptr) return;
  for (int k = 0; k < 3; ++k)
    if (const ProjectedVertex* v = cachedVertex(batch, *source.span, source.indices[k])) __builtin_prefetch(v);
}

}  // namespace pbs::triangles
