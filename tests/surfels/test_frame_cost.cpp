// FrameCosts: the fit recovers the costs of frames made by known costs, a time budget keeps its cut's
// predicted time within the limit, and the feedback scales the budget by how far frames missed.
#include "surfeled_scene.hpp"

#include <pbs/raster/framebuffer.hpp>
#include <pbs/surfels/frame_cost.hpp>
#include <pbs/surfels/lod_render.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace pbs {
namespace {

FrameCosts someCosts() {
  FrameCosts costs;
  costs.perImagePixel = 6e-9;
  costs.rasterPerTriangle = 15e-9;
  costs.rasterPerPixel = 0.0;  // a term the fit must find zero
  costs.rasterPerBoxPixel = 1.5e-9;
  costs.rasterPerNode = 20e-6;
  costs.rasterPerTriangleOnPixels = 50e-9;
  costs.raysPerImagePixel = 1.5e-9;
  costs.raysPerPixel = 20e-9;
  costs.raysPerBoxPixel = 0.5e-9;
  costs.raysPerNode = 5e-6;
  costs.perSurfel = 60e-9;
  costs.perSurfelPixel = 2e-9;
  costs.perNode = 1e-6;
  return costs;
}

// Frames of varied work, timed exactly by `costs`: half drawn by the rasterizer, half by rays.
std::vector<TimedFrame> framesTimedBy(const FrameCosts& costs) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<TimedFrame> frames;
  for (int f = 0; f < 60; ++f) {
    TimedFrame frame;
    frame.work = {.imagePixels = f % 3 == 0 ? 518400.0 : 2073600.0,
                  .triangles = 1e7 * unit(random),
                  .geometryPixels = 4e6 * unit(random),
                  .geometryRayPixels = 6e7 * unit(random),
                  .trianglesOnPixels = 0.0,
                  .surfels = 1e6 * unit(random),
                  .surfelPixels = 1e7 * unit(random),
                  .nodes = 0.0,
                  .geometryNodes = std::floor(3000.0 * unit(random))};
    frame.work.nodes = frame.work.geometryNodes + std::floor(500.0 * unit(random));
    frame.work.trianglesOnPixels = std::min(frame.work.triangles, frame.work.geometryPixels) * unit(random);
    frame.drawer = f % 2 ? GeometryDrawer::Rays : GeometryDrawer::Raster;
    frame.geometrySeconds = predictGeometryCost(costs, frame.work, frame.drawer);
    frame.seconds = frame.geometrySeconds + predictNonGeometryCost(costs, frame.work);
    frames.push_back(frame);
  }
  return frames;
}

TEST(FrameCosts, TheFitRecoversTheCostsFramesWereTimedBy) {
  const FrameCosts truth = someCosts();
  const FrameCostFit fit = fitFrameCosts(framesTimedBy(truth));
  EXPECT_EQ(fit.frames, 60u);
  EXPECT_EQ(fit.rasterFrames, 30u);
  EXPECT_EQ(fit.rayFrames, 30u);
  EXPECT_LT(fit.medianError, 1e-9);
  EXPECT_LT(fit.p90Error, 1e-9);
  EXPECT_NEAR(fit.scale, 1.0, 1e-9) << "exact times need no factor";
  const auto near = [](double fitted, double expected) {
    return std::abs(fitted - expected) <= 1e-6 * expected + 1e-18;
  };
  EXPECT_TRUE(near(fit.costs.perImagePixel, truth.perImagePixel)) << fit.costs.perImagePixel;
  EXPECT_TRUE(near(fit.costs.rasterPerTriangle, truth.rasterPerTriangle));
  EXPECT_TRUE(near(fit.costs.rasterPerPixel, 0.0)) << fit.costs.rasterPerPixel;
  EXPECT_TRUE(near(fit.costs.rasterPerBoxPixel, truth.rasterPerBoxPixel));
  EXPECT_TRUE(near(fit.costs.rasterPerNode, truth.rasterPerNode));
  EXPECT_TRUE(near(fit.costs.rasterPerTriangleOnPixels, truth.rasterPerTriangleOnPixels));
  EXPECT_TRUE(near(fit.costs.raysPerImagePixel, truth.raysPerImagePixel));
  EXPECT_TRUE(near(fit.costs.raysPerPixel, truth.raysPerPixel));
  EXPECT_TRUE(near(fit.costs.raysPerBoxPixel, truth.raysPerBoxPixel));
  EXPECT_TRUE(near(fit.costs.raysPerNode, truth.raysPerNode));
  EXPECT_TRUE(near(fit.costs.perSurfel, truth.perSurfel));
  EXPECT_TRUE(near(fit.costs.perSurfelPixel, truth.perSurfelPixel));
  EXPECT_TRUE(near(fit.costs.perNode, truth.perNode));
}

// Frames timed by the costs and then slowed by up to 30 % (noise the terms cannot explain): at a quantile q
// the costs are scaled so that q of the frames take no longer than predicted, and the median keeps the least
// squares' own underestimate from making every other frame overshoot.
TEST(FrameCosts, AtAQuantileThatShareOfTheFramesTakesNoLongerThanPredicted) {
  std::vector<TimedFrame> frames = framesTimedBy(someCosts());
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const double slower = 1.0 + 0.3 * double((f * 7) % 10) / 10.0;  // 1.0 to 1.27, evenly
    frames[f].seconds *= slower;
    frames[f].geometrySeconds *= slower;
  }
  const auto within = [&](const FrameCostFit& fit) {
    std::size_t count = 0;
    for (const TimedFrame& frame : frames)
      count += frame.seconds <= predictFrameCost(fit.costs, frame.work, frame.drawer) * (1.0 + 1e-12);
    return double(count) / double(frames.size());
  };
  for (double quantile : {0.5, 0.75, 0.9, 1.0}) {
    const FrameCostFit fit = fitFrameCosts(frames, quantile);
    EXPECT_EQ(fit.quantile, quantile);
    EXPECT_GE(within(fit), quantile) << quantile;
    EXPECT_LT(within(fit), quantile + 0.1) << quantile << ": the least factor that does";
  }
  EXPECT_GT(fitFrameCosts(frames, 0.9).scale, fitFrameCosts(frames, 0.5).scale);
  EXPECT_THROW(fitFrameCosts(frames, 0.0), std::invalid_argument);
  EXPECT_THROW(fitFrameCosts(frames, 1.5), std::invalid_argument);
  EXPECT_THROW(fitFrameCosts(frames, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

TEST(FrameCosts, TheFitKeepsCostsNonNegativeAndADrawerWithoutFramesAtItsDefault) {
  // Times that fall as surfels rise: least squares would price a surfel negative.
  std::vector<TimedFrame> frames;
  for (int f = 0; f < 8; ++f) {
    frames.push_back({.work = {.imagePixels = 1e6, .surfels = 1e5 * f},
                      .seconds = 0.02 - 0.001 * f,
                      .geometrySeconds = 0.0,
                      .drawer = GeometryDrawer::Raster});
  }
  const FrameCostFit fit = fitFrameCosts(frames);
  EXPECT_GE(fit.costs.perSurfel, 0.0);
  EXPECT_GT(fit.costs.perImagePixel, 0.0);
  EXPECT_EQ(fit.rasterFrames, 0u) << "frames without triangles say nothing of the rasterizer";
  EXPECT_EQ(fit.costs.rasterPerTriangle, FrameCosts{}.rasterPerTriangle);
  EXPECT_EQ(fit.costs.raysPerPixel, FrameCosts{}.raysPerPixel);
}

TEST(FrameCosts, TheFitRefusesTooFewFramesAndTimesThatAreNotTimes) {
  std::vector<TimedFrame> frames = framesTimedBy(someCosts());
  EXPECT_THROW(fitFrameCosts(std::span(frames).first(3)), std::invalid_argument);
  frames[5].seconds = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fitFrameCosts(frames), std::invalid_argument);
  frames[5].seconds = 0.0;
  EXPECT_THROW(fitFrameCosts(frames), std::invalid_argument);
  frames[5].seconds = 0.01;
  frames[5].geometrySeconds = 0.02;  // more than the whole frame
  EXPECT_THROW(fitFrameCosts(frames), std::invalid_argument);
}

TEST(FrameCosts, AutoPredictsTheCheaperDrawer) {
  const FrameCosts costs;
  const FrameWork many{.imagePixels = 2e6, .triangles = 2e7, .geometryPixels = 1e5, .geometryNodes = 10};
  EXPECT_LT(predictGeometryCost(costs, many, GeometryDrawer::Rays),
            predictGeometryCost(costs, many, GeometryDrawer::Raster));
  EXPECT_EQ(predictGeometryCost(costs, many, GeometryDrawer::Auto),
            predictGeometryCost(costs, many, GeometryDrawer::Rays));
  const FrameWork none{.imagePixels = 2e6};
  EXPECT_EQ(predictGeometryCost(costs, none, GeometryDrawer::Auto), 0.0) << "no geometry, no rays";
}

TEST(FrameCosts, SplatsNearTheEyeTouchMorePixelsAndNoneBehindIt) {
  const test::SurfeledScene s = test::surfeled(test::twoIdenticalGroups());
  const std::vector<Camera> cameras = test::approachCameras(s, 4);
  const std::uint32_t node = s.scene.roots[0];
  const std::uint32_t array = s.surfels.arrayOfNode[node];
  ASSERT_NE(array, kNoSurfels);
  const LodDraws::Surfels draw{node, array, 1000, s.surfels.arrays[array].spacing(1000), 0.0, 1000};
  const double far = splatPixels(cameras.front(), s.hierarchy.world[node], s.surfels.arrays[array], draw);
  const double nearer = splatPixels(cameras[2], s.hierarchy.world[node], s.surfels.arrays[array], draw);
  EXPECT_GT(far, 1000.0) << "at least a pixel a splat";
  EXPECT_GT(nearer, far);
  Camera behind = cameras.front();
  behind.view =
      glm::dmat4(-1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0) * behind.view;
  EXPECT_EQ(splatPixels(behind, s.hierarchy.world[node], s.surfels.arrays[array], draw), 0.0);
}

// A budget in seconds: the cut's predicted time (from what the frame then drew) is within the limit
// whenever the coarsest cut is, the same every time, and an ample budget draws every visible triangle.
TEST(FrameCosts, ATimeBudgetKeepsThePredictedFrameWithinTheLimit) {
  const test::SurfeledScene s = test::surfeled(test::twoIdenticalGroups());
  for (const Camera& camera : test::approachCameras(s, 4)) {
    LodOptions options;
    options.geometry = GeometryDrawer::Raster;
    const auto drawn = [&](double limit) {
      options.budget = LodBudget::seconds(limit);
      Framebuffer framebuffer =
          makeFramebuffer(camera.width, camera.height, kChannelColor | kChannelNormal | kChannelCoverage);
      return renderLod(s.scene, s.hierarchy, s.surfels, camera, framebuffer, options);
    };
    const auto predicted = [&](const LodStats& stats) {
      return predictFrameCost(options.frameCosts, frameWork(stats, std::uint64_t(camera.width) * camera.height),
                              GeometryDrawer::Raster);
    };
    const double coarsest = predicted(drawn(1e-9));
    // Not more time for more budget, necessarily: a node's triangles may cost less than its prefix.
    for (double limit : {coarsest * 1.5, coarsest * 3.0, coarsest * 10.0}) {
      const LodStats stats = drawn(limit);
      EXPECT_LE(predicted(stats), limit * (1.0 + 1e-9));
      const LodStats again = drawn(limit);
      EXPECT_EQ(again.triangles, stats.triangles) << "deterministic";
      EXPECT_EQ(again.surfels, stats.surfels);
    }
    const LodStats ample = drawn(1e3);
    EXPECT_EQ(ample.surfels, 0u) << "an ample budget refines down to every visible triangle";
    EXPECT_GT(ample.triangles, 0u);
  }
}

TEST(BudgetFeedback, DividesTheBudgetByTheMedianOfTheLastFramesRatiosAboveOne) {
  BudgetFeedback feedback(0.033);
  EXPECT_EQ(feedback.limit(), 0.033);
  feedback.observe(0.010, 0.020);
  EXPECT_DOUBLE_EQ(feedback.limit(), 0.0165) << "frames took twice the prediction: predict half the budget";
  feedback.observe(0.010, std::numeric_limits<double>::quiet_NaN());
  feedback.observe(0.0, 0.010);
  EXPECT_DOUBLE_EQ(feedback.limit(), 0.0165) << "ratios that are not ratios are ignored";
  feedback.observe(0.010, 0.015);
  EXPECT_DOUBLE_EQ(feedback.limit(), 0.033 / 1.75) << "median of 2 and 1.5";
  feedback.observe(0.010, 0.005);
  feedback.observe(0.010, 0.005);
  EXPECT_DOUBLE_EQ(feedback.limit(), 0.033)
      << "median of 2, 1.5, 0.5, 0.5: frames under their predictions never raise it";
  for (int f = 0; f < 5; ++f) feedback.observe(0.010, 0.030);
  EXPECT_DOUBLE_EQ(feedback.limit(), 0.011) << "only the last five frames count";
}

}  // namespace
}  // namespace pbs
