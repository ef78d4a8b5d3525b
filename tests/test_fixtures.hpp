// Small builders and readers shared by the raster, ray-casting and capture tests.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/raster/framebuffer.hpp>
#include <pbs/raster/texture.hpp>
#include <pbs/scene/hierarchy.hpp>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
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

// A unit quad in the z = 0 plane, [−1, 1]², two triangles split along y = x, facing +Z, uvs over [0, 1]².
inline Mesh quadMesh() {
  Mesh mesh;
  mesh.name = "quad";
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.normals.assign(4, glm::vec3(0, 0, 1));
  mesh.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  mesh.parts = {MeshPart{0, 6, 0}};
  updateMeshBounds(mesh);
  return mesh;
}

// The quad textured with a checkerboard of 128 × 128 one-texel squares, black and white, mip-mapped trilinearly;
// slantedCheckerCamera sees it at a slant, in perspective: from about one texel a pixel at the near (lower) edge
// to many at the far (upper) half, where filtering shows grey and level 0 alone black or white.
inline Scene slantedChecker() {
  constexpr std::uint32_t kTexels = 128;
  Texture checker{"checker", kTexels, kTexels, std::vector<std::uint8_t>(kTexels * kTexels * 4, 255)};
  for (std::uint32_t texel = 0; texel < kTexels * kTexels; ++texel)
    if ((texel % kTexels + texel / kTexels) % 2 == 0) std::fill_n(checker.rgba8.begin() + texel * 4, 3, 0);
  checker.mipmap = TextureMipmap::Linear;
  buildMipLevels(checker);
  Scene scene = sceneOf(quadMesh(), {glm::dmat4(1.0)});
  scene.textures.push_back(checker);
  scene.materials[0] = Material{"checker", glm::vec4(1.0f), 0};
  return scene;
}

inline Camera slantedCheckerCamera(std::uint32_t size) {
  return perspectiveCamera(glm::lookAt(glm::dvec3(0, -1.6, 1.3), glm::dvec3(0, 0.1, 0), glm::dvec3(0, 1, 0)), 0.9, 0.1,
                           20, size, size);
}

// An open sheet of 2 · n² triangles over [−1, 1]² with z = height(x, y), one part, no uvs.
template <class Height>
Mesh gridSheet(std::uint32_t n, Height&& height) {
  Mesh mesh;
  for (std::uint32_t j = 0; j <= n; ++j)
    for (std::uint32_t i = 0; i <= n; ++i) {
      const float x = -1.0f + 2.0f * float(i) / float(n), y = -1.0f + 2.0f * float(j) / float(n);
      mesh.positions.emplace_back(x, y, height(x, y));
    }
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
  mesh.parts.push_back(MeshPart{0, std::uint32_t(mesh.indices.size()), 0});
  updateMeshBounds(mesh);
  return mesh;
}

// A closed, finely tessellated box of 12 · n² triangles with one plain material.
inline Mesh tessellatedBox(std::uint32_t n) {
  Mesh mesh;
  mesh.name = "box";
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2) {
      const std::uint32_t base = std::uint32_t(mesh.positions.size());
      for (std::uint32_t j = 0; j <= n; ++j)
        for (std::uint32_t i = 0; i <= n; ++i) {
          glm::vec3 p;
          p[axis] = float(side);
          p[(axis + 1) % 3] = -1.0f + 2.0f * float(i) / float(n);
          p[(axis + 2) % 3] = -1.0f + 2.0f * float(j) / float(n);
          mesh.positions.push_back(p);
        }
      for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i) {
          const std::uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
          mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    }
  mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
  mesh.parts.push_back(MeshPart{0, std::uint32_t(mesh.indices.size()), 0});
  updateMeshBounds(mesh);
  return mesh;
}

inline glm::dmat4 placed(glm::dvec3 at, double angle, glm::dvec3 scale) {
  return glm::scale(glm::rotate(glm::translate(glm::dmat4(1.0), at), angle, glm::dvec3(0.3, 1.0, 0.2)), scale);
}

// The parts cover the indices in order, whole triangles each.
inline void expectPartsCoverIndices(const Mesh& mesh) {
  std::uint32_t next = 0;
  for (const MeshPart& part : mesh.parts) {
    EXPECT_EQ(part.firstIndex, next);
    EXPECT_EQ(part.indexCount % 3, 0u);
    next += part.indexCount;
  }
  EXPECT_EQ(next, mesh.indices.size());
}

// root → {group A, group B}; each group holds two instances of the box mesh (1,200 triangles each),
// the groups' children placed identically, so A and B are the same subtree placed differently.
inline Scene twoIdenticalGroups() {
  Scene scene;
  scene.materials.push_back(Material{"plain", glm::vec4(0.8f, 0.5f, 0.2f, 1.0f), -1});
  scene.meshes.push_back(tessellatedBox(10));
  scene.nodes.push_back(Node{"root", glm::dmat4(1.0), {1, 2}, -1});
  scene.nodes.push_back(Node{"A", placed({-5, 0, 0}, 0.3, glm::dvec3(1.0)), {3, 4}, -1});
  scene.nodes.push_back(Node{"B", placed({6, 1, 2}, 1.1, glm::dvec3(2.0)), {5, 6}, -1});
  for (int group = 0; group < 2; ++group) {
    scene.nodes.push_back(Node{"left", placed({-1.5, 0, 0}, 0.5, {1, 1, 1}), {}, 0});
    scene.nodes.push_back(Node{"right", placed({1.5, 0.5, 0}, -0.7, {1, 2, 0.5}), {}, 0});
  }
  scene.roots = {0};
  validateScene(scene, "two groups");
  return scene;
}

// twoIdenticalGroups with four different meshes over its four instances.
inline Scene groupsOfFourMeshes() {
  Scene scene = twoIdenticalGroups();
  scene.meshes.push_back(tessellatedBox(6));
  scene.meshes.push_back(tessellatedBox(14));
  scene.meshes.push_back(tessellatedBox(3));
  for (std::size_t n = 0, next = 0; n < scene.nodes.size(); ++n)
    if (scene.nodes[n].mesh >= 0) scene.nodes[n].mesh = std::int32_t(next++ % scene.meshes.size());
  validateScene(scene, "four meshes");
  return scene;
}

// groupsOfFourMeshes with the transforms that take each whole-scene computation down its slow roads: group
// B scaled unevenly (an inner node placed by a non-similarity), and a third group C, unevenly scaled too,
// holding a mesh with a mesh of its own (an inner instance) and a nested group D with a mirrored instance,
// so meshes are shared between subtrees of different frames.
inline Scene layeredScene() {
  Scene scene = groupsOfFourMeshes();
  scene.nodes[2].local = placed({6, 1, 2}, 1.1, {2.0, 1.0, 0.5});
  const std::uint32_t c = std::uint32_t(scene.nodes.size());
  scene.nodes.push_back(Node{"C", placed({0, 4, 0}, 0.4, {1, 1, 3}), {c + 1, c + 2}, 3});
  scene.nodes.push_back(Node{"C leaf", placed({1, 0, 1}, -0.2, {1, 1, 1}), {}, 1});
  scene.nodes.push_back(Node{"D", placed({-2, 0, 0}, 0.9, {1.5, 1.5, 1.5}), {c + 3, c + 4}, -1});
  scene.nodes.push_back(Node{"D leaf", placed({0, 1, 0}, 0.3, {1, 1, 1}), {}, 0});
  scene.nodes.push_back(Node{"D mirrored", placed({0, -1, 0}, 0.3, {-1, 1, 1}), {}, 2});
  scene.nodes[0].children.push_back(c);
  validateScene(scene, "layered");
  return scene;
}

}  // namespace pbs::test
