// Procedural parts for the generated scenes. Each returns one finished mesh: positions, unit
// normals, texture coordinates, one part (material 0) and bounds; closed shapes are watertight up to
// texture seams, and faces are counter-clockwise seen from outside. Units are metres, +Y is up,
// texture coordinates run one repeat per kTextureMetres, and `segments` sets the resolution.
#pragma once

#include "pbs/scene/scene.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>

namespace pbs {

inline constexpr float kTextureMetres = 4.0f;

// x and z within ±size/2, y from 0 to size.y.
Mesh makeBox(glm::vec3 size);

// A closed cylinder standing on the origin.
Mesh makeCylinder(float radius, float height, std::uint32_t segments);

// A round pipe along a polyline, its corners bent with `bendRadius`, closed at both ends.
Mesh makePipe(std::span<const glm::vec3> polyline, float radius, float bendRadius, std::uint32_t segments);

// A vessel standing on the origin: a shell of `shellHeight` between two heads of height
// capRatio * radius (1: hemispheres, less: dished heads; a sphere when shellHeight is 0). Its
// texture spans the outline once from pole to pole.
Mesh makeTank(float radius, float shellHeight, float capRatio, std::uint32_t segments);

// A ring about +Y in the XZ plane.
Mesh makeTorus(float majorRadius, float minorRadius, std::uint32_t majorSegments, std::uint32_t minorSegments);

// A wall of revolution of `thickness` whose outer face passes through `outline` (radius, height)
// from bottom to top: open at both ends like a cooling tower or a stack, but a closed solid.
Mesh makeRevolvedWall(std::span<const glm::vec2> outline, float thickness, std::uint32_t segments);

struct GearShape {
  std::uint32_t teeth = 24;
  float rootRadius = 0.9f;
  float tipRadius = 1.0f;
  float holeRadius = 0.2f;
  float thickness = 0.2f;
};

// A spur gear about +Y from y = 0 to the thickness: trapezoid teeth, a round hole for the shaft.
// `arcSegments` steps each tooth's tip and root arcs.
Mesh makeGear(const GearShape& shape, std::uint32_t arcSegments);

struct LatticeShape {
  float baseWidth = 4.0f;
  float topWidth = 1.5f;
  float height = 30.0f;
  std::uint32_t bays = 10;
  float beamWidth = 0.15f;
};

// A tapering square truss tower standing on the origin: four legs, a girt at every bay and X
// braces on every face, each beam a square bar. `bays` sets the resolution.
Mesh makeLattice(const LatticeShape& shape);

}  // namespace pbs
