// footprintBlocks: where on screen a set of boxes can show, in castRays' 4×4 blocks, so rays are cast
// only where they can hit. Boxes are marked as rectangles in a 2D difference array, then summed, so the
// cost is one step per box plus one per block however large the boxes are. coveringBoxes: a bounded
// number of boxes standing for a scene's many.
#include "embree_instances.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pbs {

std::vector<std::uint8_t> footprintBlocks(const Camera& camera, std::span<const Bounds> boxes) {
  const auto blocksX = std::int64_t((camera.width + kRayBlock - 1) / kRayBlock);
  const auto blocksY = std::int64_t((camera.height + kRayBlock - 1) / kRayBlock);
  const std::int64_t stride = blocksX + 1;
  std::vector<std::int32_t> marks(std::size_t(stride * (blocksY + 1)), 0);
  const glm::dmat4 clipFromWorld = camera.clipFromWorld();
  // The block of window coordinate `w`, clamped to [0, blocks]; NaN gives 0.
  const auto blockOf = [](double w, std::int64_t blocks) {
    const double block = std::floor(w / kRayBlock);
    return block >= double(blocks) ? blocks : block > 0.0 ? std::int64_t(block) : std::int64_t(0);
  };
  for (const Bounds& box : boxes) {
    if (box.empty()) continue;
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    bool whole = false;
    for (int corner = 0; corner < 8 && !whole; ++corner) {
      const glm::dvec3 p{(corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                         (corner & 4) ? box.max.z : box.min.z};
      const glm::dvec4 clip = clipFromWorld * glm::dvec4(p, 1.0);
      const glm::dvec2 window(windowFromClip(camera, clip));
      whole = !(clip.w > 0.0) || !std::isfinite(window.x) || !std::isfinite(window.y);
      lo = glm::min(lo, window);
      hi = glm::max(hi, window);
    }
    // One pixel of margin: Embree intersects in float, so a hit may land a hair outside its box.
    const std::int64_t x0 = whole ? 0 : blockOf(lo.x - 1.0, blocksX);
    const std::int64_t y0 = whole ? 0 : blockOf(lo.y - 1.0, blocksY);
    const std::int64_t x1 = whole ? blocksX : std::min(blockOf(hi.x + 1.0, blocksX) + 1, blocksX);
    const std::int64_t y1 = whole ? blocksY : std::min(blockOf(hi.y + 1.0, blocksY) + 1, blocksY);
    if (x0 >= x1 || y0 >= y1) continue;
    ++marks[std::size_t(y0 * stride + x0)];
    --marks[std::size_t(y0 * stride + x1)];
    --marks[std::size_t(y1 * stride + x0)];
    ++marks[std::size_t(y1 * stride + x1)];
  }
  std::vector<std::uint8_t> blocks(std::size_t(blocksX * blocksY), 0);
  std::vector<std::int32_t> column(std::size_t(blocksX), 0);  // running sums down each column
  for (std::int64_t y = 0; y < blocksY; ++y) {
    std::int32_t row = 0;
    for (std::int64_t x = 0; x < blocksX; ++x) {
      row += marks[std::size_t(y * stride + x)];
      column[std::size_t(x)] += row;
      blocks[std::size_t(y * blocksX + x)] = column[std::size_t(x)] > 0;
    }
  }
  return blocks;
}

std::vector<Bounds> coveringBoxes(std::span<const Bounds> boxes) {
  constexpr std::size_t kCells = kCoveringCells * kCoveringCells * kCoveringCells;
  Bounds all;
  std::size_t nonEmpty = 0;
  for (const Bounds& box : boxes) {
    all.extend(box);
    nonEmpty += !box.empty();
  }
  std::vector<Bounds> covering;
  if (nonEmpty <= kCells) {
    for (const Bounds& box : boxes)
      if (!box.empty()) covering.push_back(box);
    return covering;
  }
  // The cell of a centre along one axis. A flat extent puts every centre in cell 0, and so does a NaN (an
  // extent that overflowed to infinity).
  const glm::dvec3 extent = all.size();
  const auto cellAlong = [&](double c, int axis) {
    const double t = extent[axis] > 0.0 ? (c - all.min[axis]) / extent[axis] : 0.0;
    return t > 0.0 ? std::min(std::size_t(std::min(t, 1.0) * double(kCoveringCells)), kCoveringCells - 1) : 0;
  };
  std::vector<Bounds> cells(kCells);
  for (const Bounds& box : boxes) {
    if (box.empty()) continue;
    const glm::dvec3 c = box.center();
    cells[(cellAlong(c.z, 2) * kCoveringCells + cellAlong(c.y, 1)) * kCoveringCells + cellAlong(c.x, 0)].extend(box);
  }
  for (const Bounds& cell : cells)
    if (!cell.empty()) covering.push_back(cell);
  return covering;
}

}  // namespace pbs
