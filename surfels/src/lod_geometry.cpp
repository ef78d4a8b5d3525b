// drawLodGeometry: the geometry nodes through the rasterizer or an EmbreeNodeCaster, whichever the cost
// model (fitted below) expects to finish first.
#include "pbs/surfels/lod_geometry.hpp"

#include "pbs/surfels/frame_cost.hpp"

#include "elapsed.hpp"
#include "pbs/raster/projected_box.hpp"
#include "pbs/raster/value_names.hpp"
#include "pbs/scene/scene_draws.hpp"

#include <algorithm>
#include <vector>

namespace pbs {
namespace {

using detail::Clock;
using detail::secondsSince;

constexpr ValueNames<GeometryDrawer, 3> kDrawerNames{
    {{{GeometryDrawer::Raster, "raster"}, {GeometryDrawer::Rays, "rays"}, {GeometryDrawer::Auto, "auto"}}}};

// The cost model (FrameCosts' geometry terms, whose defaults are these, but for the rays' 9.4 µs a node, which
// `pbs calibrate default` fitted later, lod_render.hpp): seconds per unit of work, fitted by least
// squares (absolute seconds, coefficients kept non-negative) to 192 frames timed on the 2-core machine with no compiler
// running, each the fastest of 15 runs (the exact frames: of 6). The frames: the geometry nodes of the orbit, approach
// and flythrough paths (8 frames each) at 1920×1080 and 960×540 with --threshold 64, 128 and 512, over the embedded
// default scene and a city of bunny.glb (`pbs generate city --levels 3 --fanout 10`), each with its
// surfels from `pbs surfelize`; and the same paths with every visible mesh as geometry (exact mode, 4
// frames each at 1920×1080). With covered = min(boxPixels, imagePixels):
//   raster ≈ 12.1 ns · triangles + 41.6 ns · covered
//   rays   ≈  2.9 ns · image pixels + 55.2 ns · covered + 172 ns · triangles of BVHs yet to build
// (the last the median of the 36 builds seen, of 8 k to 448 k triangles). Shading a covered pixel costs
// both about the same, so the choice turns on triangles (each set up by the rasterizer) against image
// pixels (each a ray, or a clear outside the geometry's footprint). Single frames are off by about 30 %
// (median), but the choice is what counts: over the 168 LOD frames it took 5.43 s against 6.24 s by
// raster alone, 7.06 s by rays alone and 5.35 s choosing after the fact (21 choices wrong, costing 80 ms
// in all, 24 ms at worst); over the 24 exact frames 1.57 s against 8.16 s and 1.68 s, none wrong. Fitted
// on either scene alone, the other's frames still come within 6 % of choosing after the fact. More cores
// speed both drawers alike, and only the constants' ratios decide. A BVH yet to build is shared by the
// frames it is expected to serve (LodOptions::bvhBuildFrames; whole for a single view). `pbs calibrate`
// refits all but the builds for another machine.
constexpr double kRaysPerBuiltTriangle = 172e-9;

}  // namespace

std::optional<GeometryDrawer> geometryDrawerFromName(std::string_view name) { return kDrawerNames.parse(name); }

const char* geometryDrawerName(GeometryDrawer drawer) { return kDrawerNames.name(drawer).data(); }

GeometryWork geometryWork(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                          const Camera& camera, const EmbreeNodeCaster* rays) {
  GeometryWork work;
  work.imagePixels = std::uint64_t(camera.width) * camera.height;
  std::vector<char> counted(scene.meshes.size(), 0);
  const BoxProjection boxes(camera);
  for (std::uint32_t node : nodes) {
    const std::int32_t mesh = scene.nodes[node].mesh;
    if (mesh < 0) continue;
    const Bounds box = instanceWorldBounds(scene, hierarchy, node);
    if (boxes.outside(box)) continue;
    const std::uint64_t triangles = scene.meshes[std::size_t(mesh)].triangleCount();
    work.triangles += triangles;
    // A box around or behind the eye projects to +infinity: it fills at most the image.
    const double pixels = std::min(boxes.pixels(box), double(work.imagePixels));
    work.boxPixels += pixels;
    ++work.nodes;
    work.boxRayPixels += pixels * rayLevels(double(triangles));
    work.trianglesOnPixels += std::min(double(triangles), pixels);
    if ((!rays || !rays->drawnBefore(std::uint32_t(mesh))) && !counted[std::size_t(mesh)]) {
      counted[std::size_t(mesh)] = 1;
      work.unbuiltTriangles += triangles;
    }
  }
  return work;
}

GeometryCosts estimateGeometryCosts(const GeometryWork& work, const FrameCosts& costs, double buildFrames) {
  // The frame cost model's geometry terms (predictGeometryCost), and for rays the BVHs a frame must build.
  const FrameWork frame{.imagePixels = double(work.imagePixels),
                        .triangles = double(work.triangles),
                        .geometryPixels = work.boxPixels,
                        .geometryRayPixels = work.boxRayPixels,
                        .trianglesOnPixels = work.trianglesOnPixels,
                        .geometryNodes = double(work.nodes)};
  return {.raster = predictGeometryCost(costs, frame, GeometryDrawer::Raster),
          .rays = predictGeometryCost(costs, frame, GeometryDrawer::Rays) +
                  kRaysPerBuiltTriangle * double(work.unbuiltTriangles) / (buildFrames > 1.0 ? buildFrames : 1.0)};
}

GeometryDrawer chooseGeometryDrawer(const GeometryWork& work, const FrameCosts& costs, double buildFrames) {
  const GeometryCosts estimate = estimateGeometryCosts(work, costs, buildFrames);
  return estimate.rays < estimate.raster ? GeometryDrawer::Rays : GeometryDrawer::Raster;
}

namespace {

// The drawer that draws `work`: rays where there is a caster and `drawer` names them or Auto prefers them.
GeometryDrawer drawerFor(const GeometryWork& work, GeometryDrawer drawer, const EmbreeNodeCaster* rays,
                         const FrameCosts& costs, double buildFrames) {
  if (!rays) return GeometryDrawer::Raster;
  return drawer == GeometryDrawer::Auto ? chooseGeometryDrawer(work, costs, buildFrames) : drawer;
}

}  // namespace

void passOverLodGeometry(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                         const Camera& camera, GeometryDrawer drawer, EmbreeNodeCaster* rays, const FrameCosts& costs,
                         double buildFrames) {
  const GeometryWork work = geometryWork(scene, hierarchy, nodes, camera, rays);
  if (drawerFor(work, drawer, rays, costs, buildFrames) == GeometryDrawer::Rays) rays->noteDrawn(camera, nodes);
}

GeometryPass drawLodGeometry(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                             const Camera& camera, Framebuffer& framebuffer, GeometryDrawer drawer,
                             EmbreeNodeCaster* rays, const FrameCosts& costs, double buildFrames) {
  const auto start = Clock::now();
  GeometryPass pass;
  pass.work = geometryWork(scene, hierarchy, nodes, camera, rays);
  if (drawerFor(pass.work, drawer, rays, costs, buildFrames) == GeometryDrawer::Rays) {
    pass.drawer = GeometryDrawer::Rays;
    pass.bvhBuildSeconds = rays->render(camera, nodes, framebuffer).seconds;
  } else {
    drawNodeTriangles(scene, hierarchy, nodes, camera, framebuffer, TriangleOptions{.cullBackFaces = false});
  }
  pass.seconds = secondsSince(start);
  return pass;
}

}  // namespace pbs
