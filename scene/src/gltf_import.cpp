// glTF 2.0 import: maps the file, parses it (gltf_document), then builds the scene from the chosen
// scene's nodes (gltf_nodes), the meshes they use (gltf_mesh) and those meshes' materials (gltf_material).
#include "pbs/scene/gltf_import.hpp"

#include "gltf_document.hpp"
#include "gltf_material.hpp"
#include "gltf_mesh.hpp"
#include "gltf_nodes.hpp"
#include "mapped_file.hpp"
#include "pbs/scene/input_error.hpp"

namespace pbs {

ImportResult importGltf(const std::filesystem::path& file) {
  const MappedFile mapped(file);
  return importGltfFromMemory(mapped.bytes(), file.string(), file.parent_path());
}

ImportResult importGltfFromMemory(std::span<const std::uint8_t> bytes, const std::string& name,
                                  const std::filesystem::path& baseDir) {
  ImportResult result;
  const gltf::Document model = gltf::parseDocument(bytes, name, baseDir, result.warnings);
  Scene& scene = result.scene;
  gltf::MaterialImport materials(model, name, scene);
  gltf::SkippedPrimitives skipped;
  gltf::ZeroFilledBudget zeros;

  // Meshes are imported when a node first uses them, so that one used by many nodes is stored once;
  // one with nothing to draw is not stored and its nodes carry no mesh.
  constexpr std::int32_t kNotYet = -2;
  std::vector<std::int32_t> sceneMesh(model.meshes.size(), kNotYet);
  const auto meshFor = [&](int gltfMesh) {
    std::int32_t& index = sceneMesh[static_cast<std::size_t>(gltfMesh)];
    if (index == kNotYet) {
      Mesh mesh = gltf::importMesh(model, gltfMesh, name, materials, skipped, zeros);
      index = mesh.indices.empty() ? -1 : static_cast<std::int32_t>(scene.meshes.size());
      if (index != -1) scene.meshes.push_back(std::move(mesh));
    }
    return index;
  };
  gltf::importNodes(model, name, meshFor, scene, result.warnings);

  dropUnreadUvs(scene);
  skipped.appendWarnings(result.warnings);
  materials.appendWarnings(result.warnings);
  return result;
}

}  // namespace pbs
