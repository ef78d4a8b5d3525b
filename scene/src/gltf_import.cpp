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

namespace {

// The scene of a parsed document, each glTF mesh a node uses made by `makeMesh(gltfMesh, materialOf,
// skipped)` (an empty Mesh, no parts, for one with nothing to draw); `gltfMeshOf` gets the glTF mesh of
// every scene mesh. Returns the material import, whose choices later reads of the meshes repeat.
template <class MakeMesh>
gltf::MaterialImport buildScene(const gltf::Document& model, const std::string& name, ImportResult& result,
                                std::vector<int>& gltfMeshOf, MakeMesh makeMesh) {
  Scene& scene = result.scene;
  gltf::MaterialImport materials(model, name, scene);
  const gltf::MaterialOf materialOf = [&](int material, std::string_view referrer) {
    return materials.use(material, referrer);
  };
  gltf::SkippedPrimitives skipped;

  // Meshes are imported when a node first uses them, so that one used by many nodes is stored once;
  // one with nothing to draw is not stored and its nodes carry no mesh.
  constexpr std::int32_t kNotYet = -2;
  std::vector<std::int32_t> sceneMesh(model.meshes.size(), kNotYet);
  const auto meshFor = [&](int gltfMesh) {
    std::int32_t& index = sceneMesh[static_cast<std::size_t>(gltfMesh)];
    if (index == kNotYet) {
      Mesh mesh = makeMesh(gltfMesh, materialOf, skipped);
      index = mesh.parts.empty() ? -1 : static_cast<std::int32_t>(scene.meshes.size());
      if (index != -1) {
        scene.meshes.push_back(std::move(mesh));
        gltfMeshOf.push_back(gltfMesh);
      }
    }
    return index;
  };
  gltf::importNodes(model, name, meshFor, scene, result.warnings);

  dropUnreadUvs(scene);
  skipped.appendWarnings(result.warnings);
  materials.appendWarnings(result.warnings);
  return materials;
}

}  // namespace

ImportResult importGltf(const std::filesystem::path& file) {
  const MappedFile mapped(file);
  return importGltfFromMemory(mapped.bytes(), file.string(), file.parent_path());
}

ImportResult importGltfFromMemory(std::span<const std::uint8_t> bytes, const std::string& name,
                                  const std::filesystem::path& baseDir) {
  ImportResult result;
  const gltf::Document model = gltf::parseDocument(bytes, name, baseDir, result.warnings);
  gltf::ZeroFilledBudget zeros;
  std::vector<int> gltfMeshOf;
  buildScene(model, name, result, gltfMeshOf,
             [&](int gltfMesh, const gltf::MaterialOf& materialOf, gltf::SkippedPrimitives& skipped) {
               return gltf::importMesh(model, gltfMesh, name, materialOf, skipped, zeros);
             });
  return result;
}

LazyGltf openGltfWithoutMeshes(const std::filesystem::path& file) {
  // What reading a mesh later needs, kept together: the document's buffers are views of the mapping.
  struct Source {
    Source(MappedFile file, gltf::Document document, std::string fileName)
        : mapped(std::move(file)), model(std::move(document)), name(std::move(fileName)) {}
    MappedFile mapped;
    gltf::Document model;
    std::string name;
    std::vector<int> gltfMeshOf;
    gltf::MaterialOf materialOf;
    Scene looks;  // the materials, for dropUnreadUvs
  };
  auto source = std::make_shared<Source>(MappedFile(file), gltf::Document{}, file.string());
  LazyGltf lazy;
  source->model = gltf::parseDocument(source->mapped.bytes(), source->name, file.parent_path(), lazy.imported.warnings);
  const gltf::MaterialImport materials =
      buildScene(source->model, source->name, lazy.imported, source->gltfMeshOf,
                 [&](int gltfMesh, const gltf::MaterialOf& materialOf, gltf::SkippedPrimitives& skipped) {
                   return gltf::describeMesh(source->model, gltfMesh, source->name, materialOf, skipped);
                 });
  source->materialOf = materials.used();
  for (const std::span<const std::uint8_t> buffer : source->model.bufferBytes) lazy.bufferBytes += buffer.size();
  // Reading a mesh needs its accessors, views and buffers, not the node graph (on a city of 111,111
  // nodes, 90 MB of tinygltf's nodes), nor the images: those are in the scene now.
  std::vector<tinygltf::Node>().swap(source->model.nodes);
  std::vector<tinygltf::Scene>().swap(source->model.scenes);
  source->looks.materials = lazy.imported.scene.materials;
  lazy.decode = [source](std::uint32_t mesh) {
    // Each read has its own budget for zero-filled accessors: reads run side by side, in any order.
    gltf::ZeroFilledBudget zeros;
    gltf::SkippedPrimitives skipped;  // counted when the scene was opened
    const int gltfMesh = source->gltfMeshOf[mesh];
    Mesh result = gltf::importMesh(source->model, gltfMesh, source->name, source->materialOf, skipped, zeros);
    dropUnreadUvs(source->looks, result);
    // The decoded arrays are all that is needed of the mesh's bytes: the file's pages go (a scan of a 3 GB
    // scene would otherwise hold all of it, the mapped pages counting while they stay).
    for (const std::span<const std::uint8_t> view : gltf::meshViewBytes(source->model, gltfMesh)) {
      source->mapped.releasePages(view);
      for (const gltf::UriBytes& buffer : source->model.loadedBuffers)
        if (const MappedFile* file = std::get_if<MappedFile>(&buffer.storage)) file->releasePages(view);
    }
    return result;
  };
  return lazy;
}

}  // namespace pbs
