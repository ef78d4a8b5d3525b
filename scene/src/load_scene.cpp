// Resolves a command line's SCENE argument (a glTF file or `default`) into a validated scene.
#include "pbs/scene/load_scene.hpp"

#include "pbs/scene/generate.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/input_error.hpp"
#include "pbs/scene/loose_octree.hpp"

namespace pbs {

ImportResult loadScene(const std::string& spec, const LoadOptions& options) {
  ImportResult result;
  if (spec == "default") {
    result.scene = generateDefaultScene();
  } else {
    result = importGltf(spec);
  }
  validateScene(result.scene, spec);

  // A scene must draw something: every later step (capture, surfels, images) would be empty.
  // (After validation every node is reachable, so summing over all nodes counts every instance.)
  std::uint64_t triangles = 0;
  for (const Node& node : result.scene.nodes)
    if (node.mesh >= 0) triangles += result.scene.meshes[std::size_t(node.mesh)].triangleCount();
  if (triangles == 0) throw InputError(spec, "scene", "nothing to draw (no triangles)");

  if (options.octreeLeafTriangles > 0) {
    result.scene = buildLooseOctree(result.scene, options.octreeLeafTriangles);
    validateScene(result.scene, spec);
  }
  return result;
}

}  // namespace pbs
