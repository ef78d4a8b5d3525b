// Frame kinds: the LOD traversal's geometry drawn depth-only and its pixels counted.
#include "pbs/surfels/frame_kind.hpp"

#include "pbs/raster/framebuffer.hpp"
#include "pbs/raster/value_names.hpp"
#include "pbs/scene/scene_draws.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <functional>

namespace pbs {

namespace {

constexpr ValueNames<FrameKind, 3> kKindNames{
    {{{FrameKind::Near, "near"}, {FrameKind::Mid, "mid"}, {FrameKind::Far, "far"}}}};

}  // namespace

const char* frameKindName(FrameKind kind) { return kKindNames.name(kind).data(); }

std::optional<FrameKind> frameKindFromName(std::string_view name) { return kKindNames.parse(name); }

FrameKind frameKindOf(double geometryShare) {
  if (geometryShare >= kNearGeometryShare) return FrameKind::Near;
  if (geometryShare < kFarGeometryShare) return FrameKind::Far;
  return FrameKind::Mid;
}

std::uint64_t geometryPixels(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                             const Camera& camera, const LodOptions& options) {
  const LodDraws draws = traverseLod(scene, hierarchy, surfels, camera, options);
  Framebuffer depth = makeFramebuffer(camera.width, camera.height, 0);
  drawNodeTriangles(scene, hierarchy, draws.geometryNodes, camera, depth, TriangleOptions{.cullBackFaces = false});
  // A count is exact in any order of addition.
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, depth.pixelCount(), 1 << 16), std::uint64_t(0),
      [&](const tbb::blocked_range<std::size_t>& range, std::uint64_t covered) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) covered += depth.covered(i);
        return covered;
      },
      std::plus<>());
}

}  // namespace pbs
