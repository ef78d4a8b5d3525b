// How large a node's frame and a pixel are at a node, and the prefix draw they give, for the LOD
// traversals (threshold and budget).
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/surfels/frame_cost.hpp"
#include "pbs/surfels/lod_render.hpp"
#include "pbs/surfels/scene_surfels.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pbs::lod {

// World size of one pixel at `point`: constant for orthographic cameras, growing with the eye-space
// depth for perspective ones (row 1 of the projection scales eye y to clip y).
inline double worldPixelAt(const Camera& camera, const glm::dvec3& point) {
  const double perUnitDepth = 2.0 / (camera.projection[1][1] * camera.height);
  if (camera.isOrthographic()) return perUnitDepth;
  const double depth = -(camera.view * glm::dvec4(point, 1.0)).z;
  return perUnitDepth * std::max(depth, 0.0);
}

// The node frame's scale as the cube root of the volume change (mirroring ignored).
inline double frameScale(const glm::dmat4& world) { return std::cbrt(std::abs(glm::determinant(glm::dmat3(world)))); }

struct NodeScale {
  double worldPixel = 0.0;  // world size of one pixel at the array's centre
  double scale = 1.0;       // node frame to world
};

// The scale at which a node of world transform `world` draws its array `splats`.
inline NodeScale nodeScale(const Camera& camera, const glm::dmat4& world, const SplatArray& splats) {
  return {worldPixelAt(camera, glm::dvec3(world * glm::dvec4(splats.box.center(), 1.0))), frameScale(world)};
}

// The draw of `count` surfels of a prefix sized for `full` (count ≤ full while a transition thins it):
// discs that close the surface with the whole prefix, and their size in pixels at the node.
inline LodDraws::Surfels prefixDraw(std::uint32_t node, std::uint32_t array, const SplatArray& splats,
                                    const NodeScale& at, std::uint32_t full, std::uint32_t count) {
  // An array of one surfel has no spacing to measure: its disc spans the box.
  const double radius = splats.packing > 0.0 ? splats.spacing(full) : glm::length(splats.box.size()) / 2.0;
  const double pointSize = at.worldPixel > 0.0 ? 2.0 * radius * at.scale / at.worldPixel : 0.0;
  return {node, array, count, radius, pointSize, full};
}

// The projected size (pixels) above which node `node`'s subtree drawn by rays is predicted (options.frameCosts)
// to cost less than its prefix, which asks for `demand` surfels at `size`; infinite where it never does. Per
// pixel of the node's box the prefix pays for its surfels (their number grows with the size², as the box's
// pixels do) and the rays for their pixels, but the rays also pay for each node of the subtree they draw
// whatever its size: with c the per-node price, n the mesh nodes, p_s and p_r the two prices per pixel and F the
// preference for rays (options.raysPreference: rays are chosen up to F times the prefix's price), the sizes above
// √(c·n / (F·p_s − p_r)). Only where rays may draw the geometry: the rasterizer's price is per triangle, which is
// what the paper's surfels save.
inline double raysCheaperAbove(double demand, double size, const Hierarchy& hierarchy, std::uint32_t node,
                               const LodOptions& options) {
  constexpr double kNever = std::numeric_limits<double>::infinity();
  const double meshNodes = double(hierarchy.subtreeMeshNodes[node]);
  if (!options.descendWhereRaysCheaper || options.geometry == GeometryDrawer::Raster || !(size > 0.0) ||
      !(meshNodes > 0.0))
    return kNever;
  const FrameCosts& costs = options.frameCosts;
  const double surfelPrice = costs.perSurfel * demand / (size * size);
  const double rayPrice =
      costs.raysPerPixel + costs.raysPerBoxPixel * rayLevels(double(hierarchy.subtreeTriangles[node]));
  const double tolerated = options.raysPreference * surfelPrice;  // what the rays may cost and still be chosen
  if (!(tolerated > rayPrice)) return kNever;
  return std::sqrt(costs.raysPerNode * meshNodes / (tolerated - rayPrice));
}

// The projected size (pixels) up to which node `node` is drawn as its array's prefix rather than descended
// into: options.threshold, or lower where the array cannot meet the demand at the top of the transition band
// (options.descendExhausted: the demand grows with size², so the size at which it equals the array's length
// is size · √(length / demand(size))), or where its subtree's rays cost less than its prefix
// (raysCheaperAbove); all of it times options.descentScale (a near frame's, traverseLodForDrawer). The transition
// band lies above whichever it is, so neither change pops.
inline double descentThreshold(const SplatArray& splats, const NodeScale& at, double size, const Hierarchy& hierarchy,
                               std::uint32_t node, const LodOptions& options) {
  const double demand = prefixDemand(splats, size, at.worldPixel, at.scale, options);
  const double threshold = std::min(options.threshold, raysCheaperAbove(demand, size, hierarchy, node, options));
  if (!options.descendExhausted || !(size > 0.0) || !(demand > 0.0)) return options.descentScale * threshold;
  const double sufficient = size * std::sqrt(double(splats.size()) / demand) / (1.0 + options.band);
  return options.descentScale * std::min(threshold, sufficient);
}

}  // namespace pbs::lod
