// The LOD renderer's geometry nodes drawn by rays (EmbreeNodeCaster) rather than the rasterizer: the
// caster against the whole-scene one, its BVH cache, the G-buffer against the rasterizer's up to the
// ray caster's tolerances, surfels composed by depth over ray-cast geometry, determinism, the per-frame
// choice between the two drawers, and `--geometry` on the command line.
#include "cli_scenes.hpp"
#include "gbuffer_agreement.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"
#include "surfeled_scene.hpp"

#include <pbs/raster/orbit_camera.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/embree_caster.hpp>
#include <pbs/scene/embree_node_caster.hpp>
#include <pbs/scene/generate.hpp>
#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/scene_draws.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/lod_geometry.hpp>
#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <numeric>
#include <cmath>

namespace pbs {
namespace {

using test::placed;
using test::tessellatedBox;

constexpr ChannelMask kAllChannels = kChannelColor | kChannelPosition | kChannelNormal | kChannelIds;

Camera orbitAround(const Scene& scene, const Hierarchy& hierarchy, double distance, std::uint32_t width = 256,
                   std::uint32_t height = 256) {
  Bounds box;
  for (std::uint32_t root : scene.roots) box.extend(hierarchy.worldBounds[root]);
  return orbitCamera(box.center(), 0.5 * glm::length(box.size()), Orbit{30.0, 20.0, distance}, width, height);
}

void expectSameGBuffer(const Framebuffer& a, const Framebuffer& b) {
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.color, b.color);
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.ids, b.ids);
}

// ---- EmbreeNodeCaster -----------------------------------------------------------------------------

// A 7 × 7 grid of boxes around a perspective camera: instances behind it, beside it and cut by the near
// plane, so the caster's culling and its footprint of where rays may hit are both exercised.
Scene boxGrid() {
  Scene scene = test::sceneOf(tessellatedBox(6), {});
  for (int i = 0; i < 49; ++i) {
    const glm::dvec3 at(2.5 * (i % 7 - 3), 2.5 * (i / 7 - 3), 0.3 * (i % 3));
    scene.roots.push_back(std::uint32_t(scene.nodes.size()));
    scene.nodes.push_back(Node{"box", placed(at, 0.4 * i, {0.8, 0.6, 0.7}), {}, 0});
  }
  validateScene(scene, "grid");
  return scene;
}

// Asked for every node, the caster draws `--mode embree`'s image to the bit: its top level holds only the
// instances in view, but its frame is centred where the whole scene's is, so every instance sees the same rays.
// Asked for some, it draws only those.
TEST(EmbreeNodeCaster, GivesTheWholeSceneCastersImageOfTheSameNodes) {
  const Scene scene = boxGrid();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const Camera camera =
      perspectiveCamera(glm::lookAt(glm::dvec3(0.3, 0.2, 0.5), glm::dvec3(4.0, 1.0, 0.2), glm::dvec3(0, 1, 0)),
                        glm::radians(60.0), 0.2, 12.0, 160, 100);
  std::vector<std::uint32_t> all(scene.nodes.size());
  std::iota(all.begin(), all.end(), 0u);
  std::size_t inView = 0;
  for (std::uint32_t node : all) inView += !outsideClipVolume(camera, instanceWorldBounds(scene, hierarchy, node));
  ASSERT_GT(inView, 3u);
  ASSERT_LT(inView, all.size()) << "some boxes must be culled";
  EmbreeNodeCaster caster(scene, hierarchy);
  Framebuffer lazy = makeFramebuffer(camera.width, camera.height, kAllChannels);
  caster.render(camera, all, lazy);
  Framebuffer whole = makeFramebuffer(camera.width, camera.height, kAllChannels);
  EmbreeScene(scene, hierarchy).render(camera, whole);
  expectSameGBuffer(lazy, whole);

  std::vector<std::uint32_t> even;  // every other box
  for (std::uint32_t node = 0; node < scene.nodes.size(); node += 2) even.push_back(node);
  Framebuffer some = makeFramebuffer(camera.width, camera.height, kAllChannels);
  caster.render(camera, even, some);
  EXPECT_TRUE(std::none_of(some.ids.begin(), some.ids.end(), [](const PixelIds& ids) {
    return ids != PixelIds{} && ids.node % 2 == 1;
  })) << "nodes not asked for are not drawn";
  std::size_t drawn = 0;
  for (std::size_t pixel = 0; pixel < some.pixelCount(); ++pixel) {
    if (some.ids[pixel] == PixelIds{} || some.ids[pixel] != whole.ids[pixel]) continue;
    ++drawn;
    ASSERT_EQ(some.depth[pixel], whole.depth[pixel]) << "pixel " << pixel;
    ASSERT_EQ(some.color[pixel], whole.color[pixel]) << "pixel " << pixel;
  }
  EXPECT_GT(drawn, 100u) << "the asked nodes' pixels, as the whole scene draws them";
}

TEST(EmbreeNodeCaster, BuildsEachMeshOnceAcrossFrames) {
  // Three meshes: 0 drawn by nodes 0 and 1, 1 by node 2, 2 by node 3, which lies behind the camera.
  Scene scene;
  scene.materials.push_back(Material{"plain", glm::vec4(0.8f, 0.5f, 0.2f, 1.0f), -1});
  for (std::uint32_t n : {8u, 4u, 2u}) scene.meshes.push_back(tessellatedBox(n));
  const std::vector<std::pair<glm::dvec3, std::int32_t>> placements{
      {{0, 0, 0}, 0}, {{3, 0, 0}, 0}, {{-3, 0, 0}, 1}, {{0, 0, 40}, 2}};
  for (const auto& [at, mesh] : placements) {
    scene.roots.push_back(std::uint32_t(scene.nodes.size()));
    scene.nodes.push_back(Node{"box", placed(at, 0.3, {1, 1, 1}), {}, mesh});
  }
  validateScene(scene, "three meshes");
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const Camera camera = perspectiveCamera(glm::lookAt(glm::dvec3(0, 2, 12), glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0)),
                                          glm::radians(60.0), 0.5, 100.0, 96, 64);
  Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, kChannelIds);
  EmbreeNodeCaster caster(scene, hierarchy);
  const auto frame = [&](std::vector<std::uint32_t> nodes) { return caster.render(camera, nodes, framebuffer); };

  EmbreeBuilds builds = frame({0, 1});
  EXPECT_EQ(builds.meshes, 1u) << "two instances, one mesh";
  EXPECT_EQ(builds.triangles, scene.meshes[0].triangleCount());
  EXPECT_TRUE(caster.built(0));
  EXPECT_FALSE(caster.built(1));
  builds = frame({0, 1, 2});
  EXPECT_EQ(builds.meshes, 1u);
  EXPECT_EQ(builds.triangles, scene.meshes[1].triangleCount());
  EXPECT_EQ(frame({2, 1, 0}).meshes, 0u) << "kept across frames";
  EXPECT_EQ(frame({0, 3}).meshes, 0u) << "an instance outside the view builds nothing";
  EXPECT_FALSE(caster.built(2));
  EXPECT_TRUE(caster.drawnBefore(0) && caster.drawnBefore(1));
  EXPECT_FALSE(caster.drawnBefore(2)) << "outside the view: not drawn";
  caster.forget(0);
  EXPECT_FALSE(caster.built(0));
  EXPECT_TRUE(caster.drawnBefore(0)) << "the history stays";

  EmbreeNodeCaster noting(scene, hierarchy);
  noting.noteDrawn(camera, std::vector<std::uint32_t>{0, 3});
  EXPECT_TRUE(noting.drawnBefore(0));
  EXPECT_FALSE(noting.drawnBefore(2)) << "as render: outside the view, not drawn";
  EXPECT_FALSE(noting.built(0)) << "noted, not built";

  // Seeded from a whole-scene caster: everything is there already, and nothing drawn yet.
  const EmbreeScene whole(scene, hierarchy);
  EmbreeNodeCaster seeded(scene, hierarchy, whole);
  EXPECT_TRUE(seeded.built(2));
  EXPECT_FALSE(seeded.drawnBefore(1));
  EXPECT_EQ(seeded.render(camera, std::vector<std::uint32_t>{0, 1, 2}, framebuffer).meshes, 0u);
  EXPECT_TRUE(seeded.drawnBefore(1));
  EXPECT_TRUE(
      std::any_of(framebuffer.ids.begin(), framebuffer.ids.end(), [](const PixelIds& ids) { return ids.node == 2; }));
}

// ---- Geometry nodes by rays in the LOD renderer ------------------------------------------------------

using test::surfeled;
using test::SurfeledScene;

// The task's check: on a city of shared meshes, seen from near to far, the frame drawn with its geometry
// nodes cast by rays is the rasterized frame up to the tolerances the ray caster is held to against the
// rasterizer (gbuffer_agreement.hpp); surfels, drawn the same way over both, count as pixels too. No band:
// in a band a node's surfels lie on its children's triangles, and which of two coincident surfaces wins
// is decided by the last bits of depth in either renderer.
TEST(LodGeometry, RaysAgreeWithTheRasterizerUnderTheSurfels) {
  PBS_SHARED_SCENE(spot, "spot.glb");
  PBS_SHARED_SCENE(teapot, "teapot.glb");
  const SurfeledScene s = test::surfeledCityOf(spot, teapot);
  LodOptions options;
  options.threshold = 48.0;
  options.band = 0.0;
  EmbreeNodeCaster caster(s.scene, s.hierarchy);
  test::AgreementRange range;
  bool mixed = false;  // a frame with both geometry and surfels
  for (double distance : {0.6, 1.2, 2.5}) {
    const Camera camera = orbitAround(s.scene, s.hierarchy, distance, 320, 200);
    constexpr ChannelMask kCompared = kChannelColor | kChannelNormal | kChannelIds;
    Framebuffer raster = makeFramebuffer(camera.width, camera.height, kCompared);
    Framebuffer rays = makeFramebuffer(camera.width, camera.height, kCompared);
    options.geometry = GeometryDrawer::Raster;
    const LodStats rasterStats = renderLod(s.scene, s.hierarchy, s.surfels, camera, raster, options, &caster);
    options.geometry = GeometryDrawer::Rays;
    const LodStats rayStats = renderLod(s.scene, s.hierarchy, s.surfels, camera, rays, options, &caster);
    EXPECT_EQ(rasterStats.geometryDrawer, GeometryDrawer::Raster);
    EXPECT_EQ(rayStats.geometryDrawer, GeometryDrawer::Rays);
    mixed = mixed || (rayStats.nodesGeometry > 0 && rayStats.nodesSurfels > 0);
    range.add(test::compareViews(s.scene, s.hierarchy, camera, raster, rays));
  }
  EXPECT_TRUE(mixed);
  range.print("city, geometry by rays under surfels");
  range.expectWithinThresholds("city");
}

// FrameRenderer::cut is the cut its frames draw: with rays drawing the geometry, the nodes whose rays cost less
// than their surfels descended (fewer surfels than the threshold's cut); with the rasterizer, the threshold's.
TEST(LodGeometry, AFrameRenderersCutIsWhatItsFramesDraw) {
  const SurfeledScene s = surfeled(test::twoIdenticalGroups());
  const Camera camera = orbitAround(s.scene, s.hierarchy, 8.0, 160, 100);
  LodOptions lod;
  lod.descendWhereRaysCheaper = true;
  LodOptions thresholdOnly = lod;
  thresholdOnly.descendWhereRaysCheaper = false;
  const LodDraws threshold = traverseLod(s.scene, s.hierarchy, s.surfels, camera, thresholdOnly);
  ASSERT_GT(threshold.surfelCount, 0u);
  for (const GeometryDrawer drawer : {GeometryDrawer::Rays, GeometryDrawer::Raster}) {
    lod.geometry = drawer;
    FrameRenderer renderer(s.scene, s.hierarchy, {.mode = RenderMode::Surfels, .lod = lod}, camera.width, camera.height,
                           {.surfels = &s.surfels});
    const LodDraws cut = renderer.cut(camera);
    const FrameResult frame = renderer.render(camera);
    EXPECT_EQ(cut.surfelCount, frame.stats.surfels) << geometryDrawerName(drawer);
    EXPECT_EQ(cut.triangles, frame.stats.triangles) << geometryDrawerName(drawer);
    if (drawer == GeometryDrawer::Rays) {
      EXPECT_LT(cut.surfelCount, threshold.surfelCount) << "rays cost less than these boxes' surfels";
    } else {
      EXPECT_EQ(cut.surfelCount, threshold.surfelCount) << "the rasterizer's price is per triangle";
      EXPECT_EQ(cut.geometryNodes, threshold.geometryNodes);
    }
  }
  EXPECT_THROW(FrameRenderer(s.scene, s.hierarchy, {.mode = RenderMode::Exact}, 16, 16).cut(camera), std::logic_error);
}

// A row of 16 groups receding along x, each a 5 × 5 grid of small boxes (2,700 triangles: the group has an array,
// its boxes none). Seen from one end, the near groups are geometry and the far ones prefixes: twenty-five nodes
// of rays each cost more than a few pixels of surfels.
Scene recedingRow() {
  Scene scene;
  scene.materials.push_back(Material{"plain", glm::vec4(0.3f, 0.6f, 0.8f, 1.0f), -1});
  scene.meshes.push_back(tessellatedBox(3));
  scene.nodes.push_back(Node{"row", glm::dmat4(1.0), {}, -1});
  for (int g = 0; g < 16; ++g) {
    const auto group = std::uint32_t(scene.nodes.size());
    scene.nodes[0].children.push_back(group);
    scene.nodes.push_back(Node{"group", glm::translate(glm::dmat4(1.0), glm::dvec3(3.0 * g, 0.0, 0.0)), {}, -1});
    for (int i = 0; i < 25; ++i) {
      scene.nodes[group].children.push_back(std::uint32_t(scene.nodes.size()));
      scene.nodes.push_back(
          Node{"box", placed({0.0, 0.4 * (i % 5 - 2), 0.4 * (i / 5 - 2)}, 0.2 * i, glm::dvec3(0.18)), {}, 0});
    }
  }
  scene.roots = {0};
  validateScene(scene, "receding row");
  return scene;
}

TEST(LodGeometry, TheNearFrameDescentScaleFallsFromOneToZeroOverTheRamp) {
  EXPECT_EQ(nearFrameDescentScale(0.2, 0.35), 1.0);
  EXPECT_EQ(nearFrameDescentScale(0.35, 0.35), 1.0);
  EXPECT_NEAR(nearFrameDescentScale(0.35 + kNearFrameRamp / 4.0, 0.35), 0.75, 1e-12);
  EXPECT_NEAR(nearFrameDescentScale(0.35 + kNearFrameRamp, 0.35), 0.0, 1e-12);
  EXPECT_EQ(nearFrameDescentScale(1.0, 0.35), 0.0);
  EXPECT_EQ(nearFrameDescentScale(1.0, 1.0), 1.0) << "1 turns the rule off";
  EXPECT_EQ(nearFrameDescentScale(std::nan(""), 0.35), 1.0);
}

// Where rays draw a frame that is mostly geometry, the few prefixes left in it are drawn by rays too; a frame of
// prefixes (from afar), and any frame the rasterizer draws, keep their cut.
TEST(LodGeometry, AFrameMostlyOfGeometryIsDrawnByRaysWhole) {
  const SurfeledScene s = surfeled(recedingRow());
  EmbreeNodeCaster caster(s.scene, s.hierarchy);
  LodOptions rule;
  rule.descendWhereRaysCheaper = true;
  rule.geometry = GeometryDrawer::Rays;
  LodOptions off = rule;
  off.raysNearShare = 1.0;
  const auto cut = [&](const Camera& camera, const LodOptions& options) {
    return traverseLodForDrawer(s.scene, s.hierarchy, s.surfels, camera, options, &caster);
  };
  const auto share = [&](const Camera& camera, const LodDraws& draws) {
    const GeometryWork work = geometryWork(s.scene, s.hierarchy, draws.geometryNodes, camera, &caster);
    return nearFrameShare(s.hierarchy, s.surfels, camera, draws, work.boxPixels);
  };
  const glm::dvec3 up(0.0, 1.0, 0.0);
  const Camera near = perspectiveCamera(glm::lookAt(glm::dvec3(-1.5, 0.3, 0.4), glm::dvec3(45.0, 0.0, 0.0), up),
                                        glm::radians(60.0), 0.05, 500.0, 256, 160);
  const LodDraws kept = cut(near, off);
  ASSERT_GT(kept.surfels.size(), 0u) << "the far groups are prefixes without the rule";
  ASSERT_GT(kept.geometryNodes.size(), 25u) << "the near groups are geometry";
  const double nearShare = share(near, kept);
  std::printf("geometry's share of the near frame's cut: %.3f (%zu prefixes, %zu geometry nodes)\n", nearShare,
              kept.surfels.size(), kept.geometryNodes.size());
  EXPECT_GT(nearShare, rule.raysNearShare + kNearFrameRamp);
  const LodDraws whole = cut(near, rule);
  EXPECT_TRUE(whole.surfels.empty());
  EXPECT_EQ(whole.surfelCount, 0u);
  EXPECT_GT(whole.geometryNodes.size(), kept.geometryNodes.size());

  // From afar the row is a line of prefixes: the same cut either way.
  const Camera far = perspectiveCamera(glm::lookAt(glm::dvec3(22.5, 60.0, 400.0), glm::dvec3(22.5, 0.0, 0.0), up),
                                       glm::radians(30.0), 1.0, 1000.0, 256, 160);
  const LodDraws farCut = cut(far, rule);
  ASSERT_GT(farCut.surfels.size(), 0u);
  EXPECT_LT(share(far, farCut), rule.raysNearShare);
  EXPECT_EQ(farCut.surfelCount, cut(far, off).surfelCount);
  EXPECT_EQ(farCut.geometryNodes, cut(far, off).geometryNodes);

  // The rasterizer's price is per triangle: its cut is the threshold's, near or far.
  rule.geometry = off.geometry = GeometryDrawer::Raster;
  EXPECT_EQ(cut(near, rule).surfelCount, cut(near, off).surfelCount);
  EXPECT_GT(cut(near, rule).surfelCount, 0u);
}

// A wall (a mesh without surfels, so always geometry) with a small box in front of it and one behind,
// both drawn as surfels: the one in front shows, the one behind is hidden, whichever drawer drew the wall.
TEST(LodGeometry, SurfelsComposeByDepthOverRayCastGeometry) {
  Scene scene;
  scene.materials.push_back(Material{"plain", glm::vec4(0.6f, 0.6f, 0.6f, 1.0f), -1});
  Mesh wall = tessellatedBox(2);
  for (glm::vec3& p : wall.positions) p *= glm::vec3(4.0f, 4.0f, 0.05f);
  updateMeshBounds(wall);
  scene.meshes.push_back(std::move(wall));
  scene.meshes.push_back(tessellatedBox(2));
  const glm::dmat4 small = glm::scale(glm::dmat4(1.0), glm::dvec3(0.25));
  scene.nodes.push_back(Node{"wall", glm::dmat4(1.0), {}, 0});
  scene.nodes.push_back(Node{"front", glm::translate(glm::dmat4(1.0), {-1.5, 0, 1}) * small, {}, 1});
  scene.nodes.push_back(Node{"behind", glm::translate(glm::dmat4(1.0), {1.5, 0, -1}) * small, {}, 1});
  scene.roots = {0, 1, 2};
  validateScene(scene, "wall");
  const Hierarchy hierarchy = analyzeHierarchy(scene);

  // One array of points facing the camera over the small box's front face, used by both small nodes.
  SceneSurfels surfels;
  SplatArray points;
  points.box = scene.meshes[1].bounds;
  points.coverage = 1.0;
  for (int i = 0; i < 64; ++i) {
    points.positions.emplace_back(-0.9f + 1.8f * float(i % 8) / 7.0f, -0.9f + 1.8f * float(i / 8) / 7.0f, 1.0f);
    points.normals.emplace_back(0.0f, 0.0f, 1.0f);
    points.colors.emplace_back(255, 0, 0, 255);
  }
  points.length = points.positions.size();
  surfels.arrays.push_back(points);
  surfels.arrayOfNode = {kNoSurfels, 0, 0};

  const Camera camera = orthographicCamera(glm::lookAt(glm::dvec3(0, 0, 10), glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0)),
                                           -5, 5, -5, 5, 1, 20, 128, 128);
  const auto pixelOf = [&](const glm::dvec3& world) {
    const glm::dvec3 window = windowFromClip(camera, camera.clipFromWorld() * glm::dvec4(world, 1.0));
    return std::size_t(window.y) * camera.width + std::size_t(window.x);
  };
  EmbreeNodeCaster caster(scene, hierarchy);
  for (const GeometryDrawer drawer : {GeometryDrawer::Rays, GeometryDrawer::Raster}) {
    LodOptions options;
    options.pointSize = 3.0f;
    options.minSizeFactor = 1.0f;
    options.descendExhausted = false;  // the boxes' one-surfel arrays stay surfels
    options.geometry = drawer;
    Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, kChannelIds);
    clearFramebuffer(framebuffer, 0);
    const LodStats stats = renderLod(scene, hierarchy, surfels, camera, framebuffer, options, &caster);
    ASSERT_EQ(stats.geometryDrawer, drawer);
    ASSERT_EQ(stats.nodesGeometry, 1u) << "the wall";
    ASSERT_EQ(stats.nodesSurfels, 2u) << "the small boxes";
    EXPECT_EQ(framebuffer.ids[pixelOf({-1.5, 0, 1})].node, 1u) << "the surfels in front of the wall show";
    EXPECT_EQ(framebuffer.ids[pixelOf({1.5, 0, -1})].node, 0u) << "the wall hides the surfels behind it";
    EXPECT_EQ(framebuffer.ids[pixelOf({0, 3, 0})].node, 0u);
  }
}

TEST(LodGeometry, SameImageForOneAndTwoThreads) {
  const SurfeledScene s = surfeled(test::twoIdenticalGroups(), 1000);
  for (const GeometryDrawer drawer : {GeometryDrawer::Rays, GeometryDrawer::Auto}) {
    std::uint64_t geometryByRays = 0;  // frames whose geometry nodes were cast
    const auto renderWith = [&](int threads) {
      std::vector<std::vector<glm::vec4>> images;
      runWithThreads(threads, [&] {
        FrameOptions options{.mode = RenderMode::Surfels, .lod = {}, .samples = 4};
        options.lod.geometry = drawer;
        options.lod.threshold = 64.0;
        FrameRenderer renderer(s.scene, s.hierarchy, options, 200, 150, {.surfels = &s.surfels});
        for (double distance : {1.5, 3.0, 12.0}) {
          FrameResult frame = renderer.render(orbitAround(s.scene, s.hierarchy, distance, 200, 150));
          geometryByRays += frame.stats.nodesGeometry > 0 && frame.stats.geometryDrawer == GeometryDrawer::Rays;
          images.push_back(std::move(frame.image));
        }
      });
      return images;
    };
    EXPECT_EQ(renderWith(1), renderWith(2)) << geometryDrawerName(drawer);
    if (drawer == GeometryDrawer::Rays) {
      EXPECT_GT(geometryByRays, 0u);
    }
  }
}

// ---- The choice -------------------------------------------------------------------------------------

TEST(LodGeometry, AutoPicksRaysForManySmallTrianglesAndRasterForFewBigOnes) {
  constexpr std::uint64_t kFullHd = 1920 * 1080;
  // Millions of triangles over a fifth of the image, their BVHs built: rays.
  GeometryWork many{.triangles = 5'000'000, .boxPixels = 0.2 * kFullHd, .imagePixels = kFullHd, .unbuiltTriangles = 0};
  EXPECT_EQ(chooseGeometryDrawer(many), GeometryDrawer::Rays);
  // A few thousand triangles filling the image twice over: the rasterizer.
  const GeometryWork few{.triangles = 5'000, .boxPixels = 2.0 * kFullHd, .imagePixels = kFullHd, .unbuiltTriangles = 0};
  EXPECT_EQ(chooseGeometryDrawer(few), GeometryDrawer::Raster);
  EXPECT_EQ(chooseGeometryDrawer(GeometryWork{.imagePixels = kFullHd}), GeometryDrawer::Raster) << "nothing to draw";
  // A BVH still to build is part of what rays cost: enough of it tips the choice.
  const GeometryCosts built = estimateGeometryCosts(many);
  many.unbuiltTriangles = many.triangles;
  EXPECT_GT(estimateGeometryCosts(many).rays, built.rays);
  EXPECT_EQ(estimateGeometryCosts(many).raster, built.raster);
  // Shared by the frames of a path, a build costs each frame its share: a path that declines it on its first
  // frame would decline it on every frame after.
  GeometryWork firstFrame{.triangles = 1'500'000, .boxPixels = 95'000, .imagePixels = kFullHd};
  firstFrame.unbuiltTriangles = 400'000;
  EXPECT_EQ(chooseGeometryDrawer(firstFrame), GeometryDrawer::Raster) << "one view pays the whole build";
  EXPECT_EQ(chooseGeometryDrawer(firstFrame, {}, 24.0), GeometryDrawer::Rays) << "24 frames share it";
  const double whole = estimateGeometryCosts(firstFrame).rays, shared = estimateGeometryCosts(firstFrame, {}, 4.0).rays;
  firstFrame.unbuiltTriangles = 0;
  const double none = estimateGeometryCosts(firstFrame).rays;
  EXPECT_NEAR(shared - none, (whole - none) / 4.0, 1e-12);
  for (double frames : {0.0, -3.0, std::nan("")})  // fewer than one frame (or none said) charges it whole
    EXPECT_EQ(
        estimateGeometryCosts(GeometryWork{.triangles = 10, .imagePixels = kFullHd, .unbuiltTriangles = 10}, {}, frames)
            .rays,
        estimateGeometryCosts(GeometryWork{.triangles = 10, .imagePixels = kFullHd, .unbuiltTriangles = 10}).rays);

  // The same through geometryWork on scenes: a finely tessellated box seen small, a 12-triangle one seen
  // large, each once its BVH is built.
  for (const auto& [tessellation, distance, expected] :
       {std::tuple{300u, 8.0, GeometryDrawer::Rays}, std::tuple{1u, 1.2, GeometryDrawer::Raster}}) {
    const Scene scene = test::sceneOf(tessellatedBox(tessellation), {glm::dmat4(1.0)});
    const Hierarchy hierarchy = analyzeHierarchy(scene);
    const Camera camera = orbitAround(scene, hierarchy, distance, 1920, 1080);
    const std::vector<std::uint32_t> nodes{0};
    EmbreeNodeCaster caster(scene, hierarchy);
    GeometryWork work = geometryWork(scene, hierarchy, nodes, camera, &caster);
    EXPECT_EQ(work.triangles, scene.meshes[0].triangleCount());
    EXPECT_EQ(work.unbuiltTriangles, work.triangles);
    EXPECT_EQ(work.imagePixels, kFullHd);
    EXPECT_GT(work.boxPixels, 0.0);
    EXPECT_LE(work.boxPixels, double(kFullHd));
    Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, 0);
    caster.render(camera, nodes, framebuffer);
    work = geometryWork(scene, hierarchy, nodes, camera, &caster);
    EXPECT_EQ(work.unbuiltTriangles, 0u);
    EXPECT_EQ(chooseGeometryDrawer(work), expected) << tessellation;
  }
}

// A frame's drawer is priced by the frames drawn (or passed over) before it in the same renderer, not by BVHs
// another renderer built: two groups of one mesh's instances, the rasterizer priced at 60 ns a triangle and
// rays at their BVH builds alone. The whole scene (4 instances) goes to rays and builds the mesh; then one
// group (2 instances) goes to rays only once the mesh is drawn: a renderer that starts there takes the
// rasterizer, one that passed over the first view takes rays, to the bit of the one that drew it, and one
// seeded with a whole-scene BVH chooses as one that was not.
TEST(LodGeometry, AFrameIsPricedByTheFramesBeforeItNotByWhatOthersBuilt) {
  const Scene scene = test::twoIdenticalGroups();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const SceneSurfels none;  // no arrays: every visible mesh is geometry
  LodOptions lod;
  lod.frameCosts = FrameCosts::primitives();
  lod.frameCosts.rasterPerTriangle = 60e-9;
  lod.frameCosts.perSurfel = 0.0;
  const Camera whole = orbitAround(scene, hierarchy, 3.0, 160, 120);
  const Camera groupA = perspectiveCamera(glm::lookAt(glm::dvec3(-5, 0, 8), glm::dvec3(-5, 0, 0), glm::dvec3(0, 1, 0)),
                                          glm::radians(40.0), 0.5, 100.0, 160, 120);
  const EmbreeScene prebuilt(scene, hierarchy);
  // One sample a pixel, and four (each pass chooses its drawer, and a passed-over frame makes the same passes).
  for (const std::uint32_t samples : {1u, 4u}) {
    SCOPED_TRACE(std::to_string(samples) + " samples");
    const auto renderer = [&](const EmbreeScene* rays) {
      return FrameRenderer(scene, hierarchy, {.mode = RenderMode::Surfels, .lod = lod, .samples = samples}, 160, 120,
                           {.surfels = &none, .rays = rays});
    };

    FrameRenderer drawing = renderer(nullptr);
    const FrameResult first = drawing.render(whole);
    ASSERT_EQ(first.stats.geometryDrawer, GeometryDrawer::Rays);
    ASSERT_EQ(first.stats.nodesGeometry, 4u);
    const FrameResult second = drawing.render(groupA);
    ASSERT_EQ(second.stats.nodesGeometry, 2u) << "the other group is out of view";
    EXPECT_EQ(second.stats.geometryDrawer, GeometryDrawer::Rays) << "the mesh is built";

    FrameRenderer starting = renderer(nullptr);
    EXPECT_EQ(starting.render(groupA).stats.geometryDrawer, GeometryDrawer::Raster) << "the build is priced";

    FrameRenderer passing = renderer(nullptr);
    passing.passOver(whole);
    const FrameResult passed = passing.render(groupA);
    EXPECT_EQ(passed.stats.geometryDrawer, GeometryDrawer::Rays);
    EXPECT_GT(passed.stats.bvhBuildSeconds, 0.0) << "passing over built nothing";
    EXPECT_TRUE(passed.image == second.image) << "the frame of the run that drew the first";

    FrameRenderer seeded = renderer(&prebuilt);
    EXPECT_EQ(seeded.render(groupA).stats.geometryDrawer, GeometryDrawer::Raster)
        << "another renderer's BVH changes no price";
  }
}

// ---- The command line -------------------------------------------------------------------------------

TEST(LodGeometryCli, RenderTakesGeometryAndReportsTheDrawerAndBvhBuilds) {
  test::ScratchDir scratch;
  const auto [scene, surfels] = test::groupsWithSurfels(scratch);
  const std::string common = "render " + scene + " --surfels " + surfels +
                             " --size 160x120 --orbit 30,20,1.5 --threshold-pixels 8 --frames 2 --json";
  const auto report = [&](const std::string& drawer) {
    const test::CommandResult run = test::runPbs(common + " --geometry " + drawer);
    EXPECT_EQ(run.status, 0) << run.err;
    return nlohmann::json::parse(run.out);
  };
  const nlohmann::json rays = report("rays");
  ASSERT_EQ(rays["frames"].size(), 2u);
  for (const nlohmann::json& frame : rays["frames"]) {
    EXPECT_EQ(frame["geometry"], "rays");
    EXPECT_GT(frame["nodes_geometry"].get<int>(), 0);
    EXPECT_LE(frame["bvh_build_seconds"].get<double>(), frame["geometry_seconds"].get<double>());
  }
  EXPECT_GT(rays["frames"][0]["bvh_build_seconds"].get<double>(), 0.0) << "the first frame builds the mesh's BVH";
  EXPECT_EQ(rays["frames"][1]["bvh_build_seconds"].get<double>(), 0.0) << "the second reuses it";
  const nlohmann::json raster = report("raster");  // named: a temporary in a range-for dies before the loop
  for (const nlohmann::json& frame : raster["frames"]) EXPECT_EQ(frame["geometry"], "raster");
  const nlohmann::json automatic = report("auto");
  EXPECT_TRUE(automatic["frames"][0]["geometry"] == "raster" || automatic["frames"][0]["geometry"] == "rays");
  EXPECT_EQ(test::runPbs(common + " --geometry sideways").status, 2);
}

}  // namespace
}  // namespace pbs
