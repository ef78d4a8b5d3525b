// A scene with surfels from surfelize at small, fast settings, for tests that render it.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/scene/generate.hpp>
#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>
#include <pbs/surfels/camera_paths.hpp>
#include <pbs/surfels/scene_surfels.hpp>
#include <pbs/surfels/surfelize.hpp>

#include "test_fixtures.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

namespace pbs::test {

struct SurfeledScene {
  Scene scene;
  Hierarchy hierarchy;
  SceneSurfels surfels;
};

// Arrays for nodes above `threshold` triangles, 4000 surfels each, captured at 128 pixels.
inline SurfeledScene surfeled(Scene scene, std::uint64_t threshold = 1000) {
  SurfeledScene s{std::move(scene), {}, {}};
  s.hierarchy = analyzeHierarchy(s.scene);
  SurfelizeOptions options;
  options.file.threshold = threshold;
  options.file.maxSurfels = 4000;
  options.file.resolution = 128;
  s.surfels = sceneSurfelsOf(surfelize(s.scene, s.hierarchy, options), s.scene, s.hierarchy, "test");
  return s;
}

// A small city of two shared meshes (generateCity, 2 levels of fanout 4) surfelized with arrays above 5,000
// triangles: every mesh instance has one, and so do the blocks. The callers take the files from PBS_SHARED_SCENE.
inline SurfeledScene surfeledCityOf(const std::filesystem::path& first, const std::filesystem::path& second) {
  Scene city = generateCity({importGltf(first).scene, importGltf(second).scene}, CityOptions{.levels = 2, .fanout = 4});
  validateScene(city, "city");
  return surfeled(std::move(city), 5000);
}

// The two-groups scene surfelized (arrays of 4000 surfels: four chunks) and written to `file`, for
// tests of what reads the file as frames need it.
inline SurfeledScene writtenSurfeledScene(const std::filesystem::path& file) {
  SurfeledScene s = surfeled(twoIdenticalGroups());
  SurfelizeOptions options;
  options.file.threshold = 1000;
  options.file.maxSurfels = 4000;
  options.file.resolution = 128;
  surfelizeToFile(s.scene, s.hierarchy, options, file);
  return s;
}

// The approach path at 160×120: far frames draw short prefixes, near ones long prefixes or geometry.
inline std::vector<Camera> approachCameras(const SurfeledScene& s, std::uint32_t frames, double startDistance = 4.0) {
  std::vector<Camera> cameras;
  for (const PathView& view :
       cameraPath(CameraPath::Approach, s.hierarchy, s.scene.roots, Orbit{30.0, 20.0, startDistance}, frames, 160, 120))
    cameras.push_back(view.camera);
  return cameras;
}

inline bool sameBits(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec4)) == 0;
}

}  // namespace pbs::test
