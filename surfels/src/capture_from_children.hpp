// Capturing an inner node from its children's surfel arrays instead of their triangles.
#pragma once

#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/capture.hpp"
#include "pbs/surfels/surfel_file.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace pbs::detail {

// The capture of `node` (in the frame of `frame`, from analyzeSubtree) in which every child with an
// array (arrayOfNode[child] != kNoSurfels, arrays already made) is drawn as that array's surfels, square
// splats as wide as the array's mean spacing (from its packing value) in capture pixels, and the rest
// (the node's own mesh, children below the threshold) as triangles. It costs the children's surfel
// counts instead of the subtree's triangles; what it loses against the exact capture is measured by
// the test Surfelize.ChildSurfelCaptureErrorOnSharedScene.
// The nodes such a capture draws as triangles: `node` itself (if it has a mesh) and the whole subtrees of its
// children without an array.
std::vector<std::uint32_t> childCaptureTriangleNodes(const Scene& scene, std::uint32_t node,
                                                     std::span<const std::uint32_t> arrayOfNode);

CaptureResult captureFromChildSurfels(const Scene& scene, const Hierarchy& frame, std::uint32_t node,
                                      std::span<const SurfelArray> arrays, std::span<const std::uint32_t> arrayOfNode,
                                      const CaptureOptions& options);

}  // namespace pbs::detail
