// Scene loading with timings and the summary shared by `pbs info` and `pbs demo`.
#include "scene_report.hpp"

#include "memory_limit.hpp"
#include <pbs/evaluation/report_numbers.hpp>

#include <pbs/scene/embree_caster.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/surfels/surfel_cache.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

namespace pbs::cli {
namespace {

nlohmann::json vectorJson(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

namespace {

// Loads the scene with `load(loaded)` (which may set more of `loaded`), then analyses it with
// `analyze(scene)`, each step timed.
template <class Load, class Analyze>
LoadedScene loadTimed(const std::string& spec, Load load, Analyze analyze) {
  LoadedScene loaded;
  loaded.name = spec;
  auto start = std::chrono::steady_clock::now();
  ImportResult imported = load(loaded);
  loaded.parseSeconds = secondsSince(start);
  for (const std::string& warning : imported.warnings) std::cerr << "warning: " << warning << "\n";
  loaded.scene = std::move(imported.scene);

  start = std::chrono::steady_clock::now();
  loaded.hierarchy = analyze(loaded.scene);
  loaded.summary = summarizeScene(loaded.scene, loaded.hierarchy);
  loaded.hierarchySeconds = secondsSince(start);
  return loaded;
}

// A glTF scene opened without its mesh arrays, which decodeMesh reads later.
template <class Analyze>
LoadedScene openLazily(const std::string& spec, Analyze analyze) {
  return loadTimed(
      spec,
      [&](LoadedScene& loaded) {
        LazyGltf lazy = loadSceneWithoutMeshes(spec);
        loaded.decodeMesh = std::move(lazy.decode);
        return std::move(lazy.imported);
      },
      analyze);
}

}  // namespace

void requireSceneFits(const std::string& spec, const SceneFit& fit) {
  if (spec == "default") return;
  const LazyGltf structure = loadSceneWithoutMeshes(spec);
  std::uint64_t arrays = 0, triangles = 0;
  for (const Mesh& mesh : structure.imported.scene.meshes) {
    arrays += foreseenMeshBytes(mesh);
    triangles += mesh.triangleCount();
  }
  // The file is mapped while it is read, and unmapped before a BVH is built: the peak is the larger.
  const std::uint64_t bvh =
      fit.rays ? embreeMemoryEstimate(structure.imported.scene, analyzeStructure(structure.imported.scene)) : 0;
  requireMemory(fit.alongside + arrays + std::max(structure.bufferBytes, bvh),
                std::string(fit.rays ? "ray casting " : "reading ") + spec + " (" + withThousands(triangles) +
                    (fit.rays ? " triangles in Embree's BVHs)" : " triangles)"),
                fit.limit);
}

LoadedScene loadAndAnalyze(const std::string& spec, const LoadOptions& options, const SceneFit& fit) {
  requireSceneFits(spec, fit);
  return loadTimed(
      spec, [&](LoadedScene&) { return loadScene(spec, options); },
      [](const Scene& scene) { return analyzeHierarchy(scene); });
}

LoadedScene loadAndAnalyze(const std::string& spec, const LoadOptions& options, SurfelFileReader& surfels,
                           const SceneFit& fit) {
  requireSceneFits(spec, fit);
  // The arrays belong to the hierarchy they were made of: the scene's own, or the loose octree it was
  // rebuilt as.
  LoadOptions asMade = options;
  asMade.octreeLeafTriangles = surfels.options().octreeLeafTriangles;
  return loadTimed(
      spec, [&](LoadedScene&) { return loadScene(spec, asMade); },
      [&](const Scene& scene) { return hierarchyWithSurfels(scene, surfels); });
}

bool drawableWithoutMeshes(const std::string& spec, const SurfelFileReader& surfels) {
  return spec != "default" && !surfels.sceneTable().instanceBounds.empty() &&
         surfels.options().octreeLeafTriangles == 0;
}

LoadedScene openWithoutMeshes(const std::string& spec, SurfelFileReader& surfels) {
  return openLazily(spec, [&](const Scene& scene) {
    surfels.requireStructure(structureFingerprint(scene));
    return analyzeHierarchy(scene, surfels.sceneTable().instanceBounds);
  });
}

LoadedScene openWithoutMeshes(const std::string& spec) {
  return openLazily(spec, [](const Scene& scene) { return analyzeStructure(scene); });
}

nlohmann::json summaryJson(const LoadedScene& loaded) {
  const SceneSummary& s = loaded.summary;
  return {
      {"scene", loaded.name},
      {"nodes", s.nodes},
      {"meshes", s.meshes},
      {"instances", s.instances},
      {"triangles", s.triangles},
      {"unique_triangles", s.uniqueTriangles},
      {"max_depth", s.maxDepth},
      {"materials", s.materials},
      {"textures", s.textures},
      {"bounds", {{"min", vectorJson(s.bounds.min)}, {"max", vectorJson(s.bounds.max)}}},
      {"load_seconds", loaded.parseSeconds + loaded.hierarchySeconds},
      {"parse_seconds", loaded.parseSeconds},
      {"hierarchy_seconds", loaded.hierarchySeconds},
  };
}

void printSummary(const LoadedScene& loaded) {
  const SceneSummary& s = loaded.summary;
  std::printf("scene      %s\n", loaded.name.c_str());
  std::printf("nodes      %s (max depth %u)\n", withThousands(s.nodes).c_str(), s.maxDepth);
  std::printf("meshes     %s, used by %s nodes\n", withThousands(s.meshes).c_str(), withThousands(s.instances).c_str());
  std::printf("triangles  %s instanced, %s unique\n", withThousands(s.triangles).c_str(),
              withThousands(s.uniqueTriangles).c_str());
  std::printf("materials  %s (%s textures)\n", withThousands(s.materials).c_str(), withThousands(s.textures).c_str());
  std::printf("bounds     (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g)\n", s.bounds.min.x, s.bounds.min.y, s.bounds.min.z,
              s.bounds.max.x, s.bounds.max.y, s.bounds.max.z);
  std::printf("loaded in  %.3f s (%.3f s parse, %.3f s hierarchy)\n", loaded.parseSeconds + loaded.hierarchySeconds,
              loaded.parseSeconds, loaded.hierarchySeconds);
}

}  // namespace pbs::cli
