// Per-tile depth test of binned splats and the final writes of the winning points.
#include "points_tile.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <type_traits>

namespace pbs::points {

namespace {

// The tile's pixel rectangle in the framebuffer, and the tile-local copy of its pixels. With payloads, a pixel is
// one 64-bit word: its depth's bits in the low half, the payload of the splat that won it in the high half, so
// that a test is one load, one compare and one store. A depth-only framebuffer needs the depth alone, which
// halves the tile's footprint in L1.
template <bool kPayloads>
struct TileView {
  using Pixel = std::conditional_t<kPayloads, std::uint64_t, float>;

  std::uint32_t x0, y0, x1, y1;
  int shift;
  Pixel* pixels;

  static Pixel pack(float depth, std::uint32_t payload) {
    if constexpr (kPayloads)
      return std::uint64_t{payload} << 32 | std::bit_cast<std::uint32_t>(depth);
    else
      return depth;
  }
  static float depthOf(Pixel pixel) {
    if constexpr (kPayloads)
      return std::bit_cast<float>(static_cast<std::uint32_t>(pixel));
    else
      return pixel;
  }

  // Strict less: on equal depth the earlier point, already tested, keeps the pixel. Branch-free, since in a
  // dense draw about every other test changes the pixel's owner and a branch would mispredict.
  void test(std::uint32_t local, float depth, Pixel packed) const {
    const Pixel old = pixels[local];
    if constexpr (kPayloads) {
      // A mask, not a conditional: GCC turns the conditional into a branch.
      const std::uint64_t take = 0u - static_cast<std::uint64_t>(depth < depthOf(old));
      pixels[local] = (packed & take) | (old & ~take);
    } else {
      pixels[local] = depth < old ? depth : old;
    }
  }
  void test(std::uint32_t local, float depth, std::uint32_t payload) const { test(local, depth, pack(depth, payload)); }

  // test() over `count` consecutive pixels.
  void testRow(std::uint32_t local, std::uint32_t count, float depth, std::uint32_t payload) const {
    for (std::uint32_t i = local; i < local + count; ++i) test(i, depth, payload);
  }
};

// A PixelSplat's depth and payload lie side by side as View::pack puts them, so one load reads the packed pixel.
static_assert(offsetof(PixelSplat, payload) == offsetof(PixelSplat, depth) + 4 &&
              std::endian::native == std::endian::little);

template <class View>
void drawSplats(const View& view, std::span<const PixelSplat> splats) {
  for (const PixelSplat& splat : splats) {
    typename View::Pixel packed;
    std::memcpy(&packed, &splat.depth, sizeof packed);
    view.test(splat.pixel, splat.depth, packed);
  }
}

// The splat's rectangle clipped to the tile, row by row; `span` narrows a row to the pixels covered.
template <class View, class Splat, class Span>
void drawRows(const View& view, const Splat& splat, Span&& span) {
  const std::uint32_t x0 = std::max<std::uint32_t>(splat.x0, view.x0);
  const std::uint32_t x1 = std::min<std::uint32_t>(splat.x1, view.x1);
  const std::uint32_t y0 = std::max<std::uint32_t>(splat.y0, view.y0);
  const std::uint32_t y1 = std::min<std::uint32_t>(splat.y1, view.y1);
  for (std::uint32_t y = y0; y < y1; ++y) {
    std::uint32_t first = x0, last = x1;
    span(y, first, last);
    if (first < last)
      view.testRow(((y - view.y0) << view.shift) + (first - view.x0), last - first, splat.depth, splat.payload);
  }
}

template <class View>
void drawSplats(const View& view, std::span<const SquareSplat> splats) {
  for (const SquareSplat& splat : splats) drawRows(view, splat, [](std::uint32_t, std::uint32_t&, std::uint32_t&) {});
}

// A disc covers an interval of each row (around the centre, with the holding pixel next to or inside it): trim
// the row from both ends with the exact test and fill the rest untested.
template <class View>
void drawSplats(const View& view, std::span<const DiscSplat> splats) {
  for (const DiscSplat& splat : splats) {
    drawRows(view, splat, [&](std::uint32_t y, std::uint32_t& first, std::uint32_t& last) {
      while (first < last && !splat.covers(int(first), int(y))) ++first;
      while (last > first && !splat.covers(int(last - 1), int(y))) --last;
    });
  }
}

// A tile's segments in consecutive chunks lie far apart, out of the hardware prefetcher's sight: fetch
// the offsets that locate them a few chunks ahead. (Fetching the segments themselves ahead too gained
// nothing measurable, 2026-12-01.)
constexpr std::size_t kOffsetsAhead = 4;

template <class View>
void drawChunks(const View& view, std::span<const ChunkBins> chunks, std::uint32_t tile) {
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    if (c + kOffsetsAhead < chunks.size()) __builtin_prefetch(chunks[c + kOffsetsAhead].offsets.data() + tile);
    chunks[c].visit(tile, [&](auto splats) { drawSplats(view, splats); });
  }
}

template <bool kPayloads>
void drawTileWith(Framebuffer& framebuffer, const TileGrid& grid, std::uint32_t tile, std::span<const ChunkBins> chunks,
                  const PointSets& sets, std::uint64_t batchStart, TileScratch& scratch) {
  using View = TileView<kPayloads>;
  const std::uint32_t size = grid.tileSize();
  View view;
  view.x0 = (tile % grid.columns) << grid.shift;
  view.y0 = (tile / grid.columns) << grid.shift;
  view.x1 = std::min(view.x0 + size, grid.width);
  view.y1 = std::min(view.y0 + size, grid.height);
  view.shift = grid.shift;
  if constexpr (kPayloads)
    view.pixels = sized(scratch.packed, std::size_t(size) * size);
  else
    view.pixels = sized(scratch.depth, std::size_t(size) * size);

  const std::uint32_t width = view.x1 - view.x0;
  const auto rowStart = [&](std::uint32_t y) { return std::size_t(y) * grid.width + view.x0; };
  const auto localStart = [&](std::uint32_t y) { return std::size_t(y - view.y0) << grid.shift; };
  for (std::uint32_t y = view.y0; y < view.y1; ++y) {
    const float* depth = framebuffer.depth.data() + rowStart(y);
    typename View::Pixel* row = view.pixels + localStart(y);
    for (std::uint32_t x = 0; x < width; ++x) row[x] = View::pack(depth[x], 0);
  }

  drawChunks(view, chunks, tile);

  // Depth only goes down, so the whole row is copied back; the other channels change where it did.
  for (std::uint32_t y = view.y0; y < view.y1; ++y) {
    const typename View::Pixel* row = view.pixels + localStart(y);
    float* depth = framebuffer.depth.data() + rowStart(y);
    if constexpr (kPayloads) {
      alignas(64) float depths[kMaxTileSize];
      alignas(64) std::uint32_t payloads[kMaxTileSize];
      for (std::uint32_t x = 0; x < width; ++x) {
        depths[x] = View::depthOf(row[x]);
        payloads[x] = static_cast<std::uint32_t>(row[x] >> 32);
      }
      sets.writeChannels(framebuffer, rowStart(y), width, depths, payloads, batchStart);
      std::copy_n(depths, width, depth);
    } else {
      std::copy_n(row, width, depth);
    }
  }
}

}  // namespace

void drawTile(Framebuffer& framebuffer, const TileGrid& grid, std::uint32_t tile, std::span<const ChunkBins> chunks,
              const PointSets& sets, std::uint64_t batchStart, TileScratch& scratch) {
  if (std::none_of(chunks.begin(), chunks.end(),
                   [&](const ChunkBins& chunk) { return chunk.offsets[tile] != chunk.offsets[tile + 1]; }))
    return;
  if (sets.payloadKind() == PayloadKind::none)
    drawTileWith<false>(framebuffer, grid, tile, chunks, sets, batchStart, scratch);
  else
    drawTileWith<true>(framebuffer, grid, tile, chunks, sets, batchStart, scratch);
}

}  // namespace pbs::points
