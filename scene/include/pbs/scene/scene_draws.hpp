// Drawing a scene's mesh instances with the rasterizer: the one place that turns the scene model
// into TriangleDraws (used by capture, exact rendering and the comparison with the ray caster).
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/raster/projected_box.hpp"  // outsideClipVolume, which drawing instances tests
#include "pbs/raster/triangles.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/mesh_closure.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

// Scene::materials as the rasterizer sees them, converted once per scene. Texture pointers point
// into Scene::textures, so the Scene must outlive this object.
struct SceneMaterials {
  std::vector<SurfaceMaterial> textured;    // texture bound where the material has one
  std::vector<SurfaceMaterial> untextured;  // the same without textures: for meshes with no uvs

  // A mesh without uvs cannot sample a texture; it shows the base colour factor alone.
  std::span<const SurfaceMaterial> forMesh(const Mesh& mesh) const {
    return mesh.uvs.empty() ? std::span<const SurfaceMaterial>(untextured) : std::span<const SurfaceMaterial>(textured);
  }
};

SceneMaterials makeSceneMaterials(const Scene& scene);

// The tight world box of node `node`'s own mesh (not its subtree), Hierarchy::instanceBounds: known
// without the mesh's vertices for a scene whose meshes are read on demand. Empty for nodes without a mesh.
Bounds instanceWorldBounds(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t node);

// Draws every mesh instance (nodes in index order; PixelIds: node = node index, instance = mesh
// index, primitive = triangle index in the mesh), skipping instances outside the clip volume.
void drawSceneTriangles(const Scene& scene, const Hierarchy& hierarchy, const Camera& camera, Framebuffer& framebuffer,
                        const TriangleOptions& options = {});

// The nodes of `root`'s subtree, parents before children (root first): what a node's capture draws.
std::vector<std::uint32_t> subtreeNodes(const Scene& scene, std::uint32_t root);

// The pixels a hole's box (MeshClosure::holes, in the frame of `clipFromObject`) can project to, a pixel
// wider each way for the window's rounding; the whole window where a corner does not lie in front of the eye.
PixelRect holePixels(const Camera& camera, const glm::dmat4& clipFromObject, const Bounds& hole);

// drawSceneTriangles restricted to the mesh instances of `nodes`, drawn in the given order. With
// `meshClosures` (meshClosure of each mesh, or none), for a camera the caller knows to see every closed mesh
// from outside its box (a capture view): each closed mesh's faces that face inward are left out, but where its
// holes' boxes project (TriangleDraw::otherSidesWithin).
void drawNodeTriangles(const Scene& scene, const Hierarchy& hierarchy, std::span<const std::uint32_t> nodes,
                       const Camera& camera, Framebuffer& framebuffer, const TriangleOptions& options = {},
                       std::span<const MeshClosure> meshClosures = {});

}  // namespace pbs
