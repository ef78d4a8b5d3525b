// Depth-first octree walk over points by their centres, shared by the mesh splitter (points:
// triangle centroids) and the loose octree (points: mesh instances); internal to pbs_scene.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace pbs::detail {

// One cell as the walk visits it. Its ids are ids[begin, end); children only reorder inside that
// range, so a leaf's range is final when it is visited.
struct OctreeCell {
  std::uint32_t begin = 0;
  std::uint32_t end = 0;
  std::int64_t parent = -1;  // visit number of the parent cell, -1 for the root
  std::uint32_t slot = 0;    // which child of its parent: octant 0-7, or half 0-1 for a split by order
  bool leaf = false;
};

// Visits every cell of an octree over `ids` (reordering them) once, parents before children and
// children in slot order; visit numbers count from 0 in that order. `isLeaf(std::span<const
// std::uint32_t>)` decides whether a cell stops. A cell splits into the octants of its cube (the
// parent's octant; with a single non-empty octant, the cube around its own centres instead, so
// chains of one-child cells cannot occur); centres no cube can separate are split by order into
// halves, so the walk terminates for any input. Within a child, ids keep their order, which makes
// the result deterministic. Uses an explicit stack: any depth is safe.
template <class Vec, class IsLeaf, class Visit>
void walkOctree(std::span<std::uint32_t> ids, std::span<const Vec> centres, IsLeaf&& isLeaf, Visit&& visit) {
  using Scalar = typename Vec::value_type;
  struct Cube {
    Vec centre{0};
    Scalar half = 0;
    bool known = false;  // false: compute from the cell's own centres
  };
  struct Pending {
    OctreeCell cell;
    Cube cube;
  };

  const auto octantOf = [&](std::uint32_t id, const Vec& mid) {
    const Vec& p = centres[id];
    return static_cast<std::uint8_t>((p.x >= mid.x ? 1 : 0) | (p.y >= mid.y ? 2 : 0) | (p.z >= mid.z ? 4 : 0));
  };
  const auto tightCube = [&](std::span<const std::uint32_t> range) {
    Vec lo = centres[range.front()], hi = lo;
    for (std::uint32_t id : range) {
      lo = glm::min(lo, centres[id]);
      hi = glm::max(hi, centres[id]);
    }
    const Vec extent = hi - lo;
    return Cube{lo + extent * Scalar(0.5), std::max({extent.x, extent.y, extent.z}) * Scalar(0.5), true};
  };

  std::vector<std::uint8_t> octant(ids.size());
  std::vector<std::uint32_t> scratch(ids.size());
  std::vector<Pending> stack;
  if (!ids.empty()) stack.push_back({OctreeCell{0, static_cast<std::uint32_t>(ids.size()), -1, 0, false}, Cube{}});
  std::int64_t visits = 0;

  while (!stack.empty()) {
    Pending pending = stack.back();
    stack.pop_back();
    OctreeCell& cell = pending.cell;
    const std::span<std::uint32_t> range = ids.subspan(cell.begin, cell.end - cell.begin);
    cell.leaf = range.size() == 1 || isLeaf(std::span<const std::uint32_t>(range));
    visit(static_cast<const OctreeCell&>(cell));
    const std::int64_t self = visits++;
    if (cell.leaf) continue;

    // Count by octant; when the inherited cube leaves everything in one octant, the tight cube
    // around the cell's centres separates any two distinct centres.
    std::array<std::uint32_t, 8> count{};
    const auto separatesBy = [&](const Cube& cube) {
      count.fill(0);
      for (std::size_t i = 0; i < range.size(); ++i) ++count[octant[i] = octantOf(range[i], cube.centre)];
      return std::count(count.begin(), count.end(), 0u) < 7;
    };
    Cube cube = pending.cube.known ? pending.cube : tightCube(range);
    bool separates = separatesBy(cube);
    if (!separates && pending.cube.known) separates = separatesBy(cube = tightCube(range));

    std::vector<Pending> children;
    if (!separates) {
      const std::uint32_t middle = cell.begin + static_cast<std::uint32_t>(range.size() / 2);
      children.push_back({OctreeCell{cell.begin, middle, self, 0, false}, Cube{}});
      children.push_back({OctreeCell{middle, cell.end, self, 1, false}, Cube{}});
    } else {
      // Stable counting sort of the range by octant.
      std::array<std::uint32_t, 8> start{};
      for (int o = 1; o < 8; ++o) start[o] = start[o - 1] + count[o - 1];
      std::array<std::uint32_t, 8> next = start;
      for (std::size_t i = 0; i < range.size(); ++i) scratch[next[octant[i]]++] = range[i];
      std::copy_n(scratch.begin(), range.size(), range.begin());
      const Scalar quarter = cube.half * Scalar(0.5);
      for (std::uint32_t o = 0; o < 8; ++o) {
        if (count[o] == 0) continue;
        const Vec sign{Scalar((o & 1) ? 1 : -1), Scalar((o & 2) ? 1 : -1), Scalar((o & 4) ? 1 : -1)};
        children.push_back({OctreeCell{cell.begin + start[o], cell.begin + start[o] + count[o], self, o, false},
                            Cube{cube.centre + sign * quarter, quarter, true}});
      }
    }
    stack.insert(stack.end(), children.rbegin(), children.rend());
  }
}

}  // namespace pbs::detail
