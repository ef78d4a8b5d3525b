// Resolves a command line's SCENE argument (a glTF file or `default`) into a validated scene.
#include "pbs/scene/load_scene.hpp"

#include "pbs/scene/generate.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/input_error.hpp"
#include "pbs/scene/loose_octree.hpp"

namespace pbs {

namespace {

// Validates, and refuses a scene with nothing to draw: every later step (capture, surfels, images) would be
// empty. (After validation every node is reachable, so summing over all nodes counts every instance.)
void requireDrawable(const Scene& scene, const std::string& spec) {
  validateScene(scene, spec);
  std::uint64_t triangles = 0;
  for (const Node& node : scene.nodes)
    if (node.mesh >= 0) triangles += scene.meshes[std::size_t(node.mesh)].triangleCount();
  if (triangles == 0) throw InputError(spec, "scene", "nothing to draw (no triangles)");
}

}  // namespace

ImportResult loadScene(const std::string& spec, const LoadOptions& options) {
  ImportResult result;
  if (spec == "default") {
    result.scene = generateDefaultScene();
  } else {
    result = importGltf(spec);
  }
  requireDrawable(result.scene, spec);
  if (options.octreeLeafTriangles > 0) result.scene = asLooseOctree(result.scene, options.octreeLeafTriangles, spec);
  return result;
}

Scene asLooseOctree(const Scene& scene, std::uint32_t leafTriangles, const std::string& source) {
  Scene octree = buildLooseOctree(scene, leafTriangles);
  validateScene(octree, source);
  return octree;
}

LazyGltf loadSceneWithoutMeshes(const std::string& spec) {
  LazyGltf lazy = openGltfWithoutMeshes(spec);
  requireDrawable(lazy.imported.scene, spec);
  return lazy;
}

}  // namespace pbs
