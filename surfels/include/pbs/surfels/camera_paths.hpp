// Named camera paths through a scene (an orbit around it, an approach into its densest part, a
// flythrough among its geometry), defined from the scene's hierarchy alone, so every command that
// renders a sequence of frames sees the same cameras.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/orbit_camera.hpp"
#include "pbs/scene/hierarchy.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace pbs {

// Below, C and R are the centre and half the diagonal of the scene's box (the union of the roots'
// worldBounds). A box of no diagonal (no geometry, or all of it in one point) is taken as the cube of
// diagonal 2 around that point (the origin when there is no geometry): R = 1, as orbitCamera treats a
// radius ≤ 0, and no path divides by zero. Every camera but the orbit's is a
// perspectiveCamera with orbitCamera's vertical field of view (kOrbitFovYDegrees), +Y up, near =
// max(|eye − C| − R, 1e-3·R) and far = |eye − C| + R, which encloses the whole box from the eye.
//
// Orbit: today's `pbs render --frames` orbit, camera for camera: frame f is
//   orbitCamera(C, R, {orbit.azimuth + 360·f/frames, orbit.elevation, orbit.distance}).
//
// Approach: from outside the bounding sphere straight into the densest region, ending inside it.
//   Target region: start at a virtual root over all roots and repeatedly step to the child with the
//   most subtreeTriangles (ties: the lower node index) as long as that child has geometry and its box
//   diagonal is at least kApproachRegionFraction of the scene's; the region is the box reached
//   (the scene's box when no root qualifies), T its centre, r_T half its diagonal.
//   Direction: dir = (cos el·cos az, sin el, cos el·sin az) from orbit.azimuth and orbit.elevation
//   (elevation clamped to ±89.9° like orbitCamera's). Eyes T + dir·d_f, each looking along −dir
//   (at T), with d spaced geometrically, d_f = d_0·(d_end/d_0)^(f/(frames−1)), from
//   d_0 = |T − C| + max(orbit.distance, kApproachMinStart)·R (outside the bounding sphere) down to
//   d_end = half the distance from T along dir to the region box's surface (so the last eye is
//   inside the region), at least 1e-3·r_T (a region flat across dir cannot be entered: the last
//   eye then hovers just above it). A single frame is the first one.
//
// Flythrough: a closed loop among the scene's triangles, inside its box (min, max; height
//   H = max(max.y − min.y, kFlyFlatHeight·max(size.x, size.z)), so a flat scene still gets a camera
//   above its plane). Where the triangles lie: every node with a mesh of its own adds the centre of its
//   world box, weighted by its mesh's triangles, to a mean M and standard deviations σ per axis (in X
//   and Z). The loop's centre is M (clamped into the box) and its semi-axes a = kFlySpread·σ per axis
//   (for triangles spread evenly over the box, 0.66 of its half extents), at most kFlyRoom of the way
//   from M to the box's nearer side and at least 1e-3·R, so the loop never collapses. With θ = 2π·s:
//     eye(s) = (M.x + a.x·cos θ, min.y + H·(0.25 − 0.15·cos 2θ), M.z + a.z·sin θ)
//   an ellipse whose height goes twice per loop between kFlyLowHeight (10 %) and kFlyHighHeight (40 %)
//   of H, starting at the low point on its +X side. Frames are spaced evenly by arc length (frame f at
//   arc length L·f/frames, no repeated frame: the last frame is one step before the first). Each looks
//   along the loop's horizontal tangent (growing θ: from +X toward +Z, clockwise seen from above)
//   pitched down by kFlyPitchDegrees.
//
// Everything is computed in double relative to C, so scenes far from the origin and tiny scenes keep
// their digits, and is deterministic: the same call gives the same bits.

enum class CameraPath { Orbit, Approach, Flythrough };

inline constexpr double kApproachRegionFraction = 0.2;
inline constexpr double kApproachMinStart = 1.1;  // bounding radii beyond |T − C|, at least
inline constexpr double kFlySpread = 1.15;        // semi-axes in standard deviations of the triangles
inline constexpr double kFlyRoom = 0.9;           // at most this much of the way from the loop's centre to the box
inline constexpr double kFlyFlatHeight = 0.05;
inline constexpr double kFlyLowHeight = 0.10;   // of H, the loop's lowest point
inline constexpr double kFlyHighHeight = 0.40;  // of H, the loop's highest point
inline constexpr double kFlyPitchDegrees = 15.0;

// The union of the roots' worldBounds: the box whose centre C and half diagonal R the paths use (empty
// when there is no geometry).
Bounds sceneBounds(const Hierarchy& hierarchy, std::span<const std::uint32_t> roots);

// "orbit", "approach", "flythrough"; nullopt for any other name.
std::optional<CameraPath> cameraPathFromName(std::string_view name);
const char* cameraPathName(CameraPath path);

struct PathView {
  Camera camera;
  glm::dvec3 eye{0.0};      // world position of the camera
  glm::dvec3 forward{0.0};  // unit viewing direction
  // Where the eye sits as seen from what it looks at, in degrees around +Y from +X toward +Z (the
  // orbit's convention): the orbit's frame azimuth (orbit.azimuth + 360·f/frames, not wrapped); for the
  // other paths the azimuth of −forward in [0, 360), 0 when forward is vertical.
  double azimuthDegrees = 0.0;
};

// `frames` cameras (0 is taken as 1) of width × height pixels along `path` through the scene whose
// analysed hierarchy and roots are given, as defined above. `orbit` gives the orbit's start azimuth,
// elevation and distance, and the approach's direction and start distance.
std::vector<PathView> cameraPath(CameraPath path, const Hierarchy& hierarchy, std::span<const std::uint32_t> roots,
                                 const Orbit& orbit, std::uint32_t frames, std::uint32_t width, std::uint32_t height);

// The approach's target region (see above): its box, or the scene's when no root qualifies (empty for a
// scene without geometry).
Bounds approachRegion(const Hierarchy& hierarchy, std::span<const std::uint32_t> roots);

}  // namespace pbs
