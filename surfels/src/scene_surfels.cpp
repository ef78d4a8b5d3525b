// Decoding a .surfels file into drawable arrays and matching its node paths to a scene.
#include "pbs/surfels/scene_surfels.hpp"

#include "pbs/scene/input_error.hpp"
#include "pbs/scene/scene_fingerprint.hpp"
#include "pbs/surfels/surfel_nodes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace pbs {

double SplatArray::spacing(std::size_t count) const {
  if (count == 0) return 0.0;
  const double first = double(std::min<std::size_t>(kPackingSample, size()));
  const double last = double(size());
  double value = packing;
  if (packingEnd > 0.0 && packing > 0.0 && last > first && double(count) > first) {
    const double t = std::min(1.0, std::log(double(count) / first) / std::log(last / first));
    value = packing * std::pow(packingEnd / packing, t);
  }
  return std::sqrt(value / double(count));
}

namespace {

// The drawable array's values from the file's: neither packing value may make the array stand for more
// than the subtree's surface area (N surfels of spacing r cover N · κ r² = κ · packing): an array sparser
// than its subtree's parts (the 500 M-triangle city's root, about one surfel per building) measures the
// gaps between the parts, 6.1 times its area even at its end, where a typical array of the default
// scene stands for 0.6 of it (hidden surfaces make no surfels).
template <class FileArray>
SplatArray unloadedSplatArray(const FileArray& array, std::size_t length) {
  SplatArray splats;
  splats.box = array.box;
  splats.coverage = array.coverage;
  const double cap = array.area > 0.0 ? array.area / kSurfelAreaPerSpacing2 : std::numeric_limits<double>::infinity();
  splats.packing = std::min(array.packing, cap);
  splats.packingEnd = std::min(array.packingEnd, cap);
  splats.openSheet = array.twoSidedShare >= kOpenSheetShare;
  splats.length = length;
  return splats;
}

}  // namespace

void appendSurfels(SplatArray& array, std::span<const Surfel> surfels) {
  const std::size_t size = array.loaded() + surfels.size();
  array.positions.reserve(size);
  array.normals.reserve(size);
  array.colors.reserve(size);
  for (const Surfel& surfel : surfels) {
    array.positions.push_back(surfel.position);
    array.normals.push_back(surfel.normal);
    array.colors.push_back(surfel.color);
  }
}

SplatArray splatArrayOf(const SurfelArray& array) {
  SplatArray splats = unloadedSplatArray(array, array.surfels.size());
  appendSurfels(splats, array.surfels);
  return splats;
}

SplatArray splatArrayOf(const SurfelArrayInfo& info) { return unloadedSplatArray(info, info.count); }

std::vector<std::uint32_t> arrayOfNodes(std::span<const SurfelNodeRecord> records, const Scene& scene,
                                        const Hierarchy& hierarchy, const std::string& source) {
  std::vector<std::uint32_t> arrayOfNode(scene.nodes.size(), kNoSurfels);
  if (records.empty()) return arrayOfNode;
  std::vector<std::string> paths = nodePaths(scene, hierarchy);
  std::unordered_map<std::string, std::uint32_t> nodeOfPath;
  nodeOfPath.reserve(hierarchy.preorder.size());
  for (std::uint32_t n : hierarchy.preorder) nodeOfPath.emplace(std::move(paths[n]), n);
  for (const SurfelNodeRecord& record : records) {
    const auto found = nodeOfPath.find(record.path);
    if (found == nodeOfPath.end()) throw InputError(source, "node " + record.path, "no such node in the scene");
    arrayOfNode[found->second] = record.array;
  }
  return arrayOfNode;
}

SceneSurfels sceneSurfelsOf(const SurfelFile& file, const Scene& scene, const Hierarchy& hierarchy,
                            const std::string& source) {
  SceneSurfels result;
  result.arrays.reserve(file.arrays.size());
  for (const SurfelArray& array : file.arrays) result.arrays.push_back(splatArrayOf(array));
  result.arrayOfNode = arrayOfNodes(file.nodes, scene, hierarchy, source);
  return result;
}

SceneSurfels loadSceneSurfels(const std::filesystem::path& file, const Scene& scene, const Hierarchy& hierarchy) {
  SurfelFileReader(file).requireScene(sceneFingerprint(scene));
  return sceneSurfelsOf(readSurfelFile(file), scene, hierarchy, file.string());
}

}  // namespace pbs
