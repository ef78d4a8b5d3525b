// The procedural parts (boxes, pipes, tanks, tori, walls of revolution, gears, lattice towers),
// each a cross-section swept through frames by procedural_sweep.
#include "procedural_parts.hpp"

#include "procedural_sweep.hpp"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pbs {
namespace {

constexpr float kUvPerMetre = 1.0f / kTextureMetres;

// Whole texture repeats over `length` metres, at least one, so a closed seam stays continuous.
float repeatsOver(float length) { return std::max(1.0f, std::round(length * kUvPerMetre)); }

// Perpendicular to the 2D edge from `from` to `to`, on the side of `side`.
glm::vec2 edgeNormal(glm::vec2 from, glm::vec2 to, glm::vec2 side) {
  glm::vec2 normal = glm::normalize(glm::vec2(to.y - from.y, from.x - to.x));
  return glm::dot(normal, side) < 0.0f ? -normal : normal;
}

// Appends a section point whose v continues the previous one's by the distance between them.
void addSectionPoint(std::vector<SectionPoint>& section, glm::vec2 position, glm::vec2 normal, bool hardEdgeBefore) {
  const float v =
      section.empty() ? 0.0f : section.back().v + glm::distance(section.back().position, position) * kUvPerMetre;
  section.push_back({position, normal, v, hardEdgeBefore});
}

// A closed polygon as a section with one flat face per edge. `inside` is a point the outward
// normals face away from.
std::vector<SectionPoint> flatFacedSection(std::span<const glm::vec2> corners, glm::vec2 inside) {
  std::vector<SectionPoint> section;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const glm::vec2 from = corners[i], to = corners[(i + 1) % corners.size()];
    const glm::vec2 normal = edgeNormal(from, to, (from + to) * 0.5f - inside);
    addSectionPoint(section, from, normal, true);
    addSectionPoint(section, to, normal, false);
  }
  return section;
}

// Two frames of a straight prism from `from` to `to`, with a section plane normal to it.
std::vector<SweepFrame> straightFrames(glm::vec3 from, glm::vec3 to, glm::vec3 axisA) {
  const glm::vec3 direction = glm::normalize(to - from);
  const glm::vec3 axisB = glm::cross(direction, axisA);
  return {SweepFrame{from, axisA, axisB, 0.0f}, SweepFrame{to, axisA, axisB, glm::distance(from, to) * kUvPerMetre}};
}

// A rectangular bar from `from` to `to`, its section 2 half.x wide along axisA (normal to the
// bar) and 2 half.y across.
void appendBar(Mesh& mesh, glm::vec3 from, glm::vec3 to, glm::vec2 half, glm::vec3 axisA) {
  const glm::vec2 corners[] = {{-half.x, -half.y}, {half.x, -half.y}, {half.x, half.y}, {-half.x, half.y}};
  appendCappedSweep(mesh, flatFacedSection(corners, glm::vec2(0.0f)), straightFrames(from, to, axisA), kUvPerMetre);
}

// Outward normals along a smooth outline of (radius, height) points, bottom to top.
std::vector<glm::vec2> outlineNormals(std::span<const glm::vec2> outline) {
  std::vector<glm::vec2> normals(outline.size());
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const glm::vec2 tangent = outline[std::min(i + 1, outline.size() - 1)] - outline[i > 0 ? i - 1 : 0];
    normals[i] = glm::normalize(glm::vec2(tangent.y, -tangent.x));
  }
  return normals;
}

}  // namespace

Mesh makeBox(glm::vec3 size) {
  Mesh mesh;
  appendBar(mesh, glm::vec3(0.0f), glm::vec3(0.0f, size.y, 0.0f), 0.5f * glm::vec2(size.x, size.z), glm::vec3(1, 0, 0));
  return finishPart(std::move(mesh), "box");
}

Mesh makeCylinder(float radius, float height, std::uint32_t segments) {
  const glm::vec3 axis[] = {glm::vec3(0.0f), glm::vec3(0.0f, height, 0.0f)};
  Mesh mesh = makePipe(axis, radius, 0.0f, segments);
  mesh.name = "cylinder";
  return mesh;
}

Mesh makePipe(std::span<const glm::vec3> polyline, float radius, float bendRadius, std::uint32_t segments) {
  std::vector<SectionPoint> section = circleSection(radius, segments);
  const float repeats = repeatsOver(glm::two_pi<float>() * radius);
  for (SectionPoint& point : section) point.v *= repeats;
  Mesh mesh;
  appendCappedSweep(mesh, section, pathFrames(polyline, bendRadius, std::max(2u, segments / 4), kTextureMetres),
                    kUvPerMetre);
  return finishPart(std::move(mesh), "pipe");
}

Mesh makeTank(float radius, float shellHeight, float capRatio, std::uint32_t segments) {
  // Each head is a quarter ellipse (radius, capHeight); the shell joins them with the same
  // horizontal normal, so the whole outline is one smooth section from pole to pole.
  const float capHeight = capRatio * radius;
  const std::uint32_t capSteps = std::max(2u, segments / 4);
  std::vector<SectionPoint> section;
  for (std::uint32_t i = 0; i <= 2 * capSteps; ++i) {
    const float t = glm::pi<float>() * float(i) / float(2 * capSteps);
    // The poles' radius is exactly 0, so their rings collapse to one point and close the surface.
    const float r = (i == 0 || i == 2 * capSteps) ? 0.0f : radius * std::sin(t);
    const float y = capHeight * (1.0f - std::cos(t));
    const glm::vec2 normal = glm::normalize(glm::vec2(std::sin(t) / radius, -std::cos(t) / capHeight));
    if (i == capSteps && shellHeight > 0.0f) addSectionPoint(section, glm::vec2(radius, y), normal, false);
    addSectionPoint(section, glm::vec2(r, y + (i >= capSteps ? shellHeight : 0.0f)), normal, false);
  }
  // One texture repeat from pole to pole, so a painted band goes once round the middle; round
  // it keeps the texels about as wide as they are tall.
  const float outlineLength = section.back().v;
  for (SectionPoint& point : section) point.v /= outlineLength;
  const float repeats = std::max(1.0f, std::round(glm::two_pi<float>() * radius * kUvPerMetre / outlineLength));
  Mesh mesh;
  appendSweep(mesh, section, revolveFrames(segments, repeats));
  return finishPart(std::move(mesh), "tank");
}

Mesh makeTorus(float majorRadius, float minorRadius, std::uint32_t majorSegments, std::uint32_t minorSegments) {
  Mesh mesh;
  appendSweep(mesh, circleSection(minorRadius, minorSegments, glm::vec2(majorRadius, 0.0f)),
              revolveFrames(majorSegments, std::max(1.0f, std::round(majorRadius / minorRadius))));
  return finishPart(std::move(mesh), "torus");
}

Mesh makeRevolvedWall(std::span<const glm::vec2> outline, float thickness, std::uint32_t segments) {
  const std::vector<glm::vec2> normals = outlineNormals(outline);
  const auto inner = [&](std::size_t i) { return outline[i] - normals[i] * thickness; };
  const std::size_t top = outline.size() - 1;
  // One closed section: up the outer face, across the top rim, down the inner face, back across
  // the bottom rim; the rims meet the faces at hard edges.
  std::vector<SectionPoint> section;
  for (std::size_t i = 0; i <= top; ++i) addSectionPoint(section, outline[i], normals[i], false);
  const glm::vec2 topNormal = edgeNormal(outline[top], inner(top), glm::vec2(0, 1));
  addSectionPoint(section, outline[top], topNormal, true);
  addSectionPoint(section, inner(top), topNormal, false);
  for (std::size_t i = top + 1; i-- > 0;) addSectionPoint(section, inner(i), -normals[i], i == top);
  const glm::vec2 bottomNormal = edgeNormal(inner(0), outline[0], glm::vec2(0, -1));
  addSectionPoint(section, inner(0), bottomNormal, true);
  addSectionPoint(section, outline[0], bottomNormal, false);

  float widest = 0.0f;
  for (const glm::vec2& p : outline) widest = std::max(widest, p.x);
  Mesh mesh;
  appendSweep(mesh, section, revolveFrames(segments, repeatsOver(glm::two_pi<float>() * widest)));
  return finishPart(std::move(mesh), "wall of revolution");
}

Mesh makeGear(const GearShape& shape, std::uint32_t arcSegments) {
  // The outline as (angle, radius) samples: per tooth a root arc, a rising flank, a tip arc and
  // a falling flank into the next tooth's root. The radius is a function of the angle, so the
  // faces between hole and outline are simple strips.
  const float pitch = glm::two_pi<float>() / float(shape.teeth);
  std::vector<float> angles;
  std::vector<glm::vec2> outer;
  const auto arc = [&](float from, float to, float radius) {
    for (std::uint32_t s = 0; s <= arcSegments; ++s) {
      const float angle = from + (to - from) * float(s) / float(arcSegments);
      angles.push_back(angle);
      outer.push_back(radius * glm::vec2(std::cos(angle), std::sin(angle)));
    }
  };
  for (std::uint32_t tooth = 0; tooth < shape.teeth; ++tooth) {
    const float start = pitch * float(tooth);
    arc(start, start + 0.45f * pitch, shape.rootRadius);
    arc(start + 0.6f * pitch, start + 0.85f * pitch, shape.tipRadius);
  }
  std::vector<glm::vec2> hole(angles.size());
  for (std::size_t i = 0; i < angles.size(); ++i)
    hole[i] = shape.holeRadius * glm::vec2(std::cos(angles[i]), std::sin(angles[i]));

  Mesh mesh;
  const std::vector<SweepFrame> frames =
      straightFrames(glm::vec3(0.0f), glm::vec3(0.0f, shape.thickness, 0.0f), glm::vec3(1, 0, 0));
  appendSweep(mesh, flatFacedSection(outer, glm::vec2(0.0f)), frames);
  std::vector<SectionPoint> holeWall;
  for (std::size_t i = 0; i <= hole.size(); ++i) {
    const glm::vec2 p = hole[i % hole.size()];
    holeWall.push_back({p, -glm::normalize(p), float(i) / float(hole.size()), false});
  }
  appendSweep(mesh, holeWall, frames);

  for (std::size_t f = 0; f < frames.size(); ++f) {
    const SweepFrame& frame = frames[f];
    const glm::vec3 facing(0.0f, f == 0 ? -1.0f : 1.0f, 0.0f);
    const auto base = std::uint32_t(mesh.positions.size());
    for (std::size_t i = 0; i < outer.size(); ++i) {
      for (const glm::vec2& p : {hole[i], outer[i]}) {
        mesh.positions.push_back(frame.origin + p.x * frame.axisA + p.y * frame.axisB);
        mesh.normals.push_back(facing);
        mesh.uvs.push_back(p * kUvPerMetre);
      }
    }
    const auto count = std::uint32_t(outer.size());
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t in0 = base + 2 * i, out0 = in0 + 1;
      const std::uint32_t in1 = base + 2 * ((i + 1) % count), out1 = in1 + 1;
      appendFacingTriangle(mesh, in0, out0, out1);
      appendFacingTriangle(mesh, in0, out1, in1);
    }
  }
  return finishPart(std::move(mesh), "gear");
}

Mesh makeLattice(const LatticeShape& shape) {
  const auto corner = [&](std::uint32_t level, std::uint32_t k) {
    const float t = float(level) / float(shape.bays);
    const float half = 0.5f * (shape.baseWidth + (shape.topWidth - shape.baseWidth) * t);
    const float signs[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    return glm::vec3(signs[k][0] * half, shape.height * t, signs[k][1] * half);
  };
  Mesh mesh;
  const auto beam = [&](glm::vec3 from, glm::vec3 to) {
    const glm::vec3 direction = glm::normalize(to - from);
    const glm::vec3 reference = std::abs(direction.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    appendBar(mesh, from, to, glm::vec2(0.5f * shape.beamWidth), glm::normalize(glm::cross(direction, reference)));
  };
  for (std::uint32_t level = 0; level <= shape.bays; ++level) {
    for (std::uint32_t k = 0; k < 4; ++k) {
      const std::uint32_t next = (k + 1) % 4;
      beam(corner(level, k), corner(level, next));
      if (level == shape.bays) continue;
      beam(corner(level, k), corner(level + 1, k));
      beam(corner(level, k), corner(level + 1, next));
      beam(corner(level, next), corner(level + 1, k));
    }
  }
  return finishPart(std::move(mesh), "lattice");
}

}  // namespace pbs
