// Tests of the named camera paths: the orbit as `pbs render` has always made it, the approach into the
// densest region, the closed flythrough loop, and finite, deterministic cameras for any scene size.
#include "cli_scenes.hpp"
#include "test_fixtures.hpp"

#include <pbs/raster/orbit_camera.hpp>
#include <pbs/surfels/camera_paths.hpp>
#include <pbs/surfels/lod_render.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace pbs {
namespace {

struct Analysed {
  Scene scene;
  Hierarchy hierarchy;
};

Analysed analysed(Scene scene) {
  validateScene(scene, "test scene");
  Hierarchy hierarchy = analyzeHierarchy(scene);
  return {std::move(scene), std::move(hierarchy)};
}

Bounds sceneBounds(const Analysed& a) {
  Bounds bounds;
  for (std::uint32_t root : a.scene.roots) bounds.extend(a.hierarchy.worldBounds[root]);
  return bounds;
}

std::vector<PathView> pathOf(CameraPath path, const Analysed& a, std::uint32_t frames, const Orbit& orbit = {}) {
  return cameraPath(path, a.hierarchy, a.scene.roots, orbit, frames, 64, 36);
}

// A flat square of side 2 in the XZ plane (y = 0).
Mesh flatSquare() {
  Mesh mesh;
  mesh.name = "square";
  mesh.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  mesh.indices = {0, 2, 1, 0, 3, 2};
  mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
  mesh.parts.push_back(MeshPart{0, 6, 0});
  updateMeshBounds(mesh);
  return mesh;
}

// root → {dense: eight boxes close together around (10, 0, 0), sparse: one box at (−10, 0, 0)}.
Scene denseAndSparse() {
  Scene scene;
  scene.materials.push_back(Material{"plain", glm::vec4(0.5f), -1});
  scene.meshes.push_back(test::tessellatedBox(10));
  scene.nodes.push_back(Node{"root", glm::dmat4(1.0), {1, 2}, -1});
  scene.nodes.push_back(Node{"sparse", test::placed({-10, 0, 0}, 0.0, glm::dvec3(1.0)), {3}, -1});
  scene.nodes.push_back(Node{"dense", test::placed({10, 0, 0}, 0.0, glm::dvec3(1.0)), {}, -1});
  scene.nodes.push_back(Node{"lonely box", glm::dmat4(1.0), {}, 0});
  for (int i = 0; i < 8; ++i) {
    scene.nodes[2].children.push_back(std::uint32_t(scene.nodes.size()));
    const glm::dvec3 at{(i & 1) ? 1.5 : -1.5, (i & 2) ? 1.5 : -1.5, (i & 4) ? 1.5 : -1.5};
    scene.nodes.push_back(Node{"box", test::placed(at, 0.2 * i, glm::dvec3(0.5)), {}, 0});
  }
  scene.roots = {0};
  return scene;
}

// A 6 × 6 grid of boxes 2 wide, 3 apart: a small city to fly through.
Scene boxGrid() {
  std::vector<glm::dmat4> worlds;
  for (int z = 0; z < 6; ++z)
    for (int x = 0; x < 6; ++x) worlds.push_back(test::placed({3.0 * x, 0, 3.0 * z}, 0.0, glm::dvec3(1.0)));
  return test::sceneOf(test::tessellatedBox(2), worlds);
}

// The box mesh scaled by `scale` and moved by `offset`, as one root.
Scene scaledBox(double scale, glm::dvec3 offset) {
  return test::sceneOf(test::tessellatedBox(2), {test::placed(offset, 0.3, glm::dvec3(scale))});
}

Scene emptyScene() {
  Scene scene;
  scene.nodes.push_back(Node{"nothing", glm::dmat4(1.0), {}, -1});
  scene.roots = {0};
  return scene;
}

bool finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}
bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool sameBits(const PathView& a, const PathView& b) {
  return std::memcmp(&a.camera.view, &b.camera.view, sizeof(glm::dmat4)) == 0 &&
         std::memcmp(&a.camera.projection, &b.camera.projection, sizeof(glm::dmat4)) == 0 &&
         std::memcmp(&a.eye, &b.eye, sizeof(glm::dvec3)) == 0 &&
         std::memcmp(&a.forward, &b.forward, sizeof(glm::dvec3)) == 0 && a.azimuthDegrees == b.azimuthDegrees;
}

constexpr CameraPath kPaths[] = {CameraPath::Orbit, CameraPath::Approach, CameraPath::Flythrough};

TEST(CameraPaths, NamesRoundTrip) {
  for (CameraPath path : kPaths) EXPECT_EQ(cameraPathFromName(cameraPathName(path)), path);
  EXPECT_EQ(cameraPathFromName("orbit"), CameraPath::Orbit);
  EXPECT_EQ(cameraPathFromName("approach"), CameraPath::Approach);
  EXPECT_EQ(cameraPathFromName("flythrough"), CameraPath::Flythrough);
  EXPECT_FALSE(cameraPathFromName("Orbit"));
  EXPECT_FALSE(cameraPathFromName(""));
}

TEST(CameraPaths, OrbitIsTodaysOrbitBitForBit) {
  const Analysed a = analysed(test::twoIdenticalGroups());
  const Bounds bounds = sceneBounds(a);
  const Orbit orbit{17.0, 35.0, 3.0};
  const std::vector<PathView> views = cameraPath(CameraPath::Orbit, a.hierarchy, a.scene.roots, orbit, 7, 320, 200);
  ASSERT_EQ(views.size(), 7u);
  for (std::uint32_t f = 0; f < 7; ++f) {
    // What apps/pbs/orbit_views.cpp's orbitViews computes.
    Orbit step = orbit;
    step.azimuthDegrees += 360.0 * f / 7;
    const Camera expected = orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()), step, 320, 200);
    EXPECT_TRUE(views[f].camera.view == expected.view) << "frame " << f;
    EXPECT_TRUE(views[f].camera.projection == expected.projection) << "frame " << f;
    EXPECT_EQ(views[f].camera.width, 320u);
    EXPECT_EQ(views[f].camera.height, 200u);
    EXPECT_EQ(views[f].azimuthDegrees, step.azimuthDegrees);
    // The eye and direction agree with the camera: the centre lies straight ahead.
    const glm::dvec3 toCenter = glm::normalize(bounds.center() - views[f].eye);
    EXPECT_GT(glm::dot(toCenter, views[f].forward), 1.0 - 1e-12);
    EXPECT_NEAR(glm::length(views[f].eye - bounds.center()), 3.0 * 0.5 * glm::length(bounds.size()), 1e-9);
  }
}

TEST(CameraPaths, ApproachRegionIsTheDenseGroup) {
  const Analysed a = analysed(denseAndSparse());
  const Bounds region = approachRegion(a.hierarchy, a.scene.roots);
  const Bounds& dense = a.hierarchy.worldBounds[2];
  EXPECT_TRUE(region.min == dense.min && region.max == dense.max);
  // Each box of the group is less than a fifth of the scene's diagonal: the descent stops at the group.
  EXPECT_LT(glm::length(a.hierarchy.worldBounds[4].size()),
            kApproachRegionFraction * glm::length(sceneBounds(a).size()));
}

TEST(CameraPaths, ApproachGoesFromOutsideIntoTheRegionLookingAtIt) {
  const Analysed a = analysed(denseAndSparse());
  const Bounds bounds = sceneBounds(a);
  const double radius = 0.5 * glm::length(bounds.size());
  const Bounds region = approachRegion(a.hierarchy, a.scene.roots);
  const glm::dvec3 target = region.center();
  for (const Orbit& orbit : {Orbit{}, Orbit{200.0, -40.0, 1.0}, Orbit{0.0, 90.0, 5.0}}) {
    const std::vector<PathView> views = pathOf(CameraPath::Approach, a, 24, orbit);
    ASSERT_EQ(views.size(), 24u);
    EXPECT_GT(glm::length(views.front().eye - bounds.center()), radius) << "starts outside the bounding sphere";
    const glm::dvec3 last = views.back().eye;
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_GT(last[axis], region.min[axis]) << "ends inside the region";
      EXPECT_LT(last[axis], region.max[axis]) << "ends inside the region";
    }
    double previous = std::numeric_limits<double>::infinity();
    std::vector<double> ratios;
    for (const PathView& view : views) {
      const double distance = glm::length(view.eye - target);
      EXPECT_LT(distance, previous);
      if (std::isfinite(previous)) ratios.push_back(distance / previous);
      previous = distance;
      EXPECT_GT(glm::dot(glm::normalize(target - view.eye), view.forward), 1.0 - 1e-9) << "looks at the target";
      EXPECT_NEAR(glm::length(view.forward), 1.0, 1e-12);
    }
    // Geometric spacing: every step shrinks the distance by the same factor.
    for (double ratio : ratios) EXPECT_NEAR(ratio, ratios.front(), 1e-9);
  }
}

TEST(CameraPaths, FlythroughIsAClosedEvenLoopInsideTheBox) {
  for (const Scene& scene : {boxGrid(), test::twoIdenticalGroups(), denseAndSparse()}) {
    const Analysed a = analysed(scene);
    const Bounds bounds = sceneBounds(a);
    const glm::dvec3 size = bounds.size();
    const double height = std::max(size.y, kFlyFlatHeight * std::max(size.x, size.z));
    const std::vector<PathView> views = pathOf(CameraPath::Flythrough, a, 90);
    ASSERT_EQ(views.size(), 90u);
    std::vector<double> steps;
    for (std::size_t f = 0; f < views.size(); ++f) {
      const glm::dvec3 eye = views[f].eye;
      EXPECT_GT(eye.x, bounds.min.x);
      EXPECT_LT(eye.x, bounds.max.x);
      EXPECT_GT(eye.z, bounds.min.z);
      EXPECT_LT(eye.z, bounds.max.z);
      EXPECT_GE(eye.y, bounds.min.y + kFlyLowHeight * height - 1e-9 * height);
      EXPECT_LE(eye.y, bounds.min.y + kFlyHighHeight * height + 1e-9 * height);
      EXPECT_NEAR(glm::degrees(std::asin(-views[f].forward.y)), kFlyPitchDegrees, 1e-9);
      steps.push_back(glm::length(views[(f + 1) % views.size()].eye - eye));  // the last step closes the loop
    }
    const auto [shortest, longest] = std::minmax_element(steps.begin(), steps.end());
    // Even in arc length; the chords across a narrow ellipse's tight ends are a little shorter.
    EXPECT_LT(*longest / *shortest, 1.02) << "frames evenly spaced, the loop closed";
    // The first frame starts at the lowest point on the +X side, heading toward +Z.
    EXPECT_NEAR(views[0].eye.y, bounds.min.y + kFlyLowHeight * height, 1e-9 * height);
    EXPECT_GT(views[0].forward.z, 0.9);
  }
}

// The triangle-weighted centre of the meshes' boxes in XZ (every instance counted).
glm::dvec2 triangleCentre(const Analysed& a) {
  glm::dvec2 sum(0.0);
  double total = 0.0;
  for (std::uint32_t n : a.hierarchy.preorder) {
    if (a.scene.nodes[n].mesh < 0) continue;
    const double w = double(a.scene.meshes[std::size_t(a.scene.nodes[n].mesh)].triangleCount());
    const glm::dvec3 c = a.hierarchy.worldBounds[n].center();
    sum += w * glm::dvec2(c.x, c.z);
    total += w;
  }
  return sum / total;
}

TEST(CameraPaths, FlythroughCirclesWhereTheTrianglesAre) {
  // Eight boxes around x = 10, one around x = −10: the loop centres on the eight, not on the box.
  const Analysed a = analysed(denseAndSparse());
  const std::vector<PathView> views = pathOf(CameraPath::Flythrough, a, 64);
  glm::dvec2 mean(0.0);
  for (const PathView& view : views) mean += glm::dvec2(view.eye.x, view.eye.z) / double(views.size());
  const glm::dvec2 expected = triangleCentre(a);
  EXPECT_NEAR(mean.x, expected.x, 1e-3);
  EXPECT_NEAR(mean.y, expected.y, 1e-3);
  EXPECT_GT(expected.x, sceneBounds(a).center().x + 5.0);
}

TEST(CameraPaths, FlythroughOfAFlatSceneStaysAboveThePlane) {
  const Analysed a = analysed(test::sceneOf(flatSquare(), {glm::dmat4(1.0)}));
  for (const PathView& view : pathOf(CameraPath::Flythrough, a, 16)) {
    EXPECT_GE(view.eye.y, kFlyLowHeight * kFlyFlatHeight * 2.0 - 1e-12);
    EXPECT_LE(view.eye.y, kFlyHighHeight * kFlyFlatHeight * 2.0 + 1e-12);
  }
}

TEST(CameraPaths, FlythroughLooksAtGeometry) {
  const Analysed a = analysed(boxGrid());
  const SceneSurfels none;
  for (const PathView& view : pathOf(CameraPath::Flythrough, a, 12)) {
    Framebuffer framebuffer = makeFramebuffer(view.camera.width, view.camera.height, 0);
    renderLod(a.scene, a.hierarchy, none, view.camera, framebuffer, LodOptions{});
    std::size_t covered = 0;
    for (std::size_t p = 0; p < framebuffer.pixelCount(); ++p) covered += framebuffer.covered(p) ? 1 : 0;
    // Without a ground the gaps between the boxes show, most where the loop runs along a row.
    EXPECT_GT(covered, framebuffer.pixelCount() / 3)
        << "eye " << view.eye.x << ", " << view.eye.y << ", " << view.eye.z;
  }
}

TEST(CameraPaths, EveryCameraIsFiniteForAnySceneSize) {
  const std::vector<std::pair<std::string, Scene>> scenes = {
      {"flat", test::sceneOf(flatSquare(), {glm::dmat4(1.0)})},
      {"tiny", scaledBox(1e-6, glm::dvec3(0.0))},
      {"huge", scaledBox(1e6, glm::dvec3(0.0))},
      {"far from the origin", scaledBox(1.0, glm::dvec3(1e7, -1e7, 1e7))},
      {"tiny and off the origin", scaledBox(1e-6, glm::dvec3(3.0, 2.0, 1.0))},
      {"empty", emptyScene()},
      {"dense and sparse", denseAndSparse()},
  };
  for (const auto& [name, scene] : scenes) {
    const Analysed a = analysed(scene);
    for (CameraPath path : kPaths) {
      for (std::uint32_t frames : {0u, 1u, 2u, 13u}) {
        const std::vector<PathView> views = pathOf(path, a, frames);
        ASSERT_EQ(views.size(), std::max(1u, frames)) << name << ", " << cameraPathName(path);
        for (const PathView& view : views) {
          const std::string where = name + ", " + cameraPathName(path) + ", " + std::to_string(frames) + " frames";
          EXPECT_TRUE(finite(view.camera.view)) << where;
          EXPECT_TRUE(finite(view.camera.projection)) << where;
          EXPECT_TRUE(finite(view.camera.clipFromWorld())) << where;
          EXPECT_TRUE(finite(view.eye)) << where;
          EXPECT_TRUE(finite(view.forward)) << where;
          EXPECT_NEAR(glm::length(view.forward), 1.0, 1e-9) << where;
          EXPECT_TRUE(std::isfinite(view.azimuthDegrees)) << where;
          // The eye really is where the view matrix puts the camera.
          const glm::dvec3 eyeInView = glm::dvec3(view.camera.view * glm::dvec4(view.eye, 1.0));
          const double scale = std::max(1.0, glm::length(view.eye));
          EXPECT_LT(glm::length(eyeInView), 1e-9 * scale) << where;
        }
      }
    }
  }
}

TEST(CameraPaths, FarFromTheOriginTheSameAsAtTheOrigin) {
  // Working relative to the scene's centre keeps the path's shape when the scene moves away.
  const Analysed here = analysed(scaledBox(1.0, glm::dvec3(0.0)));
  const Analysed there = analysed(scaledBox(1.0, glm::dvec3(1e7, 0.0, -1e7)));
  const glm::dvec3 shift = sceneBounds(there).center() - sceneBounds(here).center();
  for (CameraPath path : {CameraPath::Approach, CameraPath::Flythrough}) {
    const std::vector<PathView> a = pathOf(path, here, 9), b = pathOf(path, there, 9);
    for (std::size_t f = 0; f < a.size(); ++f) {
      EXPECT_LT(glm::length((b[f].eye - shift) - a[f].eye), 1e-6) << cameraPathName(path) << " frame " << f;
      EXPECT_LT(glm::length(b[f].forward - a[f].forward), 1e-6) << cameraPathName(path) << " frame " << f;
    }
  }
}

TEST(CameraPaths, SameCallSameBits) {
  const Analysed a = analysed(denseAndSparse());
  for (CameraPath path : kPaths) {
    const std::vector<PathView> first = pathOf(path, a, 31), second = pathOf(path, a, 31);
    ASSERT_EQ(first.size(), second.size());
    for (std::size_t f = 0; f < first.size(); ++f) EXPECT_TRUE(sameBits(first[f], second[f])) << cameraPathName(path);
  }
}

TEST(CameraPaths, OneFrameIsTheFirstFrame) {
  const Analysed a = analysed(denseAndSparse());
  for (CameraPath path : kPaths) {
    const std::vector<PathView> one = pathOf(path, a, 1), many = pathOf(path, a, 10);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_TRUE(sameBits(one[0], many[0])) << cameraPathName(path);
  }
}

TEST(CameraPaths, EmptySceneCirclesTheUnitSphereAtTheOrigin) {
  const Analysed a = analysed(emptyScene());
  const Orbit orbit{};
  const std::vector<PathView> views = pathOf(CameraPath::Orbit, a, 4, orbit);
  for (const PathView& view : views) EXPECT_NEAR(glm::length(view.eye), orbit.distance, 1e-12);
  for (const PathView& view : pathOf(CameraPath::Flythrough, a, 8)) EXPECT_LT(glm::length(view.eye), 1.0);
}

TEST(CameraPaths, FigureDrawsEveryPathAndListsItsViews) {
  test::ScratchDir scratch;
  const std::string scene = test::groupsFile(scratch);
  const test::CommandResult made =
      test::runPbs("figure paths " + scene + " -o '" + (scratch / "fig").string() + "' --size 96x64 --frames 5");
  ASSERT_EQ(made.status, 0) << made.err;
  EXPECT_TRUE(std::filesystem::is_regular_file(scratch / "fig" / "paths.png"));
  const nlohmann::json json = nlohmann::json::parse(test::readFile(scratch / "fig" / "paths.json"));
  for (CameraPath path : kPaths) {
    const nlohmann::json& views = json["paths"][cameraPathName(path)]["views"];
    ASSERT_EQ(views.size(), 5u) << cameraPathName(path);
    EXPECT_EQ(views[0]["eye"].size(), 3u);
    EXPECT_EQ(views[0]["forward"].size(), 3u);
  }
  EXPECT_EQ(json["image"]["panel_width"], 96);
}

}  // namespace
}  // namespace pbs
