// traverseWithBudget: from the coarsest cut, refine the node largest on screen while the cost model says
// the frame still fits; a node whose refinement does not fit stays, and smaller ones are tried.
#include "lod_budget.hpp"

#include "lod_scale.hpp"
#include "pbs/raster/projected_box.hpp"
#include "pbs/scene/scene_draws.hpp"

#include <algorithm>
#include <cmath>
#include <queue>
#include <tuple>
#include <vector>

namespace pbs {
namespace {

// A node of the cut drawn as its surfels.
struct SurfelEntry {
  double size = 0.0;  // projected size, pixels: the refinement order
  double cost = 0.0;
  LodDraws::Surfels draw;
};

// What a subtree's coarsest cut draws: surfel nodes, geometry nodes, their cost.
struct Cut {
  std::vector<SurfelEntry> surfels;
  std::vector<std::uint32_t> geometry;
  std::uint64_t triangles = 0;
  double cost = 0.0;
};

class BudgetTraversal {
 public:
  BudgetTraversal(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                  const LodOptions& options)
      : scene_(scene), hierarchy_(hierarchy), surfels_(surfels), camera_(camera), options_(options) {}

  // Visible nodes with an array as surfels; others drawn as their own mesh and descended into.
  void coarsest(std::uint32_t node, Cut& cut) const {
    const Bounds& box = hierarchy_.worldBounds[node];
    if (box.empty() || outsideClipVolume(camera_, box)) return;
    const double pixels = projectedBoxPixels(camera_, box);
    const std::uint32_t array = node < surfels_.arrayOfNode.size() ? surfels_.arrayOfNode[node] : kNoSurfels;
    if (array != kNoSurfels) {
      const SurfelEntry entry = surfelEntry(node, array, pixels);
      // A subtree whose every triangle costs less than its prefix is drawn exactly: cheaper and better.
      if (options_.budget.perTriangle * double(hierarchy_.subtreeTriangles[node]) <= entry.cost) {
        refine(node, cut, Descent::Geometry);
      } else if (entry.draw.count > 0) {
        cut.cost += entry.cost;
        cut.surfels.push_back(entry);
      }
      return;
    }
    refine(node, cut);
  }

  enum class Descent { Coarsest, Geometry };
  // `node` drawn as its own mesh (if any) and its children's coarsest cuts, or (Geometry) its subtree's
  // triangles.
  void refine(std::uint32_t node, Cut& cut, Descent descent = Descent::Coarsest) const {
    const std::int32_t mesh = scene_.nodes[node].mesh;
    if (mesh >= 0) {
      const std::uint64_t triangles = scene_.meshes[std::size_t(mesh)].triangleCount();
      cut.cost += options_.budget.perTriangle * double(triangles);
      cut.triangles += triangles;
      cut.geometry.push_back(node);
    }
    for (std::uint32_t child : scene_.nodes[node].children) {
      if (descent == Descent::Coarsest) {
        coarsest(child, cut);
        continue;
      }
      const Bounds& box = hierarchy_.worldBounds[child];
      if (!box.empty() && !outsideClipVolume(camera_, box)) refine(child, cut, Descent::Geometry);
    }
  }

 private:
  SurfelEntry surfelEntry(std::uint32_t node, std::uint32_t array, double pixels) const {
    const SplatArray& splats = surfels_.arrays[array];
    const lod::NodeScale at = lod::nodeScale(camera_, hierarchy_.world[node], splats);
    const double size = std::sqrt(pixels);
    const std::uint32_t count = prefixLength(splats, size, at.worldPixel, at.scale, options_);
    return {size, options_.budget.perSurfel * double(count), lod::prefixDraw(node, array, splats, at, count, count)};
  }

  const Scene& scene_;
  const Hierarchy& hierarchy_;
  const SceneSurfels& surfels_;
  const Camera& camera_;
  const LodOptions& options_;
};

}  // namespace

LodDraws traverseWithBudget(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                            const Camera& camera, const LodOptions& options) {
  const BudgetTraversal traversal(scene, hierarchy, surfels, camera, options);
  Cut cut;
  for (std::uint32_t root : scene.roots) traversal.coarsest(root, cut);
  double total = cut.cost;

  // Largest on screen first; ties by node index, so the cut does not depend on the order of the queue.
  const auto later = [](const SurfelEntry& a, const SurfelEntry& b) {
    return std::tie(a.size, b.draw.node) < std::tie(b.size, a.draw.node);
  };
  std::priority_queue<SurfelEntry, std::vector<SurfelEntry>, decltype(later)> open(later, std::move(cut.surfels));
  LodDraws draws;
  draws.geometryNodes = std::move(cut.geometry);
  draws.triangles = cut.triangles;
  std::vector<SurfelEntry> kept;
  while (!open.empty()) {
    const SurfelEntry entry = open.top();
    open.pop();
    Cut finer;
    traversal.refine(entry.draw.node, finer);
    if (total - entry.cost + finer.cost > options.budget.limit) {
      kept.push_back(entry);
      continue;
    }
    total += finer.cost - entry.cost;
    draws.geometryNodes.insert(draws.geometryNodes.end(), finer.geometry.begin(), finer.geometry.end());
    draws.triangles += finer.triangles;
    for (const SurfelEntry& child : finer.surfels) open.push(child);
  }
  // In node order, as a fixed order of draws keeps blended frames bit-identical.
  std::sort(draws.geometryNodes.begin(), draws.geometryNodes.end());
  std::sort(kept.begin(), kept.end(),
            [](const SurfelEntry& a, const SurfelEntry& b) { return a.draw.node < b.draw.node; });
  for (const SurfelEntry& entry : kept) {
    draws.surfels.push_back(entry.draw);
    draws.surfelCount += entry.draw.count;
  }
  return draws;
}

}  // namespace pbs
