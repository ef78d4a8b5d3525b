// The colour spaces FLIP moves through: sRGB, linear RGB, CIE XYZ, the YCxCz opponent space and
// Hunt-adjusted CIELAB, all relative to the D65 white of linear RGB (1, 1, 1).
#pragma once

#include "flip_branchless.hpp"
#include "pbs/raster/simd_clones.hpp"

#include <glm/glm.hpp>

#include <array>
#include <cmath>

namespace pbs::flip {

using Matrix3 = std::array<std::array<double, 3>, 3>;  // [row][column]

namespace color_space_detail {

constexpr double determinant(const Matrix3& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

constexpr Matrix3 inverse(const Matrix3& m) {
  const double d = determinant(m);
  Matrix3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      // Cofactor of m[j][i] (the adjugate is the transposed cofactor matrix).
      const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
      r[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / d;
    }
  return r;
}

// Linear sRGB to XYZ from the IEC 61966-2-1 primaries and D65 white point (x, y chromaticities),
// scaled so that white has Y = 1.
constexpr Matrix3 srgbToXyz() {
  constexpr double primaries[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
  constexpr double whiteX = 0.3127, whiteY = 0.3290;
  Matrix3 columns{};
  for (int c = 0; c < 3; ++c) {
    const double x = primaries[c][0], y = primaries[c][1];
    columns[0][c] = x / y;
    columns[1][c] = 1.0;
    columns[2][c] = (1.0 - x - y) / y;
  }
  const Matrix3 toPrimaries = inverse(columns);
  const double white[3] = {whiteX / whiteY, 1.0, (1.0 - whiteX - whiteY) / whiteY};
  Matrix3 m{};
  for (int c = 0; c < 3; ++c) {
    double scale = 0.0;
    for (int k = 0; k < 3; ++k) scale += toPrimaries[c][k] * white[k];
    for (int r = 0; r < 3; ++r) m[r][c] = columns[r][c] * scale;
  }
  return m;
}

}  // namespace color_space_detail

// Linear sRGB to XYZ relative to the white (XYZ / XYZ of linear white (1, 1, 1)), the form YCxCz and
// CIELAB take: the white's scale is folded into the matrix once instead of divided out per pixel.
constexpr Matrix3 linearRgbToRelativeXyz() {
  const Matrix3 m = color_space_detail::srgbToXyz();
  Matrix3 relative = m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) relative[r][c] = m[r][c] / (m[r][0] + m[r][1] + m[r][2]);
  return relative;
}

inline constexpr Matrix3 kLinearRgbToRelativeXyz = linearRgbToRelativeXyz();
inline constexpr Matrix3 kRelativeXyzToLinearRgb = color_space_detail::inverse(kLinearRgbToRelativeXyz);

// Written out by component: glm's operator[] is a switch, which would keep the loops that call this
// from vectorising.
PBS_CLONE_INLINE glm::vec3 multiply(const Matrix3& m, const glm::vec3& v) {
  const auto row = [&](int i) { return float(m[i][0]) * v.x + float(m[i][1]) * v.y + float(m[i][2]) * v.z; };
  return {row(0), row(1), row(2)};
}

// IEC 61966-2-1 decoding of one channel, for values in [0, 1].
PBS_CLONE_INLINE float srgbToLinear(float c) {
  const float curve = powTwelveFifths((c + 0.055f) * (1.0f / 1.055f));
  const float line = c * (1.0f / 12.92f);
  return selectFloat(c <= 0.04045f, line, curve);
}

// (Y', Cx, Cz) of white-relative XYZ: Y' = 116·Y − 16, Cx = 500·(X − Y), Cz = 200·(Y − Z).
PBS_CLONE_INLINE glm::vec3 relativeXyzToYcxcz(const glm::vec3& xyz) {
  return {116.0f * xyz.y - 16.0f, 500.0f * (xyz.x - xyz.y), 200.0f * (xyz.y - xyz.z)};
}

PBS_CLONE_INLINE glm::vec3 ycxczToRelativeXyz(const glm::vec3& ycxcz) {
  const float y = (ycxcz.x + 16.0f) * (1.0f / 116.0f);
  return {y + ycxcz.y * (1.0f / 500.0f), y, y - ycxcz.z * (1.0f / 200.0f)};
}

// CIELAB's companding of a white-relative coordinate: a cube root, linear near black.
PBS_CLONE_INLINE float labCompand(float t) {
  constexpr float delta = 6.0f / 29.0f;
  const float root = cubeRoot(t);
  const float line = t * (1.0f / (3.0f * delta * delta)) + 4.0f / 29.0f;
  return selectFloat(t > delta * delta * delta, root, line);
}

// CIELAB of white-relative XYZ with the Hunt adjustment FLIP applies (a and b scaled by 0.01·L:
// colour differences are less visible in the dark).
PBS_CLONE_INLINE glm::vec3 relativeXyzToHuntLab(const glm::vec3& xyz) {
  const float fx = labCompand(xyz.x), fy = labCompand(xyz.y), fz = labCompand(xyz.z);
  const float lightness = 116.0f * fy - 16.0f;
  return {lightness, 0.01f * lightness * 500.0f * (fx - fy), 0.01f * lightness * 200.0f * (fy - fz)};
}

// HyAB: city-block in lightness, Euclidean in the chromatic plane.
PBS_CLONE_INLINE float hyab(const glm::vec3& p, const glm::vec3& q) {
  const float da = p.y - q.y, db = p.z - q.z;
  return std::abs(p.x - q.x) + sqrtNonNegative(da * da + db * db);
}

}  // namespace pbs::flip
