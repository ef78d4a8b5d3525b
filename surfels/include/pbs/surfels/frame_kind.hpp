// Near, mid or far: a frame's kind by how much of what it shows the LOD traversal draws as geometry,
// so that results over a camera path can be read per kind.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/lod_render.hpp"
#include "pbs/surfels/scene_surfels.hpp"

#include <cstdint>
#include <optional>
#include <string_view>

namespace pbs {

enum class FrameKind { Near, Mid, Far };

inline constexpr double kNearGeometryShare = 0.5;  // at least this share drawn as geometry: near
inline constexpr double kFarGeometryShare = 0.05;  // below this share: far

const char* frameKindName(FrameKind kind);  // "near", "mid", "far"
std::optional<FrameKind> frameKindFromName(std::string_view name);

// Near when geometryShare ≥ kNearGeometryShare, far when it is below kFarGeometryShare, else mid.
FrameKind frameKindOf(double geometryShare);

// The pixels (one sample each, at their centres) that the geometry nodes traverseLod(…, options)
// picks cover, drawn alone: depth only, so it is cheap next to the frame itself. Divided by the
// pixels the whole scene covers (a reference image's coverage) it is the frame's geometry share.
std::uint64_t geometryPixels(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                             const Camera& camera, const LodOptions& options);

}  // namespace pbs
