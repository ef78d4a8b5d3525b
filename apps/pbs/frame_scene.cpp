// FrameScene: the .surfels file first (it says whether the meshes can wait), then the memory check, then
// the scene read whole or opened without its meshes.
#include "frame_scene.hpp"

#include "memory_limit.hpp"

namespace pbs::cli {

FrameScene::FrameScene(const FrameSceneOptions& options) : cacheBytes(options.cacheBytes) {
  // The file holds the exact box of every instance and, from version 4, the fingerprints that let a glTF
  // scene be opened without its mesh arrays, each read when a frame first draws it as geometry (a scene
  // rebuilt as a loose octree is read whole, its meshes split).
  std::optional<SurfelFileReader> surfelFile;
  if (!options.surfels.empty()) surfelFile.emplace(options.surfels);
  const bool meshesOnDemand = surfelFile && options.meshesOnDemand && drawableWithoutMeshes(options.scene, *surfelFile);
  foreseenBytes = options.alongside;
  if (surfelFile) foreseenBytes += options.cacheBytes;
  if (meshesOnDemand) foreseenBytes += options.cacheBytes;
  requireMemory(foreseenBytes, options.what, options.maxMemory);
  const SceneFit fit{.alongside = foreseenBytes, .limit = options.maxMemory, .rays = options.rays};
  loaded = meshesOnDemand ? openWithoutMeshes(options.scene, *surfelFile)
           : surfelFile   ? loadAndAnalyze(options.scene, LoadOptions{}, *surfelFile, fit)
                          : loadAndAnalyze(options.scene, LoadOptions{}, fit);
  if (meshesOnDemand)
    meshes.emplace(loaded.scene, loaded.decodeMesh, surfelFile->sceneTable().meshes, loaded.name, options.cacheBytes);
  if (surfelFile) surfels.emplace(std::move(*surfelFile), loaded.scene, loaded.hierarchy, options.cacheBytes);
}

}  // namespace pbs::cli
