// Drawing the LOD traversal's geometry nodes the fastest exact way: the tile rasterizer or Embree rays
// (an EmbreeNodeCaster), chosen per frame by a measured cost model. Both write the rasterizer's
// G-buffer conventions, so surfels drawn afterwards compose by depth the same way over either.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/scene/embree_node_caster.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/geometry_drawer.hpp"
#include "pbs/surfels/lod_render.hpp"

#include <cstdint>
#include <span>

namespace pbs {

// What drawing a frame's geometry nodes asks of each drawer, in the terms of the cost model.
struct GeometryWork {
  std::uint64_t triangles = 0;  // of the mesh instances in view
  // Σ over those instances of their world box's projected area, each at most the image: with the image
  // as a bound, the model's estimate of the pixels the geometry covers.
  double boxPixels = 0.0;
  double boxRayPixels = 0.0;       // the same, each times its mesh's BVH levels (rayLevels)
  double trianglesOnPixels = 0.0;  // Σ min(triangles, box pixels) over those instances (FrameWork's)
  std::uint64_t nodes = 0;         // the mesh instances in view
  std::uint64_t imagePixels = 0;
  std::uint64_t unbuiltTriangles = 0;  // of the meshes whose ray BVH is still to be built, each mesh once
};

// The work of drawing `nodes` (those with a mesh; others are skipped) from `camera`; unbuiltTriangles
// counts the meshes `rays` has not drawn before (EmbreeNodeCaster::drawnBefore; all of them without a
// caster): priced by the caster's own history, a frame's choice does not depend on BVHs another renderer
// built, nor on one that a memory budget let go.
GeometryWork geometryWork(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                          const Camera& camera, const EmbreeNodeCaster* rays);

// The cost model's estimates in seconds, by the geometry terms of `costs` (defaults: the machine the
// model was measured on, lod_geometry.cpp) and the BVH builds, each shared by `buildFrames` frames
// (LodOptions::bvhBuildFrames).
struct GeometryCosts {
  double raster = 0.0;
  double rays = 0.0;
};
GeometryCosts estimateGeometryCosts(const GeometryWork& work, const FrameCosts& costs = {}, double buildFrames = 1.0);

// Raster or Rays, whichever the model estimates cheaper (Raster on a tie, and for no work at all).
GeometryDrawer chooseGeometryDrawer(const GeometryWork& work, const FrameCosts& costs = {}, double buildFrames = 1.0);

// What drawLodGeometry did.
struct GeometryPass {
  GeometryDrawer drawer = GeometryDrawer::Raster;  // never Auto
  double seconds = 0.0;                            // the whole pass, BVH builds included
  double bvhBuildSeconds = 0.0;                    // of which mesh BVHs built for rays
  GeometryWork work;                               // what it drew, in the cost model's terms
};

// Draws the meshes of `nodes` (faces not culled) with `drawer`; Auto asks chooseGeometryDrawer (a build
// shared by `buildFrames` frames). Without a
// caster the rasterizer draws whatever `drawer` says. The rasterizer draws over the framebuffer; rays
// overwrite every pixel (a miss leaves the cleared values), so draw this before anything else. The
// image does not depend on the thread count.
GeometryPass drawLodGeometry(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                             const Camera& camera, Framebuffer& framebuffer, GeometryDrawer drawer,
                             EmbreeNodeCaster* rays, const FrameCosts& costs = {}, double buildFrames = 1.0);

// What drawLodGeometry with these arguments leaves for later frames, without drawing: the meshes it would
// draw by rays are noted as drawn by `rays` (EmbreeNodeCaster::noteDrawn). Nothing without a caster.
void passOverLodGeometry(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                         const Camera& camera, GeometryDrawer drawer, EmbreeNodeCaster* rays, const FrameCosts& costs,
                         double buildFrames);

}  // namespace pbs
