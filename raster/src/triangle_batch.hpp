// One batch of triangles on its way through the stages: vertex projection, setup, binning, tiles.
#pragma once

#include "triangle_records.hpp"

#include "pbs/raster/triangles.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pbs::triangles {

// Source triangles set up and binned at once: bounds the memory of any draw list.
inline constexpr std::uint32_t kBatchTriangles = 1u << 18;
static_assert(kKeptTriangleBufferBytes == kTriangleBufferBytesPerTriangle * kBatchTriangles);
// Source triangles per setup task; with at most kMaxClipVertices − 2 triangles out of clipping
// each, a chunk's output fits the 16 local bits of a packed id.
inline constexpr std::uint32_t kChunkTriangles = 2048;
static_assert(kChunkTriangles <= 1u << kSourcePositionBits);
// A triangle spanning more tiles than this is not listed in each tile's bin; the tiles scan the
// batch's short list of such triangles instead, so bins stay bounded by triangles × 16.
inline constexpr int kMaxBinnedTiles = 16;

// A bin's count or offset of triangles of each kind, in one word so that counting, the offset pass
// and the fill treat both at once: copies in the low half, ids in the high half (each below 2^32: a
// bin holds at most the batch's triangles after clipping).
using BinCount = std::uint64_t;
inline constexpr BinCount kSoleUnit = 1, kSharedUnit = BinCount(1) << 32;
inline std::uint32_t copiesPart(BinCount count) { return std::uint32_t(count); }
inline std::uint32_t idsPart(BinCount count) { return std::uint32_t(count >> 32); }

// A run of consecutive triangles of one draw and one mesh part.
struct TriangleSpan {
  const TriangleDraw* draw = nullptr;
  glm::vec4 baseColor{1.0f};         // the material's (white without one)
  const Texture* texture = nullptr;  // null: not sampled (no colour channel, or no usable texture)
  std::size_t firstIndex = 0;        // into draw->indices
  std::uint32_t firstPrimitive = 0;
  std::uint32_t count = 0;       // triangles
  std::uint32_t batchStart = 0;  // the batch position of its first triangle

  glm::dmat4 clipFromObject{1.0};
  glm::dmat4 worldFromObject{1.0};
  glm::dmat3 normalFromObject{1.0};  // inverse transpose of the linear part
  bool mirrored = false;             // negative determinant: front faces turn clockwise
  bool drawsFront = true;            // the draw's sides
  bool drawsBack = true;             // the draw's sides, less the options' back-face culling
  // The draw's otherSidesWithin, for the faces of each side it does not draw (the back faces' left empty where
  // the options cull them).
  std::span<const PixelRect> frontWithin, backWithin;
  bool affine = false;         // clip w ≡ 1 (orthographic): no perspective division needed
  glm::u8vec4 flatColor{255};  // baseColor as RGBA8, for untextured triangles

  // Vertices firstVertex … firstVertex + vertexCount − 1 are projected once into the batch's cache
  // at cacheOffset; vertexCount 0 means the span's index range was too wide to cache and its
  // vertices are projected per triangle.
  std::uint32_t firstVertex = 0;
  std::uint32_t vertexCount = 0;
  std::size_t cacheOffset = 0;
  // The cached vertices hold window positions only; setup completes the vertices of the triangles
  // that cover a pixel centre (completeVertex). Chosen by projectVertices for spans of many
  // vertices on few pixels, such as distant instances.
  bool deferAttributes = false;
};

// A vertex projected once per batch: snapped when it needs no clipping, plus the attributes the
// channels need; one cache line. Clipping makes vertices of the same kind. Triangles that need
// clipping recompute clip positions (clipPosition), which keeps this record small.
struct ProjectedVertex {
  double depth;  // window depth; with invW, x and y only valid when `inside`
  double invW;
  std::int32_t x, y;
  glm::vec3 world;   // world position − positionOrigin (position and normal channels)
  glm::vec3 normal;  // unit world normal, zero when the draw has none (normal channel)
  glm::vec2 uv;      // texture coordinate (spans that sample a texture)
  bool inside;       // finite, w > 0, within near, far and the guard band
};

inline glm::dvec4 clipPosition(const TriangleSpan& span, std::uint32_t index) {
  return span.clipFromObject * glm::dvec4(glm::dvec3(span.draw->positions[index]), 1.0);
}

// A batch's working memory. It outlives the draw call: each thread keeps what its last call used for its
// next (drawTriangles; up to kKeptTriangleBufferBytes), since the allocator returns blocks of these sizes to the system
// and faulting their pages in again cost a frame's geometry pass a third of its time for several frames. Every stage
// writes what it reads, so what a buffer held before never shows.
struct BatchBuffers {
  UninitializedVector<ProjectedVertex> vertices;  // each written whole by projectVertices
  // The batch's chunks are the first chunkCount; those after them are kept for their memory.
  std::vector<TriangleChunk> chunks;
  // Bins: one per tile, then one of the triangles spanning more than kMaxBinnedTiles tiles, which every
  // tile scans; each in submission order, in two parts (tile_bins.hpp). A triangle in one tile alone is
  // copied into its bin, so that the tile reads those in one stream instead of one cache miss each (most
  // triangles of a capture); of the others, the bins hold ids. Bin b is soleTriangles[copiesPart(binStart[b]) …
  // copiesPart(binStart[b + 1])) and sharedIds[idsPart(binStart[b]) … idsPart(binStart[b + 1])).
  ScalableVector<BinCount> tileCounts;  // per chunk, per bin: counts, then write offsets
  ScalableVector<BinCount> binStart;
  UninitializedVector<RasterTriangle> soleTriangles;
  ScalableVector<std::uint32_t> sharedIds;  // packed ids

  std::size_t capacityBytes() const;
};

struct TriangleBatch : BatchBuffers {
  TriangleBatch(Framebuffer& framebuffer, const Camera& camera, const TriangleOptions& options);

  Framebuffer& framebuffer;
  const Camera& camera;
  TriangleOptions options;
  // Per batch, from the channels and the spans: [0] for the triangles of spans drawn in their flat
  // colour, [1] for those of spans that sample a texture. Only the latter carry the plane of texture
  // coordinates (and, without a position channel, the plane of 1/w it is interpolated over); where no span
  // samples a texture, [1] is [0].
  ShadingLayout layouts[2];
  const ShadingLayout& layoutOf(const TriangleSpan& span) const { return layouts[span.texture != nullptr]; }
  std::uint32_t maxStride() const { return std::max(layouts[0].stride, layouts[1].stride); }
  double guardX, guardY;  // the guard band as bounds on |x/w| and |y/w|
  int tilesX, tilesY;

  std::vector<TriangleSpan> spans;
  std::uint32_t triangleCount = 0;
  std::uint32_t chunkCount = 0;  // of `chunks`, set by setupTriangles

  int tileCount() const { return tilesX * tilesY; }
};

// The stages, in order; each runs in parallel on the current TBB arena.
void projectVertices(TriangleBatch& batch);
ProjectedVertex projectVertex(const TriangleBatch& batch, const TriangleSpan& span, std::uint32_t index);
// Adds the attributes to a vertex of a span that defers them: what projectVertex adds to the window position.
void completeVertex(const TriangleBatch& batch, const TriangleSpan& span, std::uint32_t index, ProjectedVertex& vertex);
void setupTriangles(TriangleBatch& batch);
void binTriangles(TriangleBatch& batch);
void rasterizeTiles(const TriangleBatch& batch);

}  // namespace pbs::triangles
