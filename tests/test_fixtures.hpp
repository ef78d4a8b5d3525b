// Small builders and readers shared by the raster, ray-casting and capture tests.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/raster/framebuffer.hpp>
#include <pbs/scene/hierarchy.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <set>
#include <utility>
#include <vector>

namespace pbs::test {

// The (x, y) of every pixel something was drawn in.
using PixelSet = std::set<std::pair<int, int>>;

inline PixelSet coveredPixels(const Framebuffer& framebuffer) {
  PixelSet pixels;
  for (std::uint32_t y = 0; y < framebuffer.height; ++y)
    for (std::uint32_t x = 0; x < framebuffer.width; ++x)
      if (framebuffer.covered(std::size_t(y) * framebuffer.width + x)) pixels.emplace(int(x), int(y));
  return pixels;
}

// Orthographic camera whose window x and y are the world's x and y, with depth −z for z in [−1, 0].
// With power-of-two sizes every step is exact, so points and vertices on pixel centres and corners
// test the edge rules exactly. It flips y: counter-clockwise on screen is clockwise in clip space.
inline Camera windowCamera(std::uint32_t width, std::uint32_t height) {
  return orthographicCamera(glm::dmat4(1.0), 0.0, width, height, 0.0, 0.0, 1.0, width, height);
}

// A validated scene of `mesh` drawn by one root per entry of `worlds`, one plain material per part.
inline Scene sceneOf(Mesh mesh, const std::vector<glm::dmat4>& worlds) {
  Scene scene;
  scene.materials.assign(std::max<std::size_t>(1, mesh.parts.size()),
                         Material{"plain", glm::vec4(0.2f, 0.4f, 0.6f, 1.0f), -1});
  scene.meshes.push_back(std::move(mesh));
  for (const glm::dmat4& world : worlds) {
    scene.roots.push_back(std::uint32_t(scene.nodes.size()));
    scene.nodes.push_back(Node{"node", world, {}, 0});
  }
  validateScene(scene, "test scene");
  return scene;
}

}  // namespace pbs::test
