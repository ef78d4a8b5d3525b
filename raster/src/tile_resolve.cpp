// Resolving a tile: for each pixel a triangle of this batch won, its attributes are interpolated
// once (perspective-correct) into the channels the framebuffer has; nothing else is computed. The
// shading record of each winner is made here, the first time one of its pixels is met.
#include "pbs/raster/simd_clones.hpp"
#include "shading_records.hpp"
#include "texture_filters.hpp"
#include "tile_buffer.hpp"

#include <cmath>

namespace pbs::triangles {
namespace {

// The interpolated vertex normal n, or where it has no direction (opposed or missing vertex
// normals) the face normal; interpolated n/w has the direction of n (w > 0), so no division.
PBS_CLONE_INLINE glm::vec3 unitNormal(const glm::vec3& n, const float* facePart) {
  const float length2 = glm::dot(n, n);
  if (length2 > 1e-24f && length2 < 1e30f) return n * (1.0f / std::sqrt(length2));
  const glm::vec3 face = loadVector<3>(facePart);
  const float face2 = glm::dot(face, face);
  return face2 > 0.0f && face2 < 1e30f ? face * (1.0f / std::sqrt(face2)) : glm::vec3(0.0f);
}

// d(uv)/dx and d(uv)/dy at the pixel, times the sample spacing: uv = P·w with P the plane of uv/w and 1/w
// a plane Q, so d(uv)/dx = (dP/dx − uv · dQ/dx) · w (the planes' x and y parts are their derivatives).
PBS_CLONE_INLINE TextureFootprint uvFootprint(const float* record, const ShadingLayout& layout, bool perspective,
                                              const glm::vec2& uv, float w, float spacing, std::uint32_t probes) {
  const glm::vec2 planeX = loadVector<2>(record + layout.uv + 2), planeY = loadVector<2>(record + layout.uv + 4);
  const float inverseWX = perspective ? record[layout.inverseW + 1] : 0.0f;
  const float inverseWY = perspective ? record[layout.inverseW + 2] : 0.0f;
  const float scale = w * spacing;
  return {(planeX - uv * inverseWX) * scale, (planeY - uv * inverseWY) * scale, probes};
}

// Marks in drawn.slotOf the places of the triangles that won a pixel of the tile.
std::uint32_t* markWinners(const TileBuffer& tile, TileDrawn& drawn) {
  drawn.slotOf.assign(drawn.triangles.size(), 0);
  std::uint32_t* const slotOf = drawn.slotOf.data();
  for (int row = 0; row < tile.height; ++row)
    for (int column = 0; column < tile.width; ++column) {
      const std::uint32_t id = tile.ids[row * kTileStride + column];
      if (id != kNoTriangle) slotOf[id] = 1;
    }
  return slotOf;
}

// The records of the marked triangles, in the order the tile drew them (the order of their index and
// vertex arrays, mostly), each marked place turned into its record's slot (an unmarked place keeps 0, but
// no pixel names it). What the records are made from is fetched ahead: the indices (or a stored record) a
// few triangles ahead, the vertices they name half as far.
PBS_CLONE_INLINE const float* makeRecords(const TriangleBatch& batch, TileDrawn& drawn) {
  std::vector<const RasterTriangle*>& winners = drawn.winners;
  std::vector<TriangleSource>& sources = drawn.sources;
  winners.clear();
  sources.clear();
  std::uint32_t* const slotOf = drawn.slotOf.data();
  for (std::uint32_t place = 0; place < drawn.triangles.size(); ++place) {
    if (slotOf[place] == 0) continue;
    slotOf[place] = std::uint32_t(winners.size());
    winners.push_back(drawn.triangles[place]);
    sources.push_back(sourceOf(batch, *drawn.triangles[place]));
  }
  const std::uint32_t stride = batch.maxStride();
  if (drawn.records.size() < winners.size() * stride) drawn.records.resize(winners.size() * stride);
  constexpr std::size_t kIndicesAhead = 8, kVerticesAhead = 4;
  const std::size_t count = winners.size();
  for (std::size_t i = 0; i < std::min(count, kIndicesAhead); ++i) prefetchIndices(batch, sources[i]);
  for (std::size_t i = 0; i < std::min(count, kVerticesAhead); ++i) prefetchVertices(batch, sources[i]);
  for (std::size_t i = 0; i < count; ++i) {
    if (i + kIndicesAhead < count) prefetchIndices(batch, sources[i + kIndicesAhead]);
    if (i + kVerticesAhead < count) prefetchVertices(batch, sources[i + kVerticesAhead]);
    shadingRecord(batch, *winners[i], sources[i], drawn.records.data() + i * stride);
  }
  return drawn.records.data();
}

// Where the batch samples textures, every textured triangle of it is affine (an orthographic view) and takes one
// probe, the footprint is the same at each of its pixels: the level of detail of each winner's, found once (null
// where not so). With
// w = 1 and the 1/w plane's slopes 0, uvFootprint's uv · 0 is ±0 and leaves each side's squared length as it is.
PBS_CLONE_INLINE const float* affineTextureLevels(const TriangleBatch& batch, TileDrawn& drawn, const float* records,
                                                  const ShadingLayout& textured, float spacing, std::uint32_t probes) {
  constexpr std::uint32_t kAbsent = ShadingLayout::kAbsent;
  if (probes != 1 || textured.uv == kAbsent || textured.inverseW != kAbsent) return nullptr;
  const std::uint32_t stride = batch.maxStride();
  drawn.textureLevels.resize(drawn.winners.size());
  for (std::size_t i = 0; i < drawn.winners.size(); ++i) {
    const float* record = records + i * stride;
    const TriangleSpan& span = batch.spans[loadHeader(record).span];
    drawn.textureLevels[i] =
        span.texture ? textureLevelOfDetail(
                           *span.texture, uvFootprint(record, textured, false, glm::vec2(0.0f), 1.0f, spacing, probes))
                     : 0.0f;
  }
  return drawn.textureLevels.data();
}

}  // namespace

// The channels' arrays and the layouts are held in locals: through the batch, every store to a
// channel could alias them, and each pixel would load them afresh.
PBS_AVX2_CLONES
void resolveTile(const TriangleBatch& batch, const TileBuffer& tile, TileDrawn& drawn) {
  Framebuffer& framebuffer = batch.framebuffer;
  const ShadingLayout flat = batch.layouts[0], textured = batch.layouts[1];
  constexpr std::uint32_t kAbsent = ShadingLayout::kAbsent;
  glm::vec3* const positions = framebuffer.has(kChannelPosition) ? framebuffer.position.data() : nullptr;
  glm::vec3* const normals = framebuffer.has(kChannelNormal) ? framebuffer.normal.data() : nullptr;
  glm::u8vec4* const colors = framebuffer.has(kChannelColor) ? framebuffer.color.data() : nullptr;
  PixelIds* const ids = framebuffer.has(kChannelIds) ? framebuffer.ids.data() : nullptr;
  const TriangleSpan* const spans = batch.spans.data();
  const std::uint32_t stride = batch.maxStride();
  std::uint32_t* const slotOf = markWinners(tile, drawn);
  const float* const records = makeRecords(batch, drawn);
  const std::size_t width = framebuffer.width;
  const auto sampleSpacing = float(batch.camera.sampleSpacing);
  const std::uint32_t textureProbes = batch.camera.textureProbes;
  const float* const levels =
      colors ? affineTextureLevels(batch, drawn, records, textured, sampleSpacing, textureProbes) : nullptr;
  for (int row = 0; row < tile.height; ++row) {
    const int y = tile.y0 + row;
    for (int column = 0; column < tile.width; ++column) {
      const std::uint32_t id = tile.ids[row * kTileStride + column];
      if (id == kNoTriangle) continue;
      // Every pixel looks its winner's record up afresh. About half the pixels continue their left
      // neighbour's triangle, but a branch to reuse its values mispredicts so often that
      // recomputing them is faster.
      const float* record = records + std::size_t(slotOf[id]) * stride;
      const ShadingHeader header = loadHeader(record);
      const TriangleSpan& span = spans[header.span];
      const ShadingLayout& layout = span.texture ? textured : flat;
      const int x = tile.x0 + column;
      const std::size_t pixel = std::size_t(y) * width + std::size_t(x);
      const float dx = float(x - header.minX), dy = float(y - header.minY);
      // w at the pixel, for the attributes interpolated over w. An affine span's plane of 1/w is exactly
      // (1, 0, 0): its w is exactly 1, as where the layout has no such plane (no span has perspective,
      // or the record interpolates nothing over w).
      const bool perspective = layout.inverseW != kAbsent;
      const float w = perspective ? 1.0f / planeValue<1>(record + layout.inverseW, dx, dy).x : 1.0f;
      if (positions) positions[pixel] = planeValue<3>(record + layout.position, dx, dy) * w;
      if (normals)
        normals[pixel] = unitNormal(planeValue<3>(record + layout.normal, dx, dy), record + layout.normal + 9);
      if (colors) {
        if (span.texture) {
          const glm::vec2 uv = planeValue<2>(record + layout.uv, dx, dy) * w;
          // The level found once for the triangle holds where uv is finite (else uv · 0 is NaN in the footprint).
          const glm::vec4 texel =
              levels && std::isfinite(uv.x) && std::isfinite(uv.y)
                  ? texture_filters::sampleAtLevel(*span.texture, uv, levels[slotOf[id]])
                  : sampleTexture(*span.texture, uv,
                                  uvFootprint(record, layout, perspective, uv, w, sampleSpacing, textureProbes));
          colors[pixel] = toUnorm8(span.baseColor * texel);
        } else {
          colors[pixel] = header.flatColor;
        }
      }
      if (ids) ids[pixel] = {span.draw->nodeId, span.draw->instanceId, header.primitive};
    }
  }
}

}  // namespace pbs::triangles
