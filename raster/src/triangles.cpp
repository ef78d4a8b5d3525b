// drawTriangles: streams the draw list through fixed-size batches (vertex projection, setup,
// binning, tiles), so any number of triangles draws in bounded memory and in submission order.
//
// Fill rule (top-left, for the y-down window, row 0 on top). Window positions are snapped to
// 1/256 pixel; a triangle is reordered so that twice its signed area
//   A = (x1 − x0)(y2 − y0) − (y1 − y0)(x2 − x0)
// is positive (clockwise on screen). For each edge a → b the edge function
//   E(p) = (xb − xa)(py − ya) − (yb − ya)(px − xa)
// is then positive inside. A pixel is covered when its centre (px + ½, py + ½) has E > 0 on all
// three edges, or E = 0 on an edge that is
//   - a left edge: yb < ya (the edge runs up the screen; the interior lies to its right, +x), or
//   - a top edge:  yb = ya and xb > xa (horizontal; the interior lies below it, at larger y).
// Shared edges are thus covered exactly once; zero-area triangles cover nothing.
#include "triangle_batch.hpp"

#include "pbs/raster/triangles.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace pbs {
namespace triangles {

TriangleBatch::TriangleBatch(Framebuffer& framebuffer, const Camera& camera, const TriangleOptions& options)
    : framebuffer(framebuffer),
      camera(camera),
      options(options),
      guardX(2.0 * kGuardBandPixels / camera.width - 1.0),
      guardY(2.0 * kGuardBandPixels / camera.height - 1.0),
      tilesX(int((framebuffer.width + kTileSize - 1) / kTileSize)),
      tilesY(int((framebuffer.height + kTileSize - 1) / kTileSize)) {}

std::size_t BatchBuffers::capacityBytes() const {
  std::size_t bytes = vertices.capacity() * sizeof(ProjectedVertex) + chunks.capacity() * sizeof(TriangleChunk) +
                      (tileCounts.capacity() + binStart.capacity()) * sizeof(BinCount) +
                      soleTriangles.capacity() * sizeof(RasterTriangle) + sharedIds.capacity() * sizeof(std::uint32_t);
  for (const TriangleChunk& chunk : chunks)
    bytes += chunk.raster.capacity() * sizeof(RasterTriangle) + chunk.storedRecords.capacity() * sizeof(float);
  return bytes;
}

namespace {

void checkTarget(const Framebuffer& framebuffer, const Camera& camera) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("drawTriangles: " + what); };
  if (framebuffer.width != camera.width || framebuffer.height != camera.height)
    fail("framebuffer " + std::to_string(framebuffer.width) + "x" + std::to_string(framebuffer.height) +
         " does not match camera viewport " + std::to_string(camera.width) + "x" + std::to_string(camera.height));
  if (framebuffer.width == 0 || framebuffer.height == 0 || framebuffer.width > kMaxViewportSize ||
      framebuffer.height > kMaxViewportSize)
    fail("viewport " + std::to_string(framebuffer.width) + "x" + std::to_string(framebuffer.height) + " outside 1 … " +
         std::to_string(kMaxViewportSize));
  const std::size_t pixels = framebuffer.pixelCount();
  const bool sized = framebuffer.depth.size() == pixels &&
                     (!framebuffer.has(kChannelColor) || framebuffer.color.size() == pixels) &&
                     (!framebuffer.has(kChannelPosition) || framebuffer.position.size() == pixels) &&
                     (!framebuffer.has(kChannelNormal) || framebuffer.normal.size() == pixels) &&
                     (!framebuffer.has(kChannelIds) || framebuffer.ids.size() == pixels);
  if (!sized) fail("framebuffer channels are not allocated for its size (use makeFramebuffer)");
}

void drawBatch(TriangleBatch& batch) {
  if (batch.triangleCount == 0) return;
  projectVertices(batch);
  setupTriangles(batch);
  binTriangles(batch);
  rasterizeTiles(batch);
  batch.spans.clear();
  batch.triangleCount = 0;
}

// The span template of one draw and part: transforms and material, without a triangle range yet.
TriangleSpan partSpan(const TriangleBatch& batch, const TriangleDraw& draw, const MeshPart& part) {
  TriangleSpan span;
  span.draw = &draw;
  // A part naming a material the draw lacks shows white rather than reading out of bounds.
  const SurfaceMaterial material =
      part.material < draw.materials.size() ? draw.materials[part.material] : SurfaceMaterial{};
  span.baseColor = material.baseColor;
  span.flatColor = toUnorm8(material.baseColor);
  if (batch.framebuffer.has(kChannelColor) && material.texture && isSampleable(*material.texture))
    span.texture = material.texture;
  span.clipFromObject = batch.camera.clipFromWorld() * draw.worldFromObject;
  span.affine = keepsUnitW(span.clipFromObject);
  span.worldFromObject = draw.worldFromObject;
  const glm::dmat3 linear(draw.worldFromObject);
  span.normalFromObject = glm::transpose(glm::inverse(linear));
  span.mirrored = glm::determinant(linear) < 0.0;
  span.drawsFront = hasSide(draw.sides, FaceSides::front);
  span.drawsBack = hasSide(draw.sides, FaceSides::back) && !batch.options.cullBackFaces;
  if (!span.drawsFront) span.frontWithin = draw.otherSidesWithin;
  if (!span.drawsBack && !batch.options.cullBackFaces) span.backWithin = draw.otherSidesWithin;
  return span;
}

}  // namespace
}  // namespace triangles

void drawTriangles(Framebuffer& framebuffer, const Camera& camera, std::span<const TriangleDraw> draws,
                   const TriangleOptions& options) {
  using namespace triangles;
  checkTarget(framebuffer, camera);
  // Taken, not shared: a call that runs while this thread waits inside another (TBB lets a waiting thread
  // take other work) finds none and allocates its own.
  thread_local BatchBuffers kept;
  TriangleBatch batch(framebuffer, camera, options);
  static_cast<BatchBuffers&>(batch) = std::exchange(kept, BatchBuffers{});
  for (const TriangleDraw& draw : draws) {
    for (const MeshPart& part : draw.parts) {
      // Parts reaching past the index array draw what they cover.
      const std::size_t first = std::min<std::size_t>(part.firstIndex, draw.indices.size());
      const std::size_t count = std::min<std::size_t>(part.indexCount, draw.indices.size() - first) / 3;
      if (count == 0) continue;
      TriangleSpan span = partSpan(batch, draw, part);
      if (!span.drawsFront && !span.drawsBack && span.frontWithin.empty() && span.backWithin.empty()) continue;
      for (std::size_t done = 0; done < count;) {
        const std::size_t n = std::min<std::size_t>(count - done, kBatchTriangles - batch.triangleCount);
        span.firstIndex = first + done * 3;
        span.firstPrimitive = std::uint32_t(first / 3 + done);
        span.count = std::uint32_t(n);
        span.batchStart = batch.triangleCount;
        batch.spans.push_back(span);
        batch.triangleCount += std::uint32_t(n);
        done += n;
        if (batch.triangleCount == kBatchTriangles) drawBatch(batch);
      }
    }
  }
  drawBatch(batch);
  // Larger buffers, left by a draw of many textured or clipped triangles, go back to the allocator.
  if (batch.capacityBytes() <= kKeptTriangleBufferBytes) kept = std::move(static_cast<BatchBuffers&>(batch));
}

}  // namespace pbs
