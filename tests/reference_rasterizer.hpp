// A plain, exact reference rasterizer for one triangle at a time, written from the pipeline stated
// in pbs/raster/triangles.hpp and camera.hpp (not from the tile rasterizer), for piglit-style tests.
#pragma once

#include "pbs/raster/camera.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace pbs::test {

// Window positions in 1/256 pixel, as the rasterizer snaps them.
inline constexpr std::int64_t kSubpixel = 256;

struct SnappedPoint {
  std::int64_t x = 0;
  std::int64_t y = 0;
};
using SnappedTriangle = std::array<SnappedPoint, 3>;

// Sutherland–Hodgman against one plane; `distance` ≥ 0 is inside. The new vertex is
// a + t·(b − a) with t = da / (da − db), exactly as triangles.hpp states it.
template <class Distance>
std::vector<glm::dvec4> clipAgainstPlane(const std::vector<glm::dvec4>& polygon, Distance distance) {
  std::vector<glm::dvec4> out;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec4& a = polygon[i];
    const glm::dvec4& b = polygon[(i + 1) % polygon.size()];
    const double da = distance(a), db = distance(b);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      out.push_back(a + t * (b - a));
    }
  }
  return out;
}

// x_w = (x/w + 1)·W/2, y_w = (1 − y/w)·H/2, then X = floor(x_w·256 + 0.5). Coordinates so large
// that the exact edge functions below could overflow are refused rather than wrapped.
inline SnappedPoint snapToWindow(const Camera& camera, const glm::dvec4& clip) {
  const double xw = (clip.x / clip.w + 1.0) * double(camera.width) / 2.0;
  const double yw = (1.0 - clip.y / clip.w) * double(camera.height) / 2.0;
  const double sx = std::floor(xw * double(kSubpixel) + 0.5);
  const double sy = std::floor(yw * double(kSubpixel) + 0.5);
  constexpr double kLimit = 0x1p61;
  if (!(std::abs(sx) < kLimit && std::abs(sy) < kLimit)) {
    std::ostringstream message;
    message << "reference rasterizer: window position (" << xw << ", " << yw << ") out of its exact range";
    throw std::out_of_range(message.str());
  }
  return {std::int64_t(sx), std::int64_t(sy)};
}

// The triangles one input triangle becomes: transformed, clipped to near and far, projected,
// snapped and fanned from the first vertex of the clipped polygon.
inline std::vector<SnappedTriangle> referenceSetup(const Camera& camera, const glm::dmat4& worldFromObject,
                                                   const std::array<glm::vec3, 3>& object) {
  const glm::dmat4 clipFromObject = camera.projection * camera.view * worldFromObject;
  std::vector<glm::dvec4> polygon;
  for (const glm::vec3& p : object) polygon.push_back(clipFromObject * glm::dvec4(glm::dvec3(p), 1.0));
  polygon = clipAgainstPlane(polygon, [](const glm::dvec4& v) { return v.z + v.w; });  // near: z ≥ −w
  polygon = clipAgainstPlane(polygon, [](const glm::dvec4& v) { return v.w - v.z; });  // far: z ≤ w
  std::vector<SnappedTriangle> triangles;
  if (polygon.size() < 3) return triangles;
  std::vector<SnappedPoint> window;
  for (const glm::dvec4& v : polygon) window.push_back(snapToWindow(camera, v));
  for (std::size_t i = 1; i + 1 < window.size(); ++i) triangles.push_back({window[0], window[i], window[i + 1]});
  return triangles;
}

// The edge function of a → b at p in 1/256² pixel². Exact: every |coordinate| < 2^61 (snapToWindow),
// so differences stay below 2^62 and the products below 2^124.
inline __int128 edgeFunction(SnappedPoint a, SnappedPoint b, SnappedPoint p) {
  return __int128(b.x - a.x) * (p.y - a.y) - __int128(b.y - a.y) * (p.x - a.x);
}

// Twice the signed area; positive when the triangle turns clockwise on screen (and so in y-up clip
// space): a back face, unless worldFromObject mirrors.
inline __int128 doubleArea(const SnappedTriangle& t) { return edgeFunction(t[0], t[1], t[2]); }

// Top-left fill rule in the y-down window (row 0 on top). For an edge a → b of a triangle whose
// interior lies where the edge function is positive, a sample exactly on the edge belongs to the
// triangle when the edge is a left edge (interior to its right: y decreases along it) or a top edge
// (horizontal, interior below it at larger y: x increases along it).
inline bool ownsSamplesOnEdge(SnappedPoint a, SnappedPoint b) {
  const std::int64_t dx = b.x - a.x, dy = b.y - a.y;
  return dy < 0 || (dy == 0 && dx > 0);
}

inline std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

// A triangle ready for sample tests: oriented so that its interior is positive on every edge,
// with the fill rule's verdict for samples on each edge. Zero-area triangles are `empty`.
struct EdgeSetup {
  SnappedTriangle t;
  std::array<bool, 3> owns{};
  bool empty = true;
};

inline EdgeSetup edgeSetup(const SnappedTriangle& triangle) {
  EdgeSetup setup{triangle};
  const __int128 area = doubleArea(triangle);
  if (area == 0) return setup;
  if (area < 0) std::swap(setup.t[1], setup.t[2]);
  for (int e = 0; e < 3; ++e) setup.owns[e] = ownsSamplesOnEdge(setup.t[e], setup.t[(e + 1) % 3]);
  setup.empty = false;
  return setup;
}

// Whether the triangle covers the centre of pixel (px, py).
inline bool coversPixel(const EdgeSetup& setup, std::int64_t px, std::int64_t py) {
  if (setup.empty) return false;
  const SnappedPoint sample{px * kSubpixel + kSubpixel / 2, py * kSubpixel + kSubpixel / 2};
  for (int e = 0; e < 3; ++e) {
    const __int128 value = edgeFunction(setup.t[e], setup.t[(e + 1) % 3], sample);
    if (value < 0 || (value == 0 && !setup.owns[e])) return false;
  }
  return true;
}

// Calls visit(pixel index) for every pixel of the width × height viewport whose centre the
// triangle covers, testing every centre of its bounding box.
template <class Visit>
void referenceCover(const SnappedTriangle& triangle, std::uint32_t width, std::uint32_t height, Visit visit) {
  const EdgeSetup setup = edgeSetup(triangle);
  if (setup.empty) return;
  const auto [minX, maxX] = std::minmax({triangle[0].x, triangle[1].x, triangle[2].x});
  const auto [minY, maxY] = std::minmax({triangle[0].y, triangle[1].y, triangle[2].y});
  // One pixel of margin on each side: the edge tests, not the box, decide coverage.
  const std::int64_t x0 = std::max<std::int64_t>(0, floorDiv(minX, kSubpixel) - 1);
  const std::int64_t x1 = std::min<std::int64_t>(std::int64_t(width) - 1, floorDiv(maxX, kSubpixel) + 1);
  const std::int64_t y0 = std::max<std::int64_t>(0, floorDiv(minY, kSubpixel) - 1);
  const std::int64_t y1 = std::min<std::int64_t>(std::int64_t(height) - 1, floorDiv(maxY, kSubpixel) + 1);
  for (std::int64_t py = y0; py <= y1; ++py)
    for (std::int64_t px = x0; px <= x1; ++px)
      if (coversPixel(setup, px, py)) visit(std::size_t(py) * width + std::size_t(px));
}

// Marks (sets to 1) the pixels of `mask` (width × height) that one input triangle covers; with
// `cullBackFaces`, only its pieces that face the camera (counter-clockwise in the object frame).
inline void referenceCoverage(const Camera& camera, const glm::dmat4& worldFromObject,
                              const std::array<glm::vec3, 3>& object, std::vector<std::uint8_t>& mask,
                              bool cullBackFaces = false) {
  const bool mirrored = glm::determinant(glm::dmat3(worldFromObject)) < 0.0;
  for (const SnappedTriangle& t : referenceSetup(camera, worldFromObject, object)) {
    if (cullBackFaces && (doubleArea(t) > 0) != mirrored) continue;
    referenceCover(t, camera.width, camera.height, [&](std::size_t pixel) { mask[pixel] = 1; });
  }
}

}  // namespace pbs::test
