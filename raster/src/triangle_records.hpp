// The compact per-triangle records that triangle setup writes and the tile rasterizer reads.
#pragma once

#include "pbs/raster/raster_limits.hpp"
#include "scalable_vectors.hpp"

#include <glm/glm.hpp>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pbs::triangles {

// The sizes and the guard band: raster_limits.hpp.
inline constexpr int kSubpixelBits = pbs::kSubpixelBits;
inline constexpr std::int64_t kSubpixelScale = std::int64_t(1) << kSubpixelBits;
inline constexpr int kTileSize = kTriangleTileSize;
inline constexpr int kBlockSize = kTriangleBlockSize;
inline constexpr double kGuardBandPixels = pbs::kGuardBandPixels;

// The least and the greatest of three snapped coordinates, without a branch: a branch here
// mispredicts on about every other triangle, and GCC turns std::min and std::max of the same pair
// (or std::minmax) into one. The differences stay below 2^30 in magnitude (coordinates lie within
// ±2^29, see kGuardBandPixels), so they cannot overflow.
struct CoordinateRange {
  std::int32_t min, max;
};
inline CoordinateRange rangeOf(std::int32_t a, std::int32_t b, std::int32_t c) {
  const auto order = [](std::int32_t& low, std::int32_t& high) {
    const std::int32_t difference = high - low;
    const std::int32_t negative = difference & (difference >> 31);  // the difference where high < low, else 0
    low += negative;
    high -= negative;
  };
  std::int32_t low = a, high = b;
  order(low, high);
  std::int32_t third = c;
  order(low, third);   // low is now the least
  order(third, high);  // high is now the greatest
  return {low, high};
}

// A triangle as coverage and depth need it, and where to find what shades it: 52 bytes.
struct RasterTriangle {
  std::int32_t x[3];                     // snapped window positions in 1/256 pixel, ordered so that twice the signed
  std::int32_t y[3];                     // area is positive (clockwise on the y-down screen)
  std::uint16_t minX, minY, maxX, maxY;  // the pixels whose centres its box holds, within the viewport
  // Window depth at pixel (px, py) is (z0 + zy·dy) + zx·dx with dx = px − minX, dy = py − minY.
  float z0, zx, zy;
  std::uint32_t id;      // packed id: its chunk and its place there, growing with submission order
  std::uint32_t source;  // where its shading record is made from (sourceWord)
};

// An attribute as a plane over pixel offsets dx = px − minX, dy = py − minY from the triangle's
// first pixel: value = (c + y·dy) + x·dx (planeValue). For perspective-correct interpolation
// the planes hold attribute/w, and the value is divided by the plane of 1/w.
template <class Value>
struct AttributePlane {
  Value c, x, y;
};

struct ShadingHeader {
  std::uint32_t span;        // index into TriangleBatch::spans
  std::uint32_t primitive;   // triangle index within its mesh
  std::uint16_t minX, minY;  // the planes' origin pixel
  glm::u8vec4 flatColor;     // the base colour of an untextured triangle
};

// What a pixel's winner needs to fill the channels, packed into one record of floats per
// triangle holding only the parts the framebuffer's channels use: one or two cache lines instead
// of one per attribute array. Offsets count floats; kAbsent marks a part not stored.
struct ShadingLayout {
  static constexpr std::uint32_t kAbsent = 0xffffffffu;
  static constexpr std::uint32_t kHeaderFloats = 4;
  std::uint32_t inverseW = kAbsent;  // AttributePlane<float> where a span has perspective; (1, 0, 0) where w ≡ 1
  std::uint32_t position = kAbsent;  // AttributePlane<glm::vec3>, world − positionOrigin
  std::uint32_t normal = kAbsent;    // AttributePlane<glm::vec3> of vertex normals, then the face normal
  std::uint32_t uv = kAbsent;        // AttributePlane<glm::vec2>
  std::uint32_t stride = kHeaderFloats;
};

// Records are read float by float, straight into registers: copying whole parts through the
// stack stalls on store forwarding in the per-pixel loop. Integers travel bit-cast.
inline void storeHeader(float* record, const ShadingHeader& h) {
  record[0] = std::bit_cast<float>(h.span);
  record[1] = std::bit_cast<float>(h.primitive);
  record[2] = std::bit_cast<float>(std::uint32_t(h.minX) | std::uint32_t(h.minY) << 16);
  record[3] = std::bit_cast<float>(h.flatColor);
}
inline ShadingHeader loadHeader(const float* record) {
  const std::uint32_t origin = std::bit_cast<std::uint32_t>(record[2]);
  return {std::bit_cast<std::uint32_t>(record[0]), std::bit_cast<std::uint32_t>(record[1]),
          std::uint16_t(origin & 0xffffu), std::uint16_t(origin >> 16), std::bit_cast<glm::u8vec4>(record[3])};
}

template <int N>
glm::vec<N, float> loadVector(const float* p) {
  glm::vec<N, float> v;
  for (int i = 0; i < N; ++i) v[i] = p[i];
  return v;
}
template <int N>
void storeVector(float* p, const glm::vec<N, float>& v) {
  for (int i = 0; i < N; ++i) p[i] = v[i];
}

// The value of a stored plane at a pixel, (c + y·dy) + x·dx, component by component in registers.
template <int N>
glm::vec<N, float> planeValue(const float* plane, float dx, float dy) {
  glm::vec<N, float> v;
  for (int i = 0; i < N; ++i) v[i] = (plane[i] + plane[2 * N + i] * dy) + plane[N + i] * dx;
  return v;
}
template <int N>
[[gnu::always_inline]] inline void storePlane(float* p, const AttributePlane<glm::vec<N, float>>& plane) {
  storeVector(p, plane.c);
  storeVector(p + N, plane.x);
  storeVector(p + 2 * N, plane.y);
}

// What one setup task produced, in submission order.
struct TriangleChunk {
  ScalableVector<RasterTriangle> raster;
  // The shading records setup made, of its clipped triangles, each of its span's layout
  // (TriangleBatch::layoutOf); those of the others are made by the tile stage (shading_records.hpp).
  UninitializedVector<float> storedRecords;
  std::uint32_t firstSpan = 0;  // the batch's span of the chunk's first source triangle
};

// Triangles are named by chunk and position within it; the packed id grows with submission order.
inline constexpr int kLocalIdBits = 16;
inline constexpr std::uint32_t kNoTriangle = 0xffffffffu;
inline std::uint32_t packTriangleId(std::uint32_t chunk, std::uint32_t local) {
  return (chunk << kLocalIdBits) | local;
}
inline std::uint32_t idChunk(std::uint32_t id) { return id >> kLocalIdBits; }
inline std::uint32_t idLocal(std::uint32_t id) { return id & ((1u << kLocalIdBits) - 1); }

// RasterTriangle::source: for a triangle whose record setup made (a clipped one) kStoredRecord and the
// offset of that record in its chunk's storedRecords; for any other, the position of its source triangle within its
// chunk's (kChunkTriangles, triangle_batch.hpp: 11 bits), its span as an offset from the chunk's first (at most as many
// as the chunk's source triangles: 11 bits), and kSwappedSource where its raster order swaps the source's vertices 1
// and 2.
inline constexpr std::uint32_t kStoredRecord = 1u << 31, kSwappedSource = 1u << 30;
inline constexpr int kSourcePositionBits = 11;
inline std::uint32_t sourceWord(std::uint32_t position, std::uint32_t spanOffset, bool swapped) {
  return position | spanOffset << kSourcePositionBits | (swapped ? kSwappedSource : 0u);
}
inline std::uint32_t sourcePosition(std::uint32_t source) { return source & ((1u << kSourcePositionBits) - 1); }
inline std::uint32_t sourceSpanOffset(std::uint32_t source) {
  return (source >> kSourcePositionBits) & ((1u << kSourcePositionBits) - 1);
}

}  // namespace pbs::triangles
