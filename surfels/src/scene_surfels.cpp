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

SplatArray splatArrayOf(const SurfelArray& array) {
  SplatArray splats;
  splats.box = array.box;
  splats.coverage = array.coverage;
  // Neither value may make the array stand for more than the subtree's surface area (N surfels of spacing
  // r cover N · κ r² = κ · packing): an array sparser than its subtree's parts (the 500 M-triangle city's
  // root, about one surfel per building) measures the gaps between the parts, 6.1 times its area even
  // at its end, where a typical array of the default scene stands for 0.6 of it (hidden surfaces make
  // no surfels).
  const double cap = array.area > 0.0 ? array.area / kSurfelAreaPerSpacing2 : std::numeric_limits<double>::infinity();
  splats.packing = std::min(array.packing, cap);
  splats.packingEnd = std::min(array.packingEnd, cap);
  splats.positions.reserve(array.surfels.size());
  splats.normals.reserve(array.surfels.size());
  splats.colors.reserve(array.surfels.size());
  for (const Surfel& surfel : array.surfels) {
    splats.positions.push_back(surfel.position);
    splats.normals.push_back(surfel.normal);
    splats.colors.push_back(surfel.color);
  }
  return splats;
}

SceneSurfels sceneSurfelsOf(const SurfelFile& file, const Scene& scene, const Hierarchy& hierarchy,
                            const std::string& source) {
  SceneSurfels result;
  result.arrays.reserve(file.arrays.size());
  for (const SurfelArray& array : file.arrays) result.arrays.push_back(splatArrayOf(array));
  result.arrayOfNode.assign(scene.nodes.size(), kNoSurfels);
  if (file.nodes.empty()) return result;
  std::vector<std::string> paths = nodePaths(scene, hierarchy);
  std::unordered_map<std::string, std::uint32_t> nodeOfPath;
  nodeOfPath.reserve(hierarchy.preorder.size());
  for (std::uint32_t n : hierarchy.preorder) nodeOfPath.emplace(std::move(paths[n]), n);
  for (const SurfelNodeRecord& record : file.nodes) {
    const auto found = nodeOfPath.find(record.path);
    if (found == nodeOfPath.end()) throw InputError(source, "node " + record.path, "no such node in the scene");
    result.arrayOfNode[found->second] = record.array;
  }
  return result;
}

SceneSurfels loadSceneSurfels(const std::filesystem::path& file, const Scene& scene, const Hierarchy& hierarchy) {
  SurfelFileReader(file).requireScene(sceneFingerprint(scene));
  return sceneSurfelsOf(readSurfelFile(file), scene, hierarchy, file.string());
}

}  // namespace pbs
