// How far two G-buffers of one view agree (the rasterizer's and the ray caster's), and the thresholds
// the rasterizer's visibility is held to: shared by the ray-caster tests and the LOD renderer's.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/raster/framebuffer.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace pbs::test {

// How far two G-buffers of one view agree.
struct Agreement {
  double coverageMismatch = 0.0;  // pixels covered by one renderer only, over all pixels
  double idMatch = 1.0;           // pixels with equal ids, over the pixels both cover
  // On pixels with equal ids: the largest window-depth difference, the share of pixels where it
  // exceeds kDepthTolerance, and the largest difference over what is allowed (see depthAllowance).
  double depthError = 0.0;
  double depthOver = 0.0;
  double depthExcess = 0.0;
  double colorMatch = 1.0;   // pixels with equal ids whose colours differ by ≤ kColorTolerance
  double normalMatch = 1.0;  // pixels with equal ids whose normals differ by less than kNormalTolerance
};

constexpr double kDepthTolerance = 1e-4;   // of the window depth range, i.e. of the view volume's depth
constexpr int kColorTolerance = 2;         // in 8-bit steps: uv interpolation differs in its last bits
constexpr double kNormalTolerance = 0.01;  // length of the difference of unit normals (about 0.6°)

// The depth difference allowed on a pixel of the triangle `ids` names: kDepthTolerance, or more
// where the triangle is so steep in the view that the rasterizer's snap of its vertices to
// 1/256 pixel (up to √2/512 px in window space) alone moves depth by more.
inline double depthAllowance(const Scene& scene, const Hierarchy& hierarchy, const Camera& camera,
                             const PixelIds& ids) {
  const Mesh& mesh = scene.meshes[ids.instance];
  const glm::dmat4 clipFromObject = camera.clipFromWorld() * hierarchy.world[ids.node];
  glm::dvec3 window[3];
  for (int k = 0; k < 3; ++k) {
    const glm::dvec4 clip =
        clipFromObject * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[std::size_t(ids.primitive) * 3 + k]]), 1.0);
    if (clip.w <= 0.0) return kDepthTolerance;  // clipped at the near plane: no simple slope to speak of
    window[k] = windowFromClip(camera, clip);
  }
  const glm::dvec3 normal = glm::cross(window[1] - window[0], window[2] - window[0]);
  const double depthPerPixel = std::hypot(normal.x, normal.y) / std::abs(normal.z);
  return std::max(kDepthTolerance, depthPerPixel * std::sqrt(2.0) / 512.0);
}

inline Agreement compareViews(const Scene& scene, const Hierarchy& hierarchy, const Camera& camera,
                              const Framebuffer& raster, const Framebuffer& rays) {
  std::uint64_t oneOnly = 0, both = 0, sameIds = 0, over = 0, sameColor = 0, sameNormal = 0;
  Agreement result;
  for (std::size_t pixel = 0; pixel < raster.pixelCount(); ++pixel) {
    if (raster.covered(pixel) != rays.covered(pixel)) ++oneOnly;
    if (!raster.covered(pixel) || !rays.covered(pixel)) continue;
    ++both;
    if (raster.ids[pixel] != rays.ids[pixel]) continue;
    ++sameIds;
    const double error = std::abs(double(raster.depth[pixel]) - double(rays.depth[pixel]));
    result.depthError = std::max(result.depthError, error);
    if (error > kDepthTolerance) {
      ++over;
      result.depthExcess =
          std::max(result.depthExcess, error / depthAllowance(scene, hierarchy, camera, raster.ids[pixel]));
    }
    const glm::ivec4 difference = glm::abs(glm::ivec4(raster.color[pixel]) - glm::ivec4(rays.color[pixel]));
    if (std::max({difference.r, difference.g, difference.b, difference.a}) <= kColorTolerance) ++sameColor;
    if (glm::distance(raster.normal[pixel], rays.normal[pixel]) < kNormalTolerance) ++sameNormal;
  }
  result.coverageMismatch = double(oneOnly) / double(raster.pixelCount());
  if (both > 0) result.idMatch = double(sameIds) / double(both);
  if (sameIds > 0) result.depthOver = double(over) / double(sameIds);
  if (sameIds > 0) result.colorMatch = double(sameColor) / double(sameIds);
  if (sameIds > 0) result.normalMatch = double(sameNormal) / double(sameIds);
  return result;
}

// The worst and best of each figure over several views.
struct AgreementRange {
  Agreement worst{0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0};
  Agreement best{1.0, 0.0, 1.0, 1.0, 1e300, 0.0, 0.0};

  void add(const Agreement& a) {
    worst = {std::max(worst.coverageMismatch, a.coverageMismatch),
             std::min(worst.idMatch, a.idMatch),
             std::max(worst.depthError, a.depthError),
             std::max(worst.depthOver, a.depthOver),
             std::max(worst.depthExcess, a.depthExcess),
             std::min(worst.colorMatch, a.colorMatch),
             std::min(worst.normalMatch, a.normalMatch)};
    best = {std::min(best.coverageMismatch, a.coverageMismatch),
            std::max(best.idMatch, a.idMatch),
            std::min(best.depthError, a.depthError),
            std::min(best.depthOver, a.depthOver),
            std::min(best.depthExcess, a.depthExcess),
            std::max(best.colorMatch, a.colorMatch),
            std::max(best.normalMatch, a.normalMatch)};
  }

  void print(const std::string& name) const {
    std::printf(
        "[embree vs raster] %s: coverage differs %.4f–%.4f %% of pixels; ids agree on %.3f–%.3f %%; "
        "depth error max %.1e–%.1e, over 1e-4 on %.4f–%.4f %% (at most %.2f of the snap allowance); "
        "colour agrees on %.2f–%.2f %%, normals on %.2f–%.2f %%\n",
        name.c_str(), 100.0 * best.coverageMismatch, 100.0 * worst.coverageMismatch, 100.0 * worst.idMatch,
        100.0 * best.idMatch, best.depthError, worst.depthError, 100.0 * best.depthOver, 100.0 * worst.depthOver,
        worst.depthExcess, 100.0 * worst.colorMatch, 100.0 * best.colorMatch, 100.0 * worst.normalMatch,
        100.0 * best.normalMatch);
  }

  // The thresholds the rasterizer's visibility is held to.
  void expectWithinThresholds(const std::string& name) const {
    EXPECT_LT(worst.coverageMismatch, 0.005) << name;
    EXPECT_GE(worst.idMatch, 0.99) << name;
    EXPECT_LE(worst.depthExcess, 1.0) << name;  // 1e-4 everywhere but where the snap itself allows more
    EXPECT_GE(worst.colorMatch, 0.99) << name;
    EXPECT_GE(worst.normalMatch, 0.99) << name;
  }
};

}  // namespace pbs::test
