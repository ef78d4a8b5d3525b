// The alternative to surfels a user would pick: the same LOD traversal, but a node small enough to
// draw surfels draws its subtree's meshes from a simplified copy of the scene (simplified_meshes.hpp).
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/lod_render.hpp"
#include "pbs/surfels/scene_surfels.hpp"

namespace pbs {

// traverseLod decides which nodes are small (those with surfel arrays below the threshold); their
// subtrees are drawn as triangles from `simplified`, every other visible mesh from `scene`. Triangles
// cannot fade, so the band is ignored (a band would only draw a node's subtree twice). `simplified`
// must be simplifyScene of `scene` (same nodes), whose Hierarchy serves both. Stats: triangles counts
// both kinds, per instance; nodesSurfels the nodes drawn simplified; surfels 0. The image does not
// depend on the thread count.
LodStats renderSimplifiedLod(const Scene& scene, const Scene& simplified, const Hierarchy& hierarchy,
                             const SceneSurfels& surfels, const Camera& camera, Framebuffer& framebuffer,
                             const LodOptions& options);

}  // namespace pbs
