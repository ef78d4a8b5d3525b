// encodeSurfel / decodeSurfel: one surfel in 16 bytes (quantized position, octahedral normal, RGBA8).
#include "pbs/surfels/surfel_file.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pbs {
namespace {

constexpr std::uint64_t kPositionMax = (std::uint64_t(1) << kPositionBits) - 1;
constexpr double kSnormMax = 32767.0;

// One axis of the box in the frame the surfel positions use (origin at the box centre). Working
// relative to the centre keeps every digit of a tiny box far from the origin: lo and hi are exact
// differences of nearby doubles, while centre + rel would round to the absolute coordinate's ulp.
struct Axis {
  double lo = 0.0;      // box.min − centre
  double extent = 0.0;  // box.max − box.min; 0 for an axis that decodes to the centre
};

Axis axisOf(const Bounds& box, int i) {
  const double min = box.min[i];
  const double max = box.max[i];
  const double centre = (min + max) * 0.5;
  const double extent = max - min;
  // Empty, infinite or NaN boxes (never written by pbs) keep every surfel at the centre, finite.
  if (!std::isfinite(centre) || !std::isfinite(extent) || !(extent > 0.0)) return {};
  return {min - centre, extent};
}

std::uint64_t quantize(float rel, const Axis& axis) {
  if (axis.extent == 0.0) return 0;
  double t = std::isnan(rel) ? 0.5 : (double(rel) - axis.lo) / axis.extent;
  t = std::clamp(t, 0.0, 1.0);
  return std::min<std::uint64_t>(std::uint64_t(std::floor(t * double(kPositionMax) + 0.5)), kPositionMax);
}

float dequantize(std::uint64_t q, const Axis& axis) {
  if (axis.extent == 0.0) return 0.0f;
  const double rel = axis.lo + axis.extent * (double(q) / double(kPositionMax));
  constexpr double kFloatMax = std::numeric_limits<float>::max();
  return float(std::clamp(rel, -kFloatMax, kFloatMax));
}

double signNotZero(double v) { return v < 0.0 ? -1.0 : 1.0; }

glm::dvec3 octDecode(double x, double y) {
  glm::dvec3 n(x, y, 1.0 - std::abs(x) - std::abs(y));
  if (n.z < 0.0) {
    const double ox = n.x;
    n.x = (1.0 - std::abs(n.y)) * signNotZero(ox);
    n.y = (1.0 - std::abs(ox)) * signNotZero(n.y);
  }
  // On the octahedron |x| + |y| + |z| = 1, so the length is at least 1/√3: never a division by zero.
  return n / std::sqrt(glm::dot(n, n));
}

double snormValue(std::int16_t s) { return std::max(double(s) / kSnormMax, -1.0); }

// The octahedral snorm pair of a normal: of the four grid points around the exact mapping, the one
// whose decoded normal is closest (Cigolle et al. 2014, "precise" variant), which halves the error of
// plain rounding.
std::array<std::int16_t, 2> octEncode(const glm::vec3& normal) {
  glm::dvec3 n(normal);
  const double scale = std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
  if (!std::isfinite(scale) || !(scale > 0.0)) return {0, 0};  // +Z
  n /= scale;                                                  // before squaring, so tiny normals do not underflow
  n /= std::sqrt(glm::dot(n, n));

  double x = n.x / (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
  double y = n.y / (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
  if (n.z < 0.0) {
    const double ox = x;
    x = (1.0 - std::abs(y)) * signNotZero(ox);
    y = (1.0 - std::abs(ox)) * signNotZero(y);
  }
  const double fx = std::floor(std::clamp(x, -1.0, 1.0) * kSnormMax);
  const double fy = std::floor(std::clamp(y, -1.0, 1.0) * kSnormMax);
  std::array<std::int16_t, 2> best{0, 0};
  double bestDot = -2.0;
  for (int dx = 0; dx <= 1; ++dx) {
    for (int dy = 0; dy <= 1; ++dy) {
      const auto sx = std::int16_t(std::clamp(fx + dx, -kSnormMax, kSnormMax));
      const auto sy = std::int16_t(std::clamp(fy + dy, -kSnormMax, kSnormMax));
      const double d = glm::dot(octDecode(snormValue(sx), snormValue(sy)), n);
      if (d > bestDot) {
        bestDot = d;
        best = {sx, sy};
      }
    }
  }
  return best;
}

}  // namespace

const char* colorEncodingName(SurfelColorEncoding encoding) {
  switch (encoding) {
    case SurfelColorEncoding::Rgba: return "rgba";
    case SurfelColorEncoding::Rgb: return "rgb";
    case SurfelColorEncoding::Constant: return "constant";
  }
  return "unknown";
}

PackedSurfel encodeSurfel(const Surfel& surfel, const Bounds& box) {
  std::uint64_t position = 0;
  for (int i = 0; i < 3; ++i) position |= quantize(surfel.position[i], axisOf(box, i)) << (kPositionBits * i);
  const auto oct = octEncode(surfel.normal);

  PackedSurfel packed{};
  for (int i = 0; i < 8; ++i) packed[i] = std::uint8_t(position >> (8 * i));
  for (int c = 0; c < 2; ++c) {
    const auto bits = static_cast<std::uint16_t>(oct[c]);
    packed[8 + 2 * c] = std::uint8_t(bits);
    packed[9 + 2 * c] = std::uint8_t(bits >> 8);
  }
  for (int i = 0; i < 4; ++i) packed[12 + i] = surfel.color[i];
  return packed;
}

Surfel decodeSurfel(const PackedSurfel& packed, const Bounds& box) {
  std::uint64_t position = 0;
  for (int i = 7; i >= 0; --i) position = (position << 8) | packed[i];
  std::int16_t oct[2];
  for (int c = 0; c < 2; ++c)
    oct[c] = static_cast<std::int16_t>(std::uint16_t(packed[8 + 2 * c] | (packed[9 + 2 * c] << 8)));

  Surfel surfel;
  for (int i = 0; i < 3; ++i) {
    surfel.position[i] = dequantize((position >> (kPositionBits * i)) & kPositionMax, axisOf(box, i));
  }
  surfel.normal = glm::vec3(octDecode(snormValue(oct[0]), snormValue(oct[1])));
  for (int i = 0; i < 4; ++i) surfel.color[i] = packed[12 + i];
  return surfel;
}

}  // namespace pbs
