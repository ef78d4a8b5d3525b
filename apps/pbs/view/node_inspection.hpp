// What `pbs view` shows of one node when it is clicked: its place in the scene and its surfel array, the
// blue-noise measure ρ(k) of the array's prefixes (the paper's Fig. 2, as a curve), and its capture
// views (the paper's Fig. 3). Each reads the scene and its surfel cache: call under the renderer's lock.
#pragma once

#include "../frame_scene.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace pbs::cli {

// Throws std::invalid_argument for a node the scene does not have.
void requireNode(const FrameScene& scene, std::uint32_t node);

// name, path (names from the root), triangles (own mesh), subtree_triangles, children, the world box's
// center and radius (half its diagonal); and with an array: array (index, surfels, coverage, packing,
// packing_end, area).
nlohmann::json describeNode(const FrameScene& scene, std::uint32_t node);

// ρ(k) of the node's array in its stored order at up to `points` log-spaced k ({"k": […], "rho": […]}),
// measured as `pbs analyze` measures a file's arrays; reads the whole array through the cache.
// std::invalid_argument for a node without an array.
nlohmann::json rhoCurve(FrameScene& scene, std::uint32_t node, std::size_t points);

// The node's capture views (base colour) side by side, 4 across, each `resolution` pixels square, as
// a PNG file's bytes; the meshes of its subtree are read for it when they are read on demand.
std::vector<std::uint8_t> captureViewsPng(FrameScene& scene, std::uint32_t node, std::uint32_t resolution);

}  // namespace pbs::cli
