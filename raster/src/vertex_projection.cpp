// Projecting each vertex once per batch: clip position, snapped window position and the world
// attributes the channels need, cached per span so triangles sharing a vertex share the work.
// Spans of many vertices on few pixels (distant instances) leave the attributes to the few
// triangles that cover a pixel centre (TriangleSpan::deferAttributes).
#include "pbs/raster/simd_clones.hpp"
#include "triangle_batch.hpp"
#include "window_snap.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pbs::triangles {
namespace {

// More distinct vertices than this per triangle of a span means its indices jump around a huge
// vertex array; caching that range would cost memory unrelated to the batch size.
constexpr std::size_t kCachedVerticesPerTriangle = 3;
constexpr std::size_t kCachedVerticesSlack = 1024;

bool isInside(const TriangleBatch& batch, const glm::dvec4& c) {
  const bool finite = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && std::isfinite(c.w);
  return finite && c.w > 0.0 && c.z >= -c.w && c.z <= c.w && std::abs(c.x) <= batch.guardX * c.w &&
         std::abs(c.y) <= batch.guardY * c.w;
}

// Smallest and largest of a set of indices or coordinates; merged by min and max, so the result
// is the same however a parallel reduction splits the work.
template <class T>
struct Extent {
  T lo = std::numeric_limits<T>::max();
  T hi = std::numeric_limits<T>::lowest();

  void add(T value) {
    lo = std::min(lo, value);
    hi = std::max(hi, value);
  }
  Extent merged(const Extent& other) const { return {std::min(lo, other.lo), std::max(hi, other.hi)}; }
};

// A span of one large mesh is one task of every per-span stage below: its scans over indices and
// vertices are split in pieces of this many, so that they run on every thread too.
constexpr std::size_t kScanGrain = 1 << 14;

// Reduces body(first, end, partial) over [0, count) in parallel pieces, merging the partial results
// (of a type with `merged`) in any order.
template <class Partial, class Body>
Partial parallelScan(std::size_t count, Body body) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, count, kScanGrain), Partial{},
      [&](const tbb::blocked_range<std::size_t>& r, Partial partial) {
        body(r.begin(), r.end(), partial);
        return partial;
      },
      [](const Partial& a, const Partial& b) { return a.merged(b); });
}

// The valid indices among indices[first, end): those below the vertex count. Selects rather than
// a skip, so that the loop vectorises.
PBS_AVX2_CLONES
void addValidIndices(const std::uint32_t* indices, std::size_t first, std::size_t end, std::size_t vertexLimit,
                     Extent<std::uint32_t>& extent) {
  const bool anyIndex = vertexLimit > 0xffffffffu;
  const std::uint32_t limit = std::uint32_t(std::min<std::size_t>(vertexLimit, 0xffffffffu));
  std::uint32_t lo = extent.lo, hi = extent.hi;
  for (std::size_t i = first; i < end; ++i) {
    const bool valid = anyIndex || indices[i] < limit;
    lo = std::min(lo, valid ? indices[i] : 0xffffffffu);
    hi = std::max(hi, valid ? indices[i] : 0u);
  }
  extent = {lo, hi};
}

// The index range a span references (indices past the vertex array are skipped later).
void chooseCacheRange(const TriangleSpan& span, std::size_t vertexLimit, std::uint32_t& first, std::uint32_t& count) {
  const std::uint32_t* indices = span.draw->indices.data() + span.firstIndex;
  const auto range = parallelScan<Extent<std::uint32_t>>(
      std::size_t(span.count) * 3, [&](std::size_t begin, std::size_t end, Extent<std::uint32_t>& extent) {
        addValidIndices(indices, begin, end, vertexLimit, extent);
      });
  const std::uint32_t lo = range.lo, hi = range.hi;
  const bool useful = lo <= hi && std::size_t(hi - lo) < kCachedVerticesPerTriangle * span.count + kCachedVerticesSlack;
  first = useful ? lo : 0;
  count = useful ? hi - lo + 1 : 0;
}

// A span whose vertices fall on fewer pixel centres than this fraction of its vertex count defers
// its vertex attributes: most of its triangles cover no pixel centre, so the attributes are
// computed per surviving triangle (three vertices each) rather than for every vertex.
constexpr std::uint64_t kDeferVerticesPerPixel = 8;

// The window position part of a projected vertex; the attributes are left zero.
// Written in place: a vertex built on the stack and returned was copied out with 16-byte loads over its
// 8- and 1-byte stores, a store-forwarding stall per vertex (two thirds of projectPositions' samples).
PBS_CLONE_INLINE void projectPosition(const TriangleBatch& batch, const TriangleSpan& span, std::uint32_t index,
                                      ProjectedVertex& vertex) {
  vertex = ProjectedVertex{};
  const glm::dvec4 clip = clipPosition(span, index);
  vertex.inside = isInside(batch, clip);
  if (vertex.inside) {
    const WindowVertex window = snapToWindow(batch.camera, clip);
    vertex.x = window.x;
    vertex.y = window.y;
    vertex.depth = window.depth;
    vertex.invW = window.invW;
  }
}

// The world attributes the channels need.
PBS_CLONE_INLINE void addAttributes(const TriangleBatch& batch, const TriangleSpan& span, std::uint32_t index,
                                    ProjectedVertex& vertex) {
  const TriangleDraw& draw = *span.draw;
  const Framebuffer& framebuffer = batch.framebuffer;
  if (framebuffer.has(kChannelPosition) || framebuffer.has(kChannelNormal)) {
    const glm::dvec3 world(span.worldFromObject * glm::dvec4(glm::dvec3(draw.positions[index]), 1.0));
    vertex.world = glm::vec3(world - framebuffer.positionOrigin);
  }
  if (framebuffer.has(kChannelNormal) && index < draw.normals.size()) {
    const glm::dvec3 normal = span.normalFromObject * glm::dvec3(draw.normals[index]);
    const double length = glm::length(normal);
    // Zero, or non-finite from a singular transform: left zero, so pixels fall back to the face normal.
    if (length > 0.0 && std::isfinite(length)) vertex.normal = glm::vec3(normal * (1.0 / length));
  }
  if (span.texture && index < draw.uvs.size()) vertex.uv = draw.uvs[index];
}

// Calls body(span, first, end) for runs of cached vertices covering those of every span, in one
// flat parallel loop: a scene of many small instances has many short spans, too short for a task
// each.
template <class Body>
void forEachCachedRun(TriangleBatch& batch, Body body) {
  const std::vector<TriangleSpan>& spans = batch.spans;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, batch.vertices.size(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        // The last span starting at or before r.begin() holds it (empty spans share the
        // start of the next one, and come before it).
        const auto after =
            std::upper_bound(spans.begin(), spans.end(), r.begin(),
                             [](std::size_t i, const TriangleSpan& span) { return i < span.cacheOffset; });
        for (std::size_t s = std::size_t(after - spans.begin()) - 1, i = r.begin(); i < r.end(); ++s) {
          const TriangleSpan& span = spans[s];
          const std::size_t end = std::min<std::size_t>(r.end(), span.cacheOffset + span.vertexCount);
          if (i >= end) continue;
          body(span, std::uint32_t(i - span.cacheOffset), std::uint32_t(end - span.cacheOffset));
          i = end;
        }
      });
}

PBS_AVX2_CLONES
void projectPositions(TriangleBatch& batch, const TriangleSpan& span, std::uint32_t first, std::uint32_t end) {
  for (std::uint32_t v = first; v < end; ++v)
    projectPosition(batch, span, span.firstVertex + v, batch.vertices[span.cacheOffset + v]);
}

PBS_AVX2_CLONES
void addRunAttributes(TriangleBatch& batch, const TriangleSpan& span, std::uint32_t first, std::uint32_t end) {
  for (std::uint32_t v = first; v < end; ++v)
    addAttributes(batch, span, span.firstVertex + v, batch.vertices[span.cacheOffset + v]);
}

// The box of a span's cached window positions, and whether any vertex lies outside.
struct WindowExtent {
  Extent<std::int32_t> x, y;
  bool outside = false;

  WindowExtent merged(const WindowExtent& other) const {
    return {x.merged(other.x), y.merged(other.y), outside || other.outside};
  }
};

// Whether the span's cached vertices, all inside, fall on few pixel centres: their box within the
// viewport, counted as emit counts a triangle's.
bool shouldDefer(const TriangleBatch& batch, const TriangleSpan& span) {
  if (span.vertexCount == 0) return false;
  const ProjectedVertex* vertices = batch.vertices.data() + span.cacheOffset;
  const auto window =
      parallelScan<WindowExtent>(span.vertexCount, [&](std::size_t first, std::size_t end, WindowExtent& extent) {
        for (std::size_t v = first; v < end; ++v) {
          extent.outside |= !vertices[v].inside;
          extent.x.add(vertices[v].x);
          extent.y.add(vertices[v].y);
        }
      });
  if (window.outside) return false;
  const PixelBox box = pixelBox(batch.framebuffer, window.x.lo, window.y.lo, window.x.hi, window.y.hi);
  if (box.empty()) return true;
  const std::uint64_t pixels = std::uint64_t(box.x1 - box.x0 + 1) * std::uint64_t(box.y1 - box.y0 + 1);
  return pixels * kDeferVerticesPerPixel < span.vertexCount;
}

}  // namespace

PBS_AVX2_CLONES
ProjectedVertex projectVertex(const TriangleBatch& batch, const TriangleSpan& span, std::uint32_t index) {
  ProjectedVertex vertex;
  projectPosition(batch, span, index, vertex);
  addAttributes(batch, span, index, vertex);
  return vertex;
}

PBS_AVX2_CLONES
void completeVertex(const TriangleBatch& batch, const TriangleSpan& span, std::uint32_t index,
                    ProjectedVertex& vertex) {
  addAttributes(batch, span, index, vertex);
}

// Positions first; then each span decides whether its attributes wait for the triangles that need
// them (shouldDefer); then the attributes of the others.
void projectVertices(TriangleBatch& batch) {
  std::vector<TriangleSpan>& spans = batch.spans;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, spans.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t s = r.begin(); s < r.end(); ++s)
      chooseCacheRange(spans[s], spans[s].draw->positions.size(), spans[s].firstVertex, spans[s].vertexCount);
  });
  std::size_t total = 0;
  for (TriangleSpan& span : spans) {
    span.cacheOffset = total;
    total += span.vertexCount;
  }
  batch.vertices.resize(total);
  forEachCachedRun(batch, [&](const TriangleSpan& span, std::uint32_t first, std::uint32_t end) {
    projectPositions(batch, span, first, end);
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, spans.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t s = r.begin(); s < r.end(); ++s) spans[s].deferAttributes = shouldDefer(batch, spans[s]);
  });
  forEachCachedRun(batch, [&](const TriangleSpan& span, std::uint32_t first, std::uint32_t end) {
    if (!span.deferAttributes) addRunAttributes(batch, span, first, end);
  });
}

}  // namespace pbs::triangles
