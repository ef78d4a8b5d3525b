// Sutherland–Hodgman clipping in homogeneous space (triangles.hpp, step 2, plus the guard band).
#include "homogeneous_clip.hpp"

#include <algorithm>

namespace pbs::triangles {
namespace {

// One plane: keeps vertices with distance ≥ 0 and adds a + t·(b − a), t = da / (da − db), where
// an edge crosses. Returns the new count, or 0 should rounding ever overflow the buffer.
template <class Distance>
int clipAgainst(const ClipVertex* in, int count, ClipVertex* out, Distance distance) {
  int written = 0;
  for (int i = 0; i < count; ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % count];
    const double da = distance(a.clip), db = distance(b.clip);
    if (written + 2 > kMaxClipVertices) return 0;
    if (da >= 0) out[written++] = a;
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      out[written++] = {a.clip + t * (b.clip - a.clip), a.barycentric + t * (b.barycentric - a.barycentric)};
    }
  }
  return written;
}

}  // namespace

int clipTriangle(const ClipVertex (&triangle)[3], double guardX, double guardY,
                 ClipVertex (&polygon)[kMaxClipVertices]) {
  ClipVertex scratch[kMaxClipVertices];
  std::copy(triangle, triangle + 3, polygon);
  int count = 3;
  const auto apply = [&](auto distance) {
    count = clipAgainst(polygon, count, scratch, distance);
    std::copy(scratch, scratch + count, polygon);
  };
  apply([](const glm::dvec4& v) { return v.z + v.w; });
  apply([](const glm::dvec4& v) { return v.w - v.z; });
  apply([&](const glm::dvec4& v) { return guardX * v.w - v.x; });
  apply([&](const glm::dvec4& v) { return guardX * v.w + v.x; });
  apply([&](const glm::dvec4& v) { return guardY * v.w - v.y; });
  apply([&](const glm::dvec4& v) { return guardY * v.w + v.y; });
  return count;
}

}  // namespace pbs::triangles
