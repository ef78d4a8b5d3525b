// The one surface builder behind the procedural parts: a cross-section carried through a sequence
// of frames (a revolution, a straight extrusion or a bent pipe path), plus flat caps.
#pragma once

#include "pbs/scene/scene.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

// A point of a cross-section in its plane's (a, b) coordinates, with its outward normal in that
// plane and the texture coordinate v along the section.
struct SectionPoint {
  glm::vec2 position{0.0f};
  glm::vec2 normal{0.0f};
  float v = 0.0f;
  bool hardEdgeBefore = false;  // no surface between the previous point and this one
};

// Where the section plane sits: origin and orthonormal axes (a, b), and texture coordinate u.
struct SweepFrame {
  glm::vec3 origin{0.0f};
  glm::vec3 axisA{1.0f, 0.0f, 0.0f};
  glm::vec3 axisB{0.0f, 1.0f, 0.0f};
  float u = 0.0f;
};

// A closed loop repeats its first point at the end (the texture seam), and so does every
// section and frame list below that closes on itself.
std::vector<SectionPoint> circleSection(float radius, std::uint32_t segments, glm::vec2 centre = glm::vec2(0.0f));

// Frames turning about +Y: the section's a axis is the radius, b is +Y. u runs 0..uRepeat.
std::vector<SweepFrame> revolveFrames(std::uint32_t segments, float uRepeat);

// Frames along a polyline whose corners are rounded with arcs of `bendRadius` (positive where the
// polyline turns; smaller where a segment is too short), `bendSegments` steps per arc, without
// twist. u is the length run divided by `uLength`.
std::vector<SweepFrame> pathFrames(std::span<const glm::vec3> polyline, float bendRadius, std::uint32_t bendSegments,
                                   float uLength);

// The surface between consecutive frames and consecutive section points. Triangles face the way
// the normals point, so outward normals give counter-clockwise outward faces.
void appendSweep(Mesh& mesh, std::span<const SectionPoint> section, std::span<const SweepFrame> frames);

// A flat fan closing a closed section (star-shaped about the frame origin) at `frame`, facing
// `outward`; its texture coordinates are the section coordinates times `uvPerUnit`.
void appendCap(Mesh& mesh, std::span<const SectionPoint> section, const SweepFrame& frame, glm::vec3 outward,
               float uvPerUnit);

// appendSweep closed by a cap at the first and at the last of two or more frames: a solid
// prism, bar or pipe.
void appendCappedSweep(Mesh& mesh, std::span<const SectionPoint> section, std::span<const SweepFrame> frames,
                       float uvPerUnit);

// Appends a triangle wound so that it faces the way its vertex normals point; a triangle with no
// area is dropped.
void appendFacingTriangle(Mesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c);

// Wraps up a built part: one part covering every index with material 0, and the bounds.
Mesh finishPart(Mesh mesh, const char* name);

}  // namespace pbs
