// The top level of the Embree casters: instances of the mesh BVHs in Embree's origin-relative frame,
// what a camera's rays are cast at, and the casting itself.
#pragma once

#include "embree_meshes.hpp"
#include "embree_shading.hpp"
#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/scene/scene_draws.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

struct EmbreeInstances {
  glm::dvec3 origin{0.0};  // Embree's frame is world − origin
  EmbreeSceneHandle top;
  std::vector<ShadedInstance> shaded;  // by the top-level scene's geometry id
  std::vector<Bounds> footprint;       // where the instances lie (coveringBoxes): rays are cast only where these show
};

// The centre of the nodes' world bounds: Embree works in single precision, so its frame is centred
// there and far-from-origin scenes keep their digits.
glm::dvec3 nodesCenter(const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes);
// Every node of `scene`, in index order: what an EmbreeScene of the whole scene is made over.
std::vector<std::uint32_t> allNodes(const Scene& scene);

// The committed top-level scene over the instances of `nodes` (from rayInstanceNodes, their meshes
// built in `meshes`), instance i being nodes[i]. `materials` must outlive the result.
EmbreeInstances makeEmbreeInstances(const EmbreeMeshes& meshes, const Scene& scene, const Hierarchy& hierarchy,
                                    const SceneMaterials& materials, std::span<const std::uint32_t> nodes,
                                    const glm::dvec3& origin);

// Rays go in 16-ray packets of 4×4 pixel blocks.
inline constexpr std::uint32_t kRayBlock = 4;

// Overwrites every pixel of the framebuffer's channels from one ray per pixel centre (see
// EmbreeScene::render), rows of blocks in parallel. Rays are cast only in the blocks where the instances'
// footprint shows (footprintBlocks): a scene seen from afar covers a small part of the image, and casting
// every other pixel's ray cost 22 ms of each 1920×1080 frame on two cores (the default scene from 2,000
// radii away: 22.4 ms, 3.5 without them). The other pixels are cleared as a miss there would clear them.
// Throws std::invalid_argument when the framebuffer is not the camera's size.
void castRays(const EmbreeInstances& instances, const Camera& camera, Framebuffer& framebuffer);

// The blocks (as castRays numbers them) that the window projections of `boxes`, one pixel wider all
// round, overlap: where instances inside those boxes can be hit. A box reaching to or behind the eye
// plane covers every block.
std::vector<std::uint8_t> footprintBlocks(const Camera& camera, std::span<const Bounds> boxes);

// At most kCoveringCells³ boxes whose union holds every box of `boxes`, for footprintBlocks to mark per frame
// at a bounded cost however many instances a scene has: the boxes themselves when there are no more than
// that, else the union of those whose centres share a cell of a uniform grid over them. Empty boxes are
// left out. Deterministic: the order of `boxes` decides nothing but the order of the result.
inline constexpr std::size_t kCoveringCells = 16;
std::vector<Bounds> coveringBoxes(std::span<const Bounds> boxes);

}  // namespace pbs
