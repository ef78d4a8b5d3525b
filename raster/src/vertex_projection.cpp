// Projecting each vertex once per batch: clip position, snapped window position and the world
// attributes the channels need, cached per span so triangles sharing a vertex share the work.
#include "triangle_batch.hpp"
#include "window_snap.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

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

// The index range a span references (indices past the vertex array are skipped later).
void chooseCacheRange(const TriangleSpan& span, std::size_t vertexLimit, std::uint32_t& first,
                      std::uint32_t& count) {
  const auto indices = span.draw->indices.subspan(span.firstIndex, std::size_t(span.count) * 3);
  std::uint32_t lo = 0xffffffffu, hi = 0;
  for (const std::uint32_t index : indices) {
    if (index >= vertexLimit) continue;
    lo = std::min(lo, index);
    hi = std::max(hi, index);
  }
  const bool useful = lo <= hi && std::size_t(hi - lo) < kCachedVerticesPerTriangle * span.count + kCachedVerticesSlack;
  first = useful ? lo : 0;
  count = useful ? hi - lo + 1 : 0;
}

}  // namespace

ProjectedVertex projectVertex(const TriangleBatch& batch, const TriangleSpan& span, std::uint32_t index) {
  const TriangleDraw& draw = *span.draw;
  const Framebuffer& framebuffer = batch.framebuffer;
  ProjectedVertex vertex{};
  const glm::dvec4 clip = clipPosition(span, index);
  vertex.inside = isInside(batch, clip);
  if (vertex.inside) {
    const WindowVertex window = snapToWindow(batch.camera, clip);
    vertex.x = window.x;
    vertex.y = window.y;
    vertex.depth = window.depth;
    vertex.invW = window.invW;
  }
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
  return vertex;
}

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
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, spans.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t s = r.begin(); s < r.end(); ++s) {
      const TriangleSpan& span = spans[s];
      tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, span.vertexCount, 4096),
                        [&](const tbb::blocked_range<std::uint32_t>& vr) {
                          for (std::uint32_t v = vr.begin(); v < vr.end(); ++v)
                            batch.vertices[span.cacheOffset + v] = projectVertex(batch, span, span.firstVertex + v);
                        });
    }
  });
}

}  // namespace pbs::triangles
