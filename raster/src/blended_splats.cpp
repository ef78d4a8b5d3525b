// drawBlendedSplats: footprints are set up and binned to tiles per chunk in parallel; then each tile, owned by
// one task, runs the visibility pass, the accumulation pass and the resolve over its pixels.
#include "pbs/raster/blended_splats.hpp"
#include "pbs/raster/headlight_shading.hpp"

#include "blend_footprint.hpp"
#include "points_grid.hpp"
#include "scalable_vectors.hpp"

#include "pbs/raster/simd_clones.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pbs {
namespace {

using blend::Footprint;
using blend::FootprintProjector;
using points::TileGrid;

// 32-pixel tiles: a tile's two layers of sums (about 80 KB) stay in L2.
constexpr int kTileShift = 5;
constexpr std::uint32_t kTilePixels = 1u << (2 * kTileShift);
constexpr std::size_t kChunkSurfels = 8192;

// One chunk's footprints and, per tile, the indices of those overlapping it (a counting sort, so each tile
// reads them in surfel order).
struct Chunk {
  UninitializedVector<Footprint> footprints;
  std::vector<std::uint32_t> tileStart;  // tiles + 1
  UninitializedVector<std::uint32_t> refs;
};

// Where surfel ordinal `first` (set order, then index) falls: calls visit(set, index, count) per set part of
// [first, last).
template <class Visit>
void forEachSetPart(std::span<const SurfelSplatSet> sets, std::span<const std::size_t> starts, std::size_t first,
                    std::size_t last, Visit&& visit) {
  std::size_t s = std::size_t(std::upper_bound(starts.begin(), starts.end(), first) - starts.begin()) - 1;
  for (; first < last; ++s) {
    const std::size_t end = std::min(last, starts[s] + sets[s].positions.size());
    if (end > first) visit(s, first - starts[s], end - first);
    first = std::max(first, end);
  }
}

void binChunk(const TileGrid& grid, Chunk& chunk) {
  const std::uint32_t tiles = grid.count();
  chunk.tileStart.assign(tiles + 1, 0);
  const auto forEachTile = [&](const Footprint& f, auto&& visit) {
    for (std::uint32_t ty = f.y0 >> kTileShift; ty <= std::uint32_t(f.y1 - 1) >> kTileShift; ++ty)
      for (std::uint32_t tx = f.x0 >> kTileShift; tx <= std::uint32_t(f.x1 - 1) >> kTileShift; ++tx)
        visit(ty * grid.columns + tx);
  };
  for (const Footprint& f : chunk.footprints) forEachTile(f, [&](std::uint32_t t) { ++chunk.tileStart[t + 1]; });
  for (std::uint32_t t = 0; t < tiles; ++t) chunk.tileStart[t + 1] += chunk.tileStart[t];
  chunk.refs.resize(chunk.tileStart[tiles]);
  std::vector<std::uint32_t> next(chunk.tileStart.begin(), chunk.tileStart.end() - 1);
  for (std::uint32_t i = 0; i < chunk.footprints.size(); ++i)
    forEachTile(chunk.footprints[i], [&](std::uint32_t t) { chunk.refs[next[t]++] = i; });
}

// Sums of one layer at one pixel.
struct LayerSums {
  float coverage = 0.0f;
  glm::vec3 color{0.0f};  // coverage-weighted, 0–255
  glm::vec3 normal{0.0f};
};

// A layer's alpha from its summed coverage S. Summed kernels conserve area, so S is right on average:
// alone it is the coverage of surfaces sparser than their kernels (wires, a distant city whose parts
// are smaller than the spacing of its surfels). Over a closed surface S ripples around 1 between the
// samples; its troughs rarely fall below 0.6. Above ½, where a surface is more than half there, alpha
// therefore rises 5× as fast as S and is 1 from S = 0.6: the troughs close, sparse coverage is kept, and
// an edge's ramp moves outward by a tenth of its width (measured on the default scene's approach:
// holes 2.2 % → 0.9 %, bloat 1.3 % → 1.6 %, FLIP 0.172 → 0.156 against min(1, S)).
PBS_CLONE_INLINE float layerAlpha(const LayerSums& sums) {
  constexpr float kRise = 4.0f;
  const float s = sums.coverage;
  return std::min(1.0f, s + kRise * std::max(0.0f, s - 0.5f));
}

// A pixel of a footprint, within its cut-off, that the visibility pass found not hidden by the geometry: what
// the accumulation pass needs of it, so that it need not walk the footprints' pixels again.
struct Touch {
  const Footprint* footprint;
  float depth;  // the footprint's depth at the pixel
  float q;      // the pixel centre's Mahalanobis distance²
  std::uint32_t local;
};

struct TileScratch {
  std::array<float, kTilePixels> front;     // visibility pass: least depth + tolerance
  std::array<float, kTilePixels> geometry;  // depth drawn before the splats
  std::array<float, kTilePixels> nearest;   // accumulation pass: the nearest contributing depth
  std::array<std::uint32_t, kTilePixels> nearestSet, nearestIndex;
  std::array<LayerSums, kTilePixels> layers[2];
  std::vector<Touch> touches;  // in footprint order, then pixel order: the accumulation pass's order
};

// Calls visit(footprint, pixel in tile, x, y, q) for every pixel of the tile within a footprint's cut-off,
// footprints in chunk order then surfel order.
template <class Visit>
PBS_CLONE_INLINE void forEachCoveredPixel(std::span<const Chunk> chunks, std::uint32_t tile, int tileX, int tileY,
                                          Visit&& visit) {
  const int size = 1 << kTileShift;
  // A tile's footprints lie scattered over their chunk (surfels are in blue-noise order, which has no
  // locality on screen): fetch a few ahead, both cache lines of each.
  constexpr std::uint32_t kAhead = 8;
  for (const Chunk& chunk : chunks) {
    const std::uint32_t end = chunk.tileStart[tile + 1];
    for (std::uint32_t r = chunk.tileStart[tile]; r < end; ++r) {
      if (r + kAhead < end) {
        const char* ahead = reinterpret_cast<const char*>(&chunk.footprints[chunk.refs[r + kAhead]]);
        __builtin_prefetch(ahead);
        __builtin_prefetch(ahead + sizeof(Footprint) - 1);
      }
      const Footprint& f = chunk.footprints[chunk.refs[r]];
      const int x0 = std::max(int(f.x0), tileX), x1 = std::min(int(f.x1), tileX + size);
      const int y0 = std::max(int(f.y0), tileY), y1 = std::min(int(f.y1), tileY + size);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const float q = f.distance(x, y);
          if (q <= f.cutoff) visit(f, std::uint32_t((y - tileY) << kTileShift | (x - tileX)), x, y, q);
        }
    }
  }
}

PBS_CLONE_INLINE glm::vec3 unitOrZero(const glm::vec3& v) {
  const float length = glm::length(v);
  return length > 0.0f ? v * (1.0f / length) : glm::vec3(0.0f);
}

// Hot: every tile with splats, every pixel a splat touches, twice. The AVX2 clone gives the float
// conversions and rounding single instructions.
PBS_AVX2_CLONES void drawTile(Framebuffer& framebuffer, const TileGrid& grid, std::uint32_t tile,
                              std::span<const Chunk> chunks, std::span<const SurfelSplatSet> sets,
                              const glm::vec3& view, TileScratch& scratch) {
  const int size = 1 << kTileShift;
  const int tileX = int(tile % grid.columns) << kTileShift, tileY = int(tile / grid.columns) << kTileShift;
  const int width = std::min(size, int(framebuffer.width) - tileX),
            height = std::min(size, int(framebuffer.height) - tileY);
  const auto pixelOf = [&](std::uint32_t local) {
    return std::size_t(tileY + int(local >> kTileShift)) * framebuffer.width + std::size_t(tileX) +
           (local & (size - 1));
  };
  bool any = false;
  for (const Chunk& chunk : chunks) any |= chunk.tileStart[tile + 1] > chunk.tileStart[tile];
  if (!any) {  // most tiles of a frame: only geometry, or nothing; rows of plain arrays, so the loop vectorises
    for (int y = 0; y < height; ++y) {
      const float* depth = framebuffer.depth.data() + pixelOf(std::uint32_t(y << kTileShift));
      float* coverage = framebuffer.coverage.data() + pixelOf(std::uint32_t(y << kTileShift));
      for (int x = 0; x < width; ++x) coverage[x] = depth[x] != kClearDepth ? 1.0f : 0.0f;
    }
    return;
  }
  // Row by row (each layer on its own: one assigned from the other stalled on the store of the first).
  for (int y = 0; y < height; ++y) {
    const std::uint32_t row = std::uint32_t(y << kTileShift);
    std::fill_n(scratch.front.begin() + row, width, kClearDepth);
    std::fill_n(scratch.nearest.begin() + row, width, kClearDepth);
    std::copy_n(framebuffer.depth.begin() + std::ptrdiff_t(pixelOf(row)), width, scratch.geometry.begin() + row);
    for (auto& layer : scratch.layers) std::fill_n(layer.begin() + row, width, LayerSums{});
  }

  // A splat deeper than the geometry by more than its tolerance is hidden by it.
  std::vector<Touch>& touches = scratch.touches;
  touches.clear();
  forEachCoveredPixel(chunks, tile, tileX, tileY, [&](const Footprint& f, std::uint32_t local, int x, int y, float q) {
    const float depth = f.depthAt(x, y);
    if (depth - f.tolerance <= scratch.geometry[local]) {
      scratch.front[local] = std::min(scratch.front[local], depth + f.tolerance);
      touches.push_back({&f, depth, q, local});
    }
  });
  for (const Touch& touch : touches) {
    const Footprint& f = *touch.footprint;
    const std::uint32_t local = touch.local;
    const float depth = touch.depth;
    const float coverage = f.amplitude * f.weight(touch.q);
    LayerSums& sums = scratch.layers[depth <= scratch.front[local] ? 0 : 1][local];
    sums.coverage += coverage;
    sums.color += coverage * glm::vec3(f.color);
    sums.normal += coverage * f.normal;
    if (depth < scratch.nearest[local]) {
      scratch.nearest[local] = depth;
      scratch.nearestSet[local] = f.set;
      scratch.nearestIndex[local] = f.index;
    }
  }

  // Front layer over back layer over geometry, in premultiplied colour.
  const bool ids = framebuffer.has(kChannelIds);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::uint32_t local = std::uint32_t(y << kTileShift | x);
      const std::size_t pixel = pixelOf(local);
      const bool geometry = scratch.geometry[local] != kClearDepth;
      if (scratch.nearest[local] == kClearDepth) {
        framebuffer.coverage[pixel] = geometry ? 1.0f : 0.0f;
        continue;
      }
      float alpha = geometry ? 1.0f : 0.0f;
      glm::vec3 color = geometry ? glm::vec3(framebuffer.color[pixel]) : glm::vec3(0.0f);
      // Shading reads |n · v|, so a normal's sign is arbitrary (a triangle's vertex normals may point inside):
      // blended as they are, a splat's normal and the opposite one of the geometry under it cancel to a sideways
      // one, a dark dot. Each is turned to face the eye first; a blend of such normals faces it too.
      const auto towardEye = [&](const glm::vec3& n) { return glm::dot(n, view) > 0.0f ? -n : n; };
      glm::vec3 normal = geometry ? towardEye(framebuffer.normal[pixel]) : glm::vec3(0.0f);
      for (int layer = 1; layer >= 0; --layer) {
        const LayerSums& sums = scratch.layers[layer][local];
        if (!(sums.coverage > 0.0f)) continue;
        const float a = layerAlpha(sums);
        color = a * (sums.color * (1.0f / sums.coverage)) + (1.0f - a) * color;
        normal = a * towardEye(unitOrZero(sums.normal)) + (1.0f - a) * normal;
        alpha = a + (1.0f - a) * alpha;
      }
      if (!(alpha > 0.0f)) {
        framebuffer.coverage[pixel] = geometry ? 1.0f : 0.0f;
        continue;
      }
      const glm::vec3 straight = glm::clamp(color * (1.0f / alpha), 0.0f, 255.0f);
      framebuffer.color[pixel] = glm::u8vec4(glm::round(straight), 255);
      framebuffer.normal[pixel] = unitOrZero(normal);
      framebuffer.coverage[pixel] = alpha;
      if (scratch.nearest[local] < scratch.geometry[local]) {
        framebuffer.depth[pixel] = scratch.nearest[local];
        if (ids) {
          const SurfelSplatSet& set = sets[scratch.nearestSet[local]];
          framebuffer.ids[pixel] = PixelIds{set.nodeId, set.instanceId, scratch.nearestIndex[local]};
        }
      }
    }
}

void checkInputs(const Framebuffer& framebuffer, const Camera& camera, std::span<const SurfelSplatSet> sets) {
  if (framebuffer.width != camera.width || framebuffer.height != camera.height)
    throw std::invalid_argument("drawBlendedSplats: the framebuffer is not the camera's size");
  if (!framebuffer.has(kChannelColor) || !framebuffer.has(kChannelNormal) || !framebuffer.has(kChannelCoverage))
    throw std::invalid_argument("drawBlendedSplats: needs the colour, normal and coverage channels");
  if (framebuffer.has(kChannelPosition))
    throw std::invalid_argument("drawBlendedSplats: the position channel is not supported");
  for (const SurfelSplatSet& set : sets)
    if (set.normals.size() != set.positions.size() || set.colors.size() != set.positions.size())
      throw std::invalid_argument("drawBlendedSplats: a set's positions, normals and colours differ in length");
}

}  // namespace

void drawBlendedSplats(Framebuffer& framebuffer, const Camera& camera, std::span<const SurfelSplatSet> sets,
                       const BlendOptions& options) {
  checkInputs(framebuffer, camera, sets);
  if (framebuffer.pixelCount() == 0) return;
  std::vector<std::size_t> starts(sets.size() + 1, 0);
  for (std::size_t s = 0; s < sets.size(); ++s) starts[s + 1] = starts[s] + sets[s].positions.size();
  const std::size_t total = starts.back();

  TileGrid grid;
  grid.width = framebuffer.width;
  grid.height = framebuffer.height;
  grid.shift = kTileShift;
  grid.columns = (grid.width + (1u << kTileShift) - 1) >> kTileShift;
  grid.rows = (grid.height + (1u << kTileShift) - 1) >> kTileShift;

  std::vector<Chunk> chunks((total + kChunkSurfels - 1) / kChunkSurfels);
  tbb::parallel_for(std::size_t(0), chunks.size(), [&](std::size_t c) {
    Chunk& chunk = chunks[c];
    chunk.footprints.resize(std::min(kChunkSurfels, total - c * kChunkSurfels));
    std::size_t kept = 0;
    forEachSetPart(sets, starts, c * kChunkSurfels, std::min(total, (c + 1) * kChunkSurfels),
                   [&](std::size_t s, std::size_t index, std::size_t count) {
                     const FootprintProjector projector(camera, sets[s], std::uint32_t(s), options);
                     kept += projector.projectRange(index, count, chunk.footprints.data() + kept);
                   });
    chunk.footprints.resize(kept);
    binChunk(grid, chunk);
  });

  const glm::vec3 view = headlightDirection(camera);
  tbb::enumerable_thread_specific<std::unique_ptr<TileScratch>> scratches;
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, grid.count(), 1),
                    [&](const tbb::blocked_range<std::uint32_t>& r) {
                      std::unique_ptr<TileScratch>& scratch = scratches.local();
                      if (!scratch) scratch = std::make_unique<TileScratch>();
                      for (std::uint32_t tile = r.begin(); tile != r.end(); ++tile)
                        drawTile(framebuffer, grid, tile, chunks, sets, view, *scratch);
                    });
}

}  // namespace pbs
