// The cut chosen by a budget (LodOptions::budget): within the limit, the coarsest cut when the limit is
// below it, no node refined below its descent threshold (every visible triangle when that threshold is tiny
// and the budget ample), closer to the exact picture as the budget grows, and the same draws every time.
#include "surfeled_scene.hpp"

#include <pbs/raster/image_metrics.hpp>
#include <pbs/raster/image_upscale.hpp>
#include <pbs/surfels/frame_cost.hpp>
#include <pbs/raster/projected_box.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/generate.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/lod_render.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pbs {
namespace {

// A budget of `limit` primitives that may refine nodes down to `thresholdPixels` on screen: the ample budgets
// below refine to every triangle at a threshold this small.
constexpr double kRefineAll = 1e-3;
LodOptions budgeted(double limit, double thresholdPixels = kRefineAll) {
  LodOptions options;
  options.budget = LodBudget::primitives(limit);
  options.threshold = thresholdPixels;
  return options;
}

std::uint64_t primitives(const LodDraws& draws) { return draws.triangles + draws.surfelCount; }

TEST(LodBudget, StaysWithinTheLimitAndIsDeterministic) {
  const test::SurfeledScene s = test::surfeled(test::twoIdenticalGroups());
  int stoppedAtTheThreshold = 0;  // views where an ample budget at the default threshold keeps surfels
  for (const Camera& camera : test::approachCameras(s, 4)) {
    const LodDraws coarsest = traverseLod(s.scene, s.hierarchy, s.surfels, camera, budgeted(1.0));
    // A root whose box reaches the eye has no finite size and is descended into, whatever the budget.
    const std::uint32_t root = s.scene.roots[0];
    if (std::isfinite(projectedBoxPixels(camera, s.hierarchy.worldBounds[root]))) {
      ASSERT_EQ(coarsest.surfels.size(), 1u);
      EXPECT_EQ(coarsest.surfels[0].node, root) << "the coarsest cut draws the root's prefix";
      EXPECT_TRUE(coarsest.geometryNodes.empty());
    } else {
      for (const LodDraws::Surfels& draw : coarsest.surfels) EXPECT_NE(draw.node, root);
    }
    const LodDraws ample = traverseLod(s.scene, s.hierarchy, s.surfels, camera, budgeted(1e9));
    EXPECT_TRUE(ample.surfels.empty()) << "an ample budget refines down to every visible triangle";
    EXPECT_GT(ample.triangles, 0u);
    // At the default threshold an ample budget stops where the threshold's traversal does: no node it keeps
    // as surfels is larger than that on screen (its children would cost more and look no better).
    const double threshold = LodOptions{}.threshold;
    const LodDraws stopped = traverseLod(s.scene, s.hierarchy, s.surfels, camera, budgeted(1e9, threshold));
    const LodDraws fixed = traverseLod(s.scene, s.hierarchy, s.surfels, camera, LodOptions{});
    EXPECT_EQ(stopped.surfels.empty(), fixed.surfels.empty());
    for (const LodDraws::Surfels& draw : stopped.surfels)
      EXPECT_LE(std::sqrt(projectedBoxPixels(camera, s.hierarchy.worldBounds[draw.node])), threshold) << draw.node;
    EXPECT_LE(primitives(stopped), primitives(ample));
    stoppedAtTheThreshold += !stopped.surfels.empty();
    for (double limit : {2000.0, 4000.0, 8000.0, 16000.0}) {
      // Not more primitives for more budget, necessarily: a node's triangles may cost less than its prefix.
      const LodDraws draws = traverseLod(s.scene, s.hierarchy, s.surfels, camera, budgeted(limit));
      if (limit >= double(primitives(coarsest))) {
        EXPECT_LE(double(primitives(draws)), limit) << limit;
      }
      const LodDraws again = traverseLod(s.scene, s.hierarchy, s.surfels, camera, budgeted(limit));
      EXPECT_EQ(again.geometryNodes, draws.geometryNodes);
      ASSERT_EQ(again.surfels.size(), draws.surfels.size());
      for (std::size_t i = 0; i < draws.surfels.size(); ++i) {
        EXPECT_EQ(again.surfels[i].node, draws.surfels[i].node);
        EXPECT_EQ(again.surfels[i].count, draws.surfels[i].count);
      }
    }
  }
  EXPECT_GT(stoppedAtTheThreshold, 0) << "some view must leave nodes below the threshold";
}

// A city of 64 boxes in three levels, seen from the start of its approach: the least budget draws the
// coarsest cut, an ample one every triangle (the exact picture), and one half-way between their costs
// lies between them in error.
TEST(LodBudget, ErrorFallsAsTheBudgetGrows) {
  const Scene box = test::sceneOf(test::tessellatedBox(20), {glm::dmat4(1.0)});
  const test::SurfeledScene s = test::surfeled(generateCity({box}, {.levels = 3, .fanout = 4}));
  const Camera camera = test::approachCameras(s, 4, 2.0)[1];
  FrameRenderer exact(s.scene, s.hierarchy, {.mode = RenderMode::Exact}, camera.width, camera.height);
  const RgbaImage reference{camera.width, camera.height, exact.render(camera).image};
  const double coarsest = double(primitives(traverseLod(s.scene, s.hierarchy, s.surfels, camera, budgeted(1.0))));
  const double ample = double(primitives(traverseLod(s.scene, s.hierarchy, s.surfels, camera, budgeted(1e9))));
  ASSERT_LT(coarsest, ample) << "the view must leave the budget something to choose";
  const double halfway = (coarsest + ample) / 2.0;
  EXPECT_LE(double(primitives(traverseLod(s.scene, s.hierarchy, s.surfels, camera, budgeted(halfway)))), halfway);
  std::vector<double> errors;
  for (double limit : {1.0, halfway, 1e9}) {
    // The geometry drawn as the exact renderer draws it (rays agree with it only to a tolerance).
    LodOptions lod = budgeted(limit);
    lod.geometry = GeometryDrawer::Raster;
    FrameRenderer renderer(s.scene, s.hierarchy, {.mode = RenderMode::Surfels, .lod = lod}, camera.width, camera.height,
                           {.surfels = &s.surfels});
    errors.push_back(compareImages(RgbaImage{camera.width, camera.height, renderer.render(camera).image}, reference)
                         .flipForegroundMean);
  }
  EXPECT_GE(errors[0], errors[1]);
  EXPECT_GE(errors[1], errors[2]);
  EXPECT_GT(errors[0], errors[2]);
  EXPECT_EQ(errors[2], 0.0) << "an ample budget draws every triangle, as the exact renderer does";
}

LodOptions inSeconds(double limit, bool lowerResolution = true) {
  LodOptions options;
  options.budget = LodBudget::seconds(limit);
  options.budget.lowerResolution = lowerResolution;
  return options;
}

double coveredPixels(const std::vector<glm::vec4>& image) {
  double covered = 0.0;
  for (const glm::vec4& pixel : image) covered += pixel.a;
  return covered;
}

// A budget in seconds that not even the coarsest cut fits draws the frame at the lowest resolution of the
// ladder and upscales it to the frame's size: exactly the frame drawn at that size, upscaled, covering about
// what the full-resolution frame covers, the same bytes for any thread count. An ample budget, a budget that keeps the
// resolution, and supersampled frames draw at full resolution.
TEST(LodBudget, ABudgetNoCutFitsDrawsAtALowerResolutionAndUpscales) {
  const Scene box = test::sceneOf(test::tessellatedBox(20), {glm::dmat4(1.0)});
  const test::SurfeledScene s = test::surfeled(generateCity({box}, {.levels = 3, .fanout = 4}));
  const Camera camera = test::approachCameras(s, 4, 2.0)[1];
  const auto renderAt = [&](const Camera& at, const LodOptions& lod, std::uint32_t samples = 1) {
    FrameRenderer renderer(s.scene, s.hierarchy, {.mode = RenderMode::Surfels, .lod = lod, .samples = samples},
                           at.width, at.height, {.surfels = &s.surfels});
    return renderer.render(at);
  };
  const auto render = [&](const LodOptions& lod, std::uint32_t samples = 1) { return renderAt(camera, lod, samples); };
  const FrameResult full = render(inSeconds(1e-9, false));
  EXPECT_EQ(full.divisor, 1.0);
  EXPECT_EQ(full.drawnWidth, camera.width);

  const FrameResult reduced = render(inSeconds(1e-9));
  EXPECT_EQ(reduced.divisor, 8.0);
  EXPECT_EQ(reduced.drawnWidth, std::uint32_t(std::lround(camera.width / 8.0)));
  EXPECT_EQ(reduced.drawnHeight, std::uint32_t(std::lround(camera.height / 8.0)));
  ASSERT_EQ(reduced.image.size(), full.image.size());
  Camera small = camera;
  small.width = reduced.drawnWidth;
  small.height = reduced.drawnHeight;
  EXPECT_EQ(reduced.image, upscaleBilinear(renderAt(small, inSeconds(1e-9, false)).image, small.width, small.height,
                                           camera.width, camera.height))
      << "the frame the budget draws at the small size, upscaled";
  // A frame of 10 × 8 pixels, its edges half a pixel (4 of the frame's) wide.
  EXPECT_NEAR(coveredPixels(reduced.image), coveredPixels(full.image), 0.2 * coveredPixels(full.image));
  FrameResult again;
  runWithThreads(1, [&] { again = render(inSeconds(1e-9)); });
  EXPECT_EQ(again.image, reduced.image) << "one thread and all";

  // Between the two, a growing budget draws at finer resolutions, through the ladder's middle.
  std::vector<double> divisors;
  double middleLimit = 0.0;
  for (double limit = 1e-6; limit < 1e-1; limit *= 1.5) {
    divisors.push_back(render(inSeconds(limit)).divisor);
    if (middleLimit == 0.0 && divisors.back() > 1.0 && divisors.back() < 8.0) middleLimit = limit;
  }
  EXPECT_TRUE(std::is_sorted(divisors.rbegin(), divisors.rend()));
  ASSERT_GT(middleLimit, 0.0) << "a budget drawn in the ladder's middle";
  // There the cut chosen with the size is drawn: the frame a traversal at that size under the budget left after
  // the upscale makes, upscaled.
  const FrameResult middle = render(inSeconds(middleLimit));
  Camera middleCamera = camera;
  middleCamera.width = middle.drawnWidth;
  middleCamera.height = middle.drawnHeight;
  const double left = std::max(middleLimit - predictUpscaleCost(FrameCosts{}, double(camera.width) * camera.height),
                               middleLimit * 1e-3);
  EXPECT_EQ(middle.image, upscaleBilinear(renderAt(middleCamera, inSeconds(left, false)).image, middleCamera.width,
                                          middleCamera.height, camera.width, camera.height));
  EXPECT_EQ(divisors.back(), 1.0);
  EXPECT_EQ(render(inSeconds(1e3)).divisor, 1.0) << "an ample budget";
  EXPECT_EQ(render(inSeconds(1e-9), 4).divisor, 1.0) << "supersampled frames keep their resolution";
  EXPECT_EQ(render(budgeted(1.0)).divisor, 1.0) << "a budget of primitives is the same on every machine";

  // One renderer whose frames change resolution (its G-buffer shrinks and grows back) draws each frame as a
  // fresh renderer would.
  FrameRenderer reused(s.scene, s.hierarchy, {.mode = RenderMode::Surfels, .lod = inSeconds(1e-9, false)}, camera.width,
                       camera.height, {.surfels = &s.surfels});
  EXPECT_EQ(reused.render(camera).image, full.image);
  reused.setBudget(inSeconds(1e-9).budget);
  EXPECT_EQ(reused.render(camera).image, reduced.image);
  reused.setBudget(inSeconds(1e-9, false).budget);
  EXPECT_EQ(reused.render(camera).image, full.image) << "back at full size";
}

// Priced in primitives (a surfel or a triangle a unit, the upscale free), a limit just above the full-size
// coarsest cut (here the root's whole array) fits that cut and nothing finer, and no smaller size refines it
// either (its children's arrays are as long at any size): the frame keeps its size rather than drawing the same
// cut with fewer pixels.
TEST(LodBudget, ASmallerSizeIsNotTakenForTheSameCut) {
  const Scene box = test::sceneOf(test::tessellatedBox(20), {glm::dmat4(1.0)});
  const test::SurfeledScene s = test::surfeled(generateCity({box}, {.levels = 3, .fanout = 4}));
  // Far enough that the root's surfels stand for the city, large enough that their discs are many pixels.
  Camera camera = test::approachCameras(s, 4, 4.0)[0];
  camera.width *= 4;
  camera.height *= 4;
  const auto inPrimitives = [](double limit, bool lowerResolution) {
    LodOptions options = inSeconds(limit, lowerResolution);
    options.frameCosts = FrameCosts::primitives();
    options.geometry = GeometryDrawer::Raster;  // primitives() prices no ray
    return options;
  };
  const auto renderWith = [&](const LodOptions& lod) {
    FrameRenderer renderer(s.scene, s.hierarchy, {.mode = RenderMode::Surfels, .lod = lod}, camera.width, camera.height,
                           {.surfels = &s.surfels});
    return renderer.render(camera);
  };
  const FrameResult coarsest = renderWith(inPrimitives(1.0, false));
  ASSERT_EQ(coarsest.stats.nodesSurfels + coarsest.stats.nodesGeometry, 1u) << "the root's array";
  const FrameResult chosen = renderWith(inPrimitives(double(coarsest.stats.surfels) * 1.01, true));
  EXPECT_EQ(chosen.divisor, 1.0);
  EXPECT_EQ(chosen.image, coarsest.image);
}

// The budget's own traversal is part of the frame: priced per node it weighs, a dearer weighing leaves less of
// the limit to draw with, so the cut is coarser; the frame reports the nodes weighed.
TEST(LodBudget, ABudgetPaysForTheNodesItWeighs) {
  const Scene box = test::sceneOf(test::tessellatedBox(20), {glm::dmat4(1.0)});
  const test::SurfeledScene s = test::surfeled(generateCity({box}, {.levels = 3, .fanout = 4}));
  const Camera camera = test::approachCameras(s, 4, 2.0)[1];
  const auto drawn = [&](double perNodeWeighed) {
    LodOptions lod = inSeconds(0.02, false);
    lod.frameCosts.perNodeWeighed = perNodeWeighed;
    FrameRenderer renderer(s.scene, s.hierarchy, {.mode = RenderMode::Surfels, .lod = lod}, camera.width, camera.height,
                           {.surfels = &s.surfels});
    return renderer.render(camera).stats;
  };
  const LodStats free = drawn(0.0), dear = drawn(2e-3);
  // (A refinement tried and refused was weighed all the same, so the dear frame weighs no more nodes.)
  EXPECT_GE(free.nodesWeighed, dear.nodesWeighed);
  EXPECT_GT(dear.nodesWeighed, 0u);
  EXPECT_GT(free.nodesSurfels + free.nodesGeometry, dear.nodesSurfels + dear.nodesGeometry);
}

}  // namespace
}  // namespace pbs
