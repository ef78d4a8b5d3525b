// Sections swept through frames, caps and facing triangles: the shared core of the procedural parts.
#include "procedural_sweep.hpp"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pbs {
namespace {

struct PathSample {
  glm::vec3 point;
  glm::vec3 tangent;
};

void pushSample(std::vector<PathSample>& samples, glm::vec3 point, glm::vec3 tangent) {
  // Two corners trimmed to the same point would give a ring of zero-area triangles.
  if (!samples.empty() && glm::distance(samples.back().point, point) < 1e-6f) {
    samples.back().tangent = tangent;
    return;
  }
  samples.push_back({point, tangent});
}

glm::vec3 anyPerpendicular(glm::vec3 v) {
  const glm::vec3 a = std::abs(v.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  return glm::normalize(glm::cross(v, a));
}

// The polyline's points with its corners replaced by circular arcs.
std::vector<PathSample> roundCorners(std::span<const glm::vec3> polyline, float bendRadius,
                                     std::uint32_t bendSegments) {
  std::vector<glm::vec3> points;
  for (const glm::vec3& p : polyline)
    if (points.empty() || glm::distance(points.back(), p) > 1e-6f) points.push_back(p);
  if (points.size() < 2) throw std::invalid_argument("pathFrames: the polyline needs two distinct points");

  std::vector<PathSample> samples;
  pushSample(samples, points.front(), glm::normalize(points[1] - points[0]));
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    const glm::vec3 before = points[i] - points[i - 1], after = points[i + 1] - points[i];
    const glm::vec3 in = glm::normalize(before), out = glm::normalize(after);
    const float angle = std::acos(std::clamp(glm::dot(in, out), -1.0f, 1.0f));
    if (angle < 1e-4f) continue;
    // Each segment gives at most half its length to each of its two corners.
    const float trim =
        std::min(bendRadius * std::tan(angle * 0.5f), 0.5f * std::min(glm::length(before), glm::length(after)));
    const float radius = trim / std::tan(angle * 0.5f);
    const glm::vec3 start = points[i] - in * trim;
    glm::vec3 inward = out - in * glm::dot(in, out);
    inward = glm::length(inward) > 1e-6f ? glm::normalize(inward) : anyPerpendicular(in);  // a U-turn: any side
    const glm::vec3 centre = start + inward * radius;
    for (std::uint32_t s = 0; s <= bendSegments; ++s) {
      const float phi = angle * float(s) / float(bendSegments);
      pushSample(samples, centre + radius * (std::sin(phi) * in - std::cos(phi) * inward),
                 std::cos(phi) * in + std::sin(phi) * inward);
    }
  }
  pushSample(samples, points.back(), glm::normalize(points.back() - points[points.size() - 2]));
  return samples;
}

// One reflection of `v` in the plane normal to `axis` (identity when axis is zero).
glm::vec3 reflect(glm::vec3 v, glm::vec3 axis) {
  const float axisLength2 = glm::dot(axis, axis);
  return axisLength2 > 0.0f ? v - (2.0f / axisLength2) * glm::dot(axis, v) * axis : v;
}

}  // namespace

std::vector<SectionPoint> circleSection(float radius, std::uint32_t segments, glm::vec2 centre) {
  std::vector<SectionPoint> section(segments + 1);
  for (std::uint32_t i = 0; i <= segments; ++i) {
    const float angle = glm::two_pi<float>() * float(i % segments) / float(segments);
    const glm::vec2 direction(std::cos(angle), std::sin(angle));
    section[i] = {centre + radius * direction, direction, float(i) / float(segments), false};
  }
  return section;
}

std::vector<SweepFrame> revolveFrames(std::uint32_t segments, float uRepeat) {
  std::vector<SweepFrame> frames(segments + 1);
  for (std::uint32_t i = 0; i <= segments; ++i) {
    // i % segments makes the seam frame bit-identical to the first, so the surface closes exactly.
    const float angle = glm::two_pi<float>() * float(i % segments) / float(segments);
    frames[i] = {glm::vec3(0.0f), glm::vec3(std::cos(angle), 0.0f, -std::sin(angle)), glm::vec3(0, 1, 0),
                 uRepeat * float(i) / float(segments)};
  }
  return frames;
}

std::vector<SweepFrame> pathFrames(std::span<const glm::vec3> polyline, float bendRadius, std::uint32_t bendSegments,
                                   float uLength) {
  const std::vector<PathSample> samples = roundCorners(polyline, bendRadius, std::max(bendSegments, 1u));
  std::vector<SweepFrame> frames(samples.size());
  // Rotation-minimising frames by double reflection (Wang et al. 2008): no twist along the pipe.
  glm::vec3 normal = anyPerpendicular(samples[0].tangent);
  float run = 0.0f;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (i > 0) {
      const glm::vec3 step = samples[i].point - samples[i - 1].point;
      const glm::vec3 reflectedNormal = reflect(normal, step);
      const glm::vec3 reflectedTangent = reflect(samples[i - 1].tangent, step);
      normal = glm::normalize(reflect(reflectedNormal, samples[i].tangent - reflectedTangent));
      run += glm::length(step);
    }
    const glm::vec3 tangent = samples[i].tangent;
    normal = glm::normalize(normal - glm::dot(normal, tangent) * tangent);  // keep rounding from drifting
    frames[i] = {samples[i].point, normal, glm::cross(tangent, normal), run / uLength};
  }
  return frames;
}

void appendSweep(Mesh& mesh, std::span<const SectionPoint> section, std::span<const SweepFrame> frames) {
  const auto base = std::uint32_t(mesh.positions.size());
  const auto width = std::uint32_t(section.size());
  for (const SweepFrame& frame : frames) {
    for (const SectionPoint& point : section) {
      mesh.positions.push_back(frame.origin + point.position.x * frame.axisA + point.position.y * frame.axisB);
      mesh.normals.push_back(glm::normalize(point.normal.x * frame.axisA + point.normal.y * frame.axisB));
      mesh.uvs.emplace_back(frame.u, point.v);
    }
  }
  for (std::uint32_t f = 0; f + 1 < frames.size(); ++f) {
    for (std::uint32_t s = 0; s + 1 < width; ++s) {
      if (section[s + 1].hardEdgeBefore) continue;
      const std::uint32_t a = base + f * width + s, b = a + 1, c = a + width, d = c + 1;
      appendFacingTriangle(mesh, a, b, d);
      appendFacingTriangle(mesh, a, d, c);
    }
  }
}

void appendCap(Mesh& mesh, std::span<const SectionPoint> section, const SweepFrame& frame, glm::vec3 outward,
               float uvPerUnit) {
  const auto centre = std::uint32_t(mesh.positions.size());
  mesh.positions.push_back(frame.origin);
  mesh.normals.push_back(outward);
  mesh.uvs.emplace_back(0.0f, 0.0f);
  glm::vec2 previous(std::numeric_limits<float>::quiet_NaN());
  for (const SectionPoint& point : section) {
    if (point.position == previous) continue;  // hard edges repeat a corner; the fan needs it once
    previous = point.position;
    mesh.positions.push_back(frame.origin + point.position.x * frame.axisA + point.position.y * frame.axisB);
    mesh.normals.push_back(outward);
    mesh.uvs.push_back(point.position * uvPerUnit);
  }
  for (auto v = centre + 1; v + 1 < std::uint32_t(mesh.positions.size()); ++v)
    appendFacingTriangle(mesh, centre, v, v + 1);
}

void appendCappedSweep(Mesh& mesh, std::span<const SectionPoint> section, std::span<const SweepFrame> frames,
                       float uvPerUnit) {
  appendSweep(mesh, section, frames);
  // A cap lies in its end frame's plane, facing away from the next frame inward.
  const auto facingAway = [](const SweepFrame& end, const SweepFrame& inner) {
    const glm::vec3 normal = glm::normalize(glm::cross(end.axisA, end.axisB));
    return glm::dot(normal, end.origin - inner.origin) >= 0.0f ? normal : -normal;
  };
  appendCap(mesh, section, frames.front(), facingAway(frames.front(), frames[1]), uvPerUnit);
  appendCap(mesh, section, frames.back(), facingAway(frames.back(), frames[frames.size() - 2]), uvPerUnit);
}

void appendFacingTriangle(Mesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  const glm::vec3& pa = mesh.positions[a];
  const glm::vec3 face = glm::cross(mesh.positions[b] - pa, mesh.positions[c] - pa);
  if (face == glm::vec3(0.0f)) return;
  const glm::vec3 normalSum = mesh.normals[a] + mesh.normals[b] + mesh.normals[c];
  if (glm::dot(face, normalSum) < 0.0f) std::swap(b, c);
  mesh.indices.insert(mesh.indices.end(), {a, b, c});
}

Mesh finishPart(Mesh mesh, const char* name) {
  mesh.name = name;
  mesh.parts = {MeshPart{0, std::uint32_t(mesh.indices.size()), 0}};
  updateMeshBounds(mesh);
  return mesh;
}

}  // namespace pbs
