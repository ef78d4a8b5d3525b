// Loading a SCENE argument with timings, and printing its summary for people or as JSON.
#pragma once

#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/lazy_meshes.hpp>
#include <pbs/scene/load_scene.hpp>
#include <pbs/surfels/surfel_file.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace pbs::cli {

struct LoadedScene {
  std::string name;
  Scene scene;
  Hierarchy hierarchy;
  SceneSummary summary;
  double parseSeconds = 0;        // import (or generation) and validation
  double hierarchySeconds = 0;    // world transforms, exact bounds, subtree counts
  LazyMeshes::Decode decodeMesh;  // set when opened without its mesh arrays (openWithoutMeshes)
};

// What reading a scene whole must fit in besides itself.
struct SceneFit {
  std::uint64_t alongside = 0;  // bytes the command needs besides the scene
  std::uint64_t limit = 0;      // --max-memory; 0: the machine's memory
  bool rays = false;            // Embree's BVH over the whole scene too
};
// Before a glTF scene is read whole: what it (and the rest) will take, foreseen from its structure alone
// (each mesh's parts and vertex count, and the file's data, mapped while it is read), so that a
// scene that would not fit is refused in one line instead of being killed half-way through reading it.
// Nothing for `default`.
void requireSceneFits(const std::string& spec, const SceneFit& fit);

// Loads and analyses; prints the importer's warnings to stderr as "warning: …" lines. A glTF file that
// would not fit in memory with `fit` is refused first (requireSceneFits).
LoadedScene loadAndAnalyze(const std::string& spec, const LoadOptions& options, const SceneFit& fit = {});
// The same for a scene with its .surfels file: rebuilds the scene as the loose octree the file was made
// for, if any (`options`' octree is ignored), requires the file to be the scene's and takes the exact
// instance boxes from it where it stores them (hierarchyWithSurfels), so no vertex is read for them.
LoadedScene loadAndAnalyze(const std::string& spec, const LoadOptions& options, SurfelFileReader& surfels,
                           const SceneFit& fit = {});

// A glTF scene opened without its mesh arrays for drawing with its .surfels file: the structure is required
// to be the file's (SurfelFileReader::requireStructure) and the hierarchy comes from the file's instance
// boxes; the meshes are read by decodeMesh (for LazyMeshes, which checks each against the file's
// fingerprints). Needs a file with a scene table (version 4) of the scene's own hierarchy (no octree: it
// splits the meshes; drawableWithoutMeshes says which files can).
LoadedScene openWithoutMeshes(const std::string& spec, SurfelFileReader& surfels);
// Whether a glTF scene can be drawn with the file `surfels` without its mesh arrays (openWithoutMeshes).
bool drawableWithoutMeshes(const std::string& spec, const SurfelFileReader& surfels);
// A glTF scene opened without its mesh arrays and without a .surfels file: the hierarchy has no boxes
// (analyzeStructure), the meshes are read by decodeMesh.
LoadedScene openWithoutMeshes(const std::string& spec);

nlohmann::json summaryJson(const LoadedScene& loaded);
void printSummary(const LoadedScene& loaded);

}  // namespace pbs::cli
