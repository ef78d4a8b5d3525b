// Ray-hit shading for the Embree caster: interpolates the hit triangle's attributes exactly as the
// rasterizer's channels define them.
#include "embree_shading.hpp"

#include <algorithm>
#include <cmath>

namespace pbs {
namespace {

// The part holding `triangle`: parts cover the indices in order, so the last one starting at or
// before it.
const MeshPart& partOf(const Mesh& mesh, std::uint32_t triangle) {
  const auto after =
      std::upper_bound(mesh.parts.begin(), mesh.parts.end(), std::uint64_t(triangle) * 3,
                       [](std::uint64_t index, const MeshPart& part) { return index < part.firstIndex; });
  return *(after - 1);
}

// d(uv)/dx and d(uv)/dy at the hit in window pixels, times the camera's sample spacing: the footprint the
// rasterizer reads from its planes (tile_resolve.cpp), here from the triangle's homogeneous window
// coordinates h_k = (x·w, y·w, w). A window point s = (x, y, 1) sees the triangle at barycentrics
// g / Σg with g = M⁻¹ s, M the matrix of columns h_k; M⁻¹'s rows are h_1 × h_2, h_2 × h_0 and h_0 × h_1
// over det M, which cancels in every ratio below, so no division by det M or by a vertex's w (a triangle
// reaching behind the eye has its derivatives too). uv = UV·g / Σg, and its derivative along x is
// (UV·g_x − uv · Σg_x) / Σg with g_x = M⁻¹ (1, 0, 0). The ray went through the pixel's centre, s.
TextureFootprint hitFootprint(const ShadingView& view, const glm::dmat4& windowFromObject, const Mesh& mesh,
                              const std::uint32_t (&index)[3], const glm::dvec2& s, const glm::vec2& uv) {
  glm::dvec3 h[3];
  for (int k = 0; k < 3; ++k) {
    const glm::dvec4 window = windowFromObject * glm::dvec4(glm::dvec3(mesh.positions[index[k]]), 1.0);
    h[k] = glm::dvec3(window.x, window.y, window.w);
  }
  const glm::dvec3 rows[3] = {glm::cross(h[1], h[2]), glm::cross(h[2], h[0]), glm::cross(h[0], h[1])};
  double sum = 0.0, sumX = 0.0, sumY = 0.0;
  glm::dvec2 uvX(0.0), uvY(0.0);
  for (int k = 0; k < 3; ++k) {
    sum += rows[k].x * s.x + rows[k].y * s.y + rows[k].z;
    sumX += rows[k].x;
    sumY += rows[k].y;
    const glm::dvec2 vertexUv(mesh.uvs[index[k]]);
    uvX += rows[k].x * vertexUv;
    uvY += rows[k].y * vertexUv;
  }
  const double scale = view.camera->sampleSpacing / sum;
  return {glm::vec2((uvX - glm::dvec2(uv) * sumX) * scale), glm::vec2((uvY - glm::dvec2(uv) * sumY) * scale),
          view.camera->textureProbes};
}

}  // namespace

void shadeHit(const ShadingView& view, const ShadedInstance& instance, InstanceMatrices& matrices,
              std::uint32_t triangle, float u, float v, Framebuffer& framebuffer, std::size_t pixel) {
  const Mesh& mesh = *instance.mesh;
  const std::uint32_t i0 = mesh.indices[std::size_t(triangle) * 3 + 0];
  const std::uint32_t i1 = mesh.indices[std::size_t(triangle) * 3 + 1];
  const std::uint32_t i2 = mesh.indices[std::size_t(triangle) * 3 + 2];
  const double b1 = u;
  const double b2 = v;
  const double b0 = 1.0 - b1 - b2;

  // The hit point from the barycentrics on the double-precision triangle rather than from the ray's
  // float t: it lies on the triangle's plane, as the rasterizer's interpolated depth does.
  const glm::dvec3 object =
      b0 * glm::dvec3(mesh.positions[i0]) + b1 * glm::dvec3(mesh.positions[i1]) + b2 * glm::dvec3(mesh.positions[i2]);
  const glm::dvec3 world = glm::dvec3(*instance.worldFromObject * glm::dvec4(object, 1.0));
  const double depth = windowFromClip(*view.camera, view.clipFromWorld * glm::dvec4(world, 1.0)).z;
  // The near/far interval of the ray already bounds the hit; rounding may still step just outside.
  framebuffer.depth[pixel] = float(std::clamp(depth, 0.0, 1.0));

  if (framebuffer.has(kChannelColor)) {
    const SurfaceMaterial& material = instance.materials[partOf(mesh, triangle).material];
    glm::vec4 color = material.baseColor;
    if (material.texture && isSampleable(*material.texture)) {
      const glm::vec2 uv = float(b0) * mesh.uvs[i0] + float(b1) * mesh.uvs[i1] + float(b2) * mesh.uvs[i2];
      const glm::dvec2 centre(double(pixel % framebuffer.width) + 0.5, double(pixel / framebuffer.width) + 0.5);
      color *= sampleTexture(*material.texture, uv,
                             hitFootprint(view, matrices.windowFromObject(instance), mesh, {i0, i1, i2}, centre, uv));
    }
    framebuffer.color[pixel] = toUnorm8(color);
  }
  if (framebuffer.has(kChannelPosition)) framebuffer.position[pixel] = glm::vec3(world - framebuffer.positionOrigin);
  if (framebuffer.has(kChannelNormal)) {
    const glm::dmat3& normalFromObject = matrices.normalFromObject(instance);
    // As the rasterizer does it: each vertex normal to world space and unit length, then interpolated.
    const auto worldNormal = [&](std::uint32_t index) {
      const glm::dvec3 n = normalFromObject * glm::dvec3(mesh.normals[index]);
      const double length = glm::length(n);
      return length > 0.0 && std::isfinite(length) ? n / length : glm::dvec3(0.0);
    };
    glm::dvec3 normal = b0 * worldNormal(i0) + b1 * worldNormal(i1) + b2 * worldNormal(i2);
    // Opposite vertex normals can cancel; the face's own normal is then the only direction there is.
    if (!(glm::dot(normal, normal) > 1e-24)) {
      const glm::dvec3 p0(mesh.positions[i0]);
      normal = normalFromObject * glm::cross(glm::dvec3(mesh.positions[i1]) - p0, glm::dvec3(mesh.positions[i2]) - p0);
    }
    framebuffer.normal[pixel] = glm::vec3(glm::normalize(normal));
  }
  if (framebuffer.has(kChannelIds)) framebuffer.ids[pixel] = PixelIds{instance.node, instance.meshIndex, triangle};
}

void clearMissedPixels(Framebuffer& framebuffer, std::size_t first, std::size_t count) {
  std::fill_n(framebuffer.depth.begin() + std::ptrdiff_t(first), count, kClearDepth);
  if (framebuffer.has(kChannelIds)) std::fill_n(framebuffer.ids.begin() + std::ptrdiff_t(first), count, PixelIds{});
}

}  // namespace pbs
