// traverseWithBudget: from the coarsest cut, refine the node largest on screen while the cost model says
// the frame still fits; a node whose refinement does not fit stays, and smaller ones are tried.
#include "lod_budget.hpp"

#include "elapsed.hpp"
#include "lod_scale.hpp"
#include "pbs/raster/projected_box.hpp"
#include "pbs/scene/scene_draws.hpp"
#include "pbs/surfels/frame_cost.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <tuple>
#include <vector>

namespace pbs {
namespace {

// A node of the cut drawn as its surfels.
struct SurfelEntry {
  double size = 0.0;  // projected size, pixels: the refinement order
  // At or below the node's descent threshold: the threshold's traversal draws it as this prefix, and so does
  // the budget, refining no further (its children would cost more per pixel and look no better).
  bool finest = false;
  FrameWork work;
  LodDraws::Surfels draw;
};

// What a subtree's coarsest cut draws: surfel nodes, geometry nodes, their work.
struct Cut {
  std::vector<SurfelEntry> surfels;
  std::vector<std::uint32_t> geometry;
  std::uint64_t triangles = 0;
  FrameWork work;
};

class BudgetTraversal {
 public:
  BudgetTraversal(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                  const LodOptions& options)
      : scene_(scene),
        hierarchy_(hierarchy),
        surfels_(surfels),
        camera_(camera),
        boxes_(camera),
        options_(options),
        costs_(options.budgetCosts()),
        // A budget of primitives counts triangles whoever draws them.
        drawer_(options.budget.unit == BudgetUnit::Primitives ? GeometryDrawer::Raster : options.geometry),
        imagePixels_(double(camera.width) * double(camera.height)) {}

  // Visible nodes with an array (and a finite size) as surfels; others drawn as their own mesh and descended
  // into.
  void coarsest(std::uint32_t node, Cut& cut) const {
    const Bounds& box = hierarchy_.worldBounds[node];
    if (boxes_.outside(box)) return;
    cut.work.nodesWeighed += 1.0;
    const double pixels = boxes_.pixels(box);
    const std::uint32_t array = node < surfels_.arrayOfNode.size() ? surfels_.arrayOfNode[node] : kNoSurfels;
    // A box that reaches the eye has no finite size: its surfels would be discs without bound near the eye,
    // so it is always descended into, as the threshold's traversal does.
    if (array != kNoSurfels && std::isfinite(pixels)) {
      const SurfelEntry entry = surfelEntry(node, array, pixels);
      // A subtree whose every triangle costs less than its prefix is drawn exactly: cheaper and better.
      const FrameWork exact =
          geometryNodeWork(double(hierarchy_.subtreeTriangles[node]), std::min(pixels, imagePixels_));
      if (cost(exact) <= cost(entry.work)) {
        refine(node, cut, Descent::Geometry);
      } else if (entry.draw.count > 0) {
        cut.work += entry.work;
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
      // Only a budget in seconds prices pixels.
      const double pixels = options_.budget.unit == BudgetUnit::Seconds
                                ? clippedBoxPixels(boxes_, instanceWorldBounds(scene_, hierarchy_, node))
                                : 0.0;
      cut.work += geometryNodeWork(double(triangles), pixels);
      cut.triangles += triangles;
      cut.geometry.push_back(node);
    }
    for (std::uint32_t child : scene_.nodes[node].children) {
      if (descent == Descent::Coarsest) {
        coarsest(child, cut);
        continue;
      }
      const Bounds& box = hierarchy_.worldBounds[child];
      if (boxes_.outside(box)) continue;
      cut.work.nodesWeighed += 1.0;
      refine(child, cut, Descent::Geometry);
    }
  }

  // The frame's cost when it draws `work`, whatever every frame costs included.
  double cost(FrameWork work) const {
    work.imagePixels = imagePixels_;
    return predictFrameCost(costs_, work, drawer_);
  }

 private:
  SurfelEntry surfelEntry(std::uint32_t node, std::uint32_t array, double pixels) const {
    const SplatArray& splats = surfels_.arrays[array];
    const lod::NodeScale at = lod::nodeScale(camera_, hierarchy_.world[node], splats);
    const double size = std::sqrt(pixels);
    const std::uint32_t count = prefixLength(splats, size, at.worldPixel, at.scale, options_);
    const LodDraws::Surfels draw = lod::prefixDraw(node, array, splats, at, count, count);
    FrameWork work{.imagePixels = imagePixels_, .surfels = double(count), .nodes = 1.0};
    // Only a budget in seconds prices pixels.
    if (options_.budget.unit == BudgetUnit::Seconds)
      work.surfelPixels = splatPixels(camera_, hierarchy_.world[node], splats, draw);
    return {size, size <= lod::descentThreshold(splats, at, size, hierarchy_, node, options_), work, draw};
  }

  const Scene& scene_;
  const Hierarchy& hierarchy_;
  const SceneSurfels& surfels_;
  const Camera& camera_;
  const BoxProjection boxes_;
  const LodOptions& options_;
  const FrameCosts costs_;
  const GeometryDrawer drawer_;
  const double imagePixels_;
};

// A refined cut whose blur (cutBlur) is at most this many drawn pixels is kept at its size; a smaller size is
// taken only when its cut's blur is at most this share of the larger's (the same cut drawn smaller only loses
// pixels, whatever rounding says).
constexpr double kCoarseBlur = 4.0;
constexpr double kFinerBlur = 0.9;

// How coarse a cut drawn at `divisor` (by `reduced`) looks at the frame's size: the mean, over the pixels its
// nodes' boxes cover (clipped, counted at the frame's size), of the larger of a drawn pixel's side (the
// divisor) and, for a node drawn as surfels, its discs' diameter. A full-size cut of a few huge discs scores
// worse than a third of the size refined to geometry, which looks it.
double cutBlur(const Scene& scene, const Hierarchy& hierarchy, const Camera& reduced, const LodDraws& draws,
               double divisor) {
  double weighted = 0.0, pixels = 0.0;
  const BoxProjection boxes(reduced);
  const auto add = [&](const Bounds& box, double blur) {
    const double covered = clippedBoxPixels(boxes, box) * divisor * divisor;
    weighted += covered * blur;
    pixels += covered;
  };
  for (const LodDraws::Surfels& draw : draws.surfels)
    add(hierarchy.worldBounds[draw.node], divisor * std::max(1.0, draw.pointSize));
  for (std::uint32_t node : draws.geometryNodes) add(instanceWorldBounds(scene, hierarchy, node), divisor);
  return pixels > 0.0 ? weighted / pixels : divisor;
}

}  // namespace

Camera reducedCamera(const Camera& camera, double divisor) {
  Camera reduced = camera;
  reduced.width = std::max(1u, std::uint32_t(std::lround(double(camera.width) / divisor)));
  reduced.height = std::max(1u, std::uint32_t(std::lround(double(camera.height) / divisor)));
  return reduced;
}

BudgetResolution budgetResolution(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                                  const Camera& camera, const LodOptions& options) {
  const LodBudget& budget = options.budget;
  if (!(budget.limit > 0.0) || budget.unit != BudgetUnit::Seconds || !budget.lowerResolution)
    return {.divisor = 1.0, .pass = budget};
  const double upscale = predictUpscaleCost(options.frameCosts, double(camera.width) * double(camera.height));
  const auto reducedBy = [&](double divisor) {
    LodBudget pass = budget;
    // What is left after the upscale, or a sliver of the limit where the upscale alone would spend it (the
    // coarsest cut is drawn then).
    if (divisor > 1.0) pass.limit = std::max(budget.limit - upscale, budget.limit * 1e-3);
    return BudgetResolution{.divisor = divisor, .pass = pass};
  };
  // The refined cut at a size, kept in it, and its blur; the traversal's time added to `spent`.
  double spent = 0.0;
  const auto plan = [&](BudgetResolution& resolution) {
    const auto start = detail::Clock::now();
    const Camera reduced = reducedCamera(camera, resolution.divisor);
    LodOptions lod = options;
    lod.budget = resolution.pass;
    resolution.draws = traverseWithBudget(scene, hierarchy, surfels, reduced, lod);
    spent += detail::secondsSince(start);
    return cutBlur(scene, hierarchy, reduced, *resolution.draws, resolution.divisor);
  };
  for (std::size_t d = 0; d < kBudgetDivisors.size(); ++d) {
    const Camera reduced = reducedCamera(camera, kBudgetDivisors[d]);  // named: the traversal keeps a reference
    const BudgetTraversal traversal(scene, hierarchy, surfels, reduced, options);
    Cut cut;
    for (std::uint32_t root : scene.roots) traversal.coarsest(root, cut);
    if (traversal.cost(cut.work) + (d > 0 ? upscale : 0.0) > budget.limit) continue;
    BudgetResolution best = reducedBy(kBudgetDivisors[d]);
    double bestBlur = plan(best);
    for (std::size_t smaller = d + 1; smaller < kBudgetDivisors.size() && bestBlur > kCoarseBlur * best.divisor;
         ++smaller) {
      BudgetResolution candidate = reducedBy(kBudgetDivisors[smaller]);
      const double blur = plan(candidate);
      if (!(blur < kFinerBlur * bestBlur)) break;
      best = std::move(candidate);
      bestBlur = blur;
    }
    best.traverseSeconds = spent;
    return best;
  }
  return reducedBy(kBudgetDivisors.back());
}

LodDraws traverseWithBudget(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                            const Camera& camera, const LodOptions& options) {
  const BudgetTraversal traversal(scene, hierarchy, surfels, camera, options);
  Cut cut;
  for (std::uint32_t root : scene.roots) traversal.coarsest(root, cut);
  FrameWork total = cut.work;

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
    if (entry.finest) {
      kept.push_back(entry);
      continue;
    }
    Cut finer;
    traversal.refine(entry.draw.node, finer);
    FrameWork refined = total;
    refined -= entry.work;
    refined += finer.work;
    if (traversal.cost(refined) > options.budget.limit) {
      // Weighing the finer cut was spent all the same.
      total.nodesWeighed += finer.work.nodesWeighed;
      kept.push_back(entry);
      continue;
    }
    total = refined;
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
  draws.nodesWeighed = std::uint64_t(total.nodesWeighed);
  return draws;
}

}  // namespace pbs
