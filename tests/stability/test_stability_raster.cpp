// Numerical stability of the rasterizer (camera.hpp, triangles.hpp, points.hpp, framebuffer.hpp): far
// and scaled scenes, extreme near and far planes, the largest viewport and non-finite input. Each test
// states the behaviour it expects; measured error bounds are in the comments where they are asserted.
#include "stability_checks.hpp"

#include "test_fixtures.hpp"

#include <pbs/raster/camera.hpp>
#include <pbs/raster/points.hpp>
#include <pbs/raster/triangles.hpp>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

namespace pbs {
namespace {

using stability::expectFiniteFramebuffer;
using stability::framebufferBytes;
using stability::sameBytesForOneTwoAndFourThreads;

constexpr ChannelMask kAllChannels = kChannelColor | kChannelPosition | kChannelNormal | kChannelIds;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// A unit quad of two triangles with normals and uvs, and a 9×9 grid of points on it, owning its arrays.
struct QuadInput {
  std::vector<glm::vec3> positions{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  std::vector<glm::vec3> normals{4, glm::vec3(0, 0, 1)};
  std::vector<glm::vec2> uvs{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<std::uint32_t> indices{0, 1, 2, 0, 2, 3};
  std::vector<MeshPart> parts{{0, 6, 0}};
  Texture texture{.name = "checker",
                  .width = 2,
                  .height = 2,
                  .rgba8 = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255}};
  std::vector<SurfaceMaterial> materials{{glm::vec4(1.0f), &texture}};
  std::vector<glm::vec3> points;
  std::vector<glm::vec3> pointNormals;
  std::vector<glm::u8vec4> pointColors;
  glm::dmat4 worldFromObject{1.0};

  QuadInput() {
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i) points.emplace_back(-0.8f + 0.2f * float(i), -0.8f + 0.2f * float(j), 0.0f);
    pointNormals.assign(points.size(), glm::vec3(0, 0, 1));
    pointColors.assign(points.size(), glm::u8vec4(200, 100, 50, 255));
  }
  QuadInput(const QuadInput&) = delete;  // the material points at this object's texture

  TriangleDraw triangles() const {
    return TriangleDraw{.positions = positions,
                        .normals = normals,
                        .uvs = uvs,
                        .indices = indices,
                        .parts = parts,
                        .materials = materials,
                        .worldFromObject = worldFromObject,
                        .nodeId = 1,
                        .instanceId = 2};
  }
  PointSet pointSet(float size) const {
    return PointSet{.positions = points,
                    .normals = pointNormals,
                    .colors = pointColors,
                    .worldFromObject = worldFromObject,
                    .pointSize = size,
                    .nodeId = 3,
                    .instanceId = 4};
  }
};

Framebuffer drawQuad(const QuadInput& input, const Camera& camera, ChannelMask channels,
                     const glm::dvec3& positionOrigin = glm::dvec3(0.0)) {
  Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, channels, positionOrigin);
  const TriangleDraw draw = input.triangles();
  drawTriangles(framebuffer, camera, {&draw, 1});
  return framebuffer;
}

Framebuffer drawQuadPoints(const QuadInput& input, const Camera& camera, ChannelMask channels, float size,
                           const glm::dvec3& positionOrigin = glm::dvec3(0.0)) {
  Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, channels, positionOrigin);
  const PointSet set = input.pointSet(size);
  drawPoints(framebuffer, camera, {&set, 1});
  return framebuffer;
}

std::size_t coveredCount(const Framebuffer& framebuffer) {
  std::size_t count = 0;
  for (std::size_t p = 0; p < framebuffer.pixelCount(); ++p) count += framebuffer.covered(p);
  return count;
}

// ---- Far from the origin and extreme scales ---------------------------------------------------

// A scene moved to `offset` and scaled by `scale`, camera and near/far planes with it.
struct Placement {
  std::string name;
  glm::dvec3 offset;
  double scale;
};
// gtest prints a parameter in test listings (ctest names): its name, not its bytes.
void PrintTo(const Placement& placement, std::ostream* out) { *out << placement.name; }

// The tilted quad and a camera looking at it from 4 units away (times the scale), positions stored
// relative to the placement's offset as captures and renders do.
struct PlacedView {
  Camera camera;
  glm::dmat4 worldFromObject;
};

PlacedView placedView(const Placement& placement) {
  const double s = placement.scale;
  const glm::dvec3 eye = placement.offset + s * glm::dvec3(0.3, 0.2, 4.0);
  const glm::dmat4 view = glm::lookAt(eye, placement.offset, glm::dvec3(0.0, 1.0, 0.0));
  const glm::dmat4 world = glm::rotate(glm::scale(glm::translate(glm::dmat4(1.0), placement.offset), glm::dvec3(s)),
                                       0.5, glm::dvec3(1.0, 0.3, 0.0));
  return {perspectiveCamera(view, glm::radians(50.0), 0.5 * s, 20.0 * s, 96, 64), world};
}

class StabilityFarOrScaledScene : public testing::TestWithParam<Placement> {};

// Expected: the same pixels as the unit scene at the origin, every value finite, the same bytes for
// any thread count. The rasterizer composes projection · view · world in double before rounding, so
// an offset of 1e7 costs ~1e-9 world units, far below the 1/256-pixel snap.
// Measured (Release, x86-64): coverage and ids identical in every case; depth bit-identical except at
// offset 1e7 with scale 1e-3 (2.4e-7, a few float ulps; asserted: 2.5e-7); positions (relative to the
// offset, divided by the scale) within 9.3e-7 of the unit scene's (asserted: 1e-5; the quad is 2 units
// wide); normals within 1e-5.
TEST_P(StabilityFarOrScaledScene, TrianglesMatchTheUnitSceneAtTheOrigin) {
  const Placement& placement = GetParam();
  QuadInput input;
  const PlacedView unitView = placedView({"unit", glm::dvec3(0.0), 1.0});
  input.worldFromObject = unitView.worldFromObject;
  const Framebuffer unit = drawQuad(input, unitView.camera, kChannelPosition | kChannelNormal | kChannelIds);

  const PlacedView placed = placedView(placement);
  input.worldFromObject = placed.worldFromObject;
  const Framebuffer moved = sameBytesForOneTwoAndFourThreads(
      [&] { return drawQuad(input, placed.camera, kChannelPosition | kChannelNormal | kChannelIds, placement.offset); },
      framebufferBytes);
  expectFiniteFramebuffer(moved);
  ASSERT_GT(coveredCount(unit), 1000u);
  EXPECT_EQ(test::coveredPixels(moved), test::coveredPixels(unit));
  double depthError = 0.0, positionError = 0.0, normalError = 0.0;
  for (std::size_t p = 0; p < unit.pixelCount(); ++p) {
    if (!unit.covered(p) || !moved.covered(p)) continue;
    EXPECT_EQ(moved.ids[p], unit.ids[p]);
    depthError = std::max(depthError, double(std::abs(moved.depth[p] - unit.depth[p])));
    const glm::dvec3 position = glm::dvec3(moved.position[p]) / placement.scale;
    positionError = std::max(positionError, glm::length(position - glm::dvec3(unit.position[p])));
    normalError = std::max(normalError, double(glm::length(moved.normal[p] - unit.normal[p])));
  }
  stability::recordMeasured("max_depth_error", depthError);
  stability::recordMeasured("max_position_error", positionError);
  EXPECT_LE(depthError, 2.5e-7);
  EXPECT_LE(positionError, 1e-5);
  EXPECT_LE(normalError, 1e-5);
}

// Expected: points project like vertices, so the splats cover the unit scene's pixels exactly.
// Measured: identical coverage; depth bit-identical except at offset 1e7 with scale 1e-3 (2.4e-7;
// asserted: 2.5e-7).
TEST_P(StabilityFarOrScaledScene, PointsMatchTheUnitSceneAtTheOrigin) {
  const Placement& placement = GetParam();
  QuadInput input;
  const PlacedView unitView = placedView({"unit", glm::dvec3(0.0), 1.0});
  input.worldFromObject = unitView.worldFromObject;
  const Framebuffer unit = drawQuadPoints(input, unitView.camera, kChannelPosition | kChannelIds, 2.0f);
  const PlacedView placed = placedView(placement);
  input.worldFromObject = placed.worldFromObject;
  const Framebuffer moved = sameBytesForOneTwoAndFourThreads(
      [&] { return drawQuadPoints(input, placed.camera, kChannelPosition | kChannelIds, 2.0f, placement.offset); },
      framebufferBytes);
  expectFiniteFramebuffer(moved);
  ASSERT_EQ(coveredCount(unit), 81u * 4u);  // 81 separate 2×2 splats
  EXPECT_EQ(test::coveredPixels(moved), test::coveredPixels(unit));
  double depthError = 0.0;
  for (std::size_t p = 0; p < unit.pixelCount(); ++p) {
    if (!unit.covered(p) || !moved.covered(p)) continue;
    EXPECT_EQ(moved.ids[p], unit.ids[p]);
    depthError = std::max(depthError, double(std::abs(moved.depth[p] - unit.depth[p])));
  }
  stability::recordMeasured("max_depth_error", depthError);
  EXPECT_LE(depthError, 2.5e-7);
}

INSTANTIATE_TEST_SUITE_P(Placements, StabilityFarOrScaledScene,
                         testing::Values(Placement{"Offset1e6", glm::dvec3(1e6, -1e6, 1e6), 1.0},
                                         Placement{"Offset1e7", glm::dvec3(-1e7, 1e7, 1e7), 1.0},
                                         Placement{"Scale1e_6", glm::dvec3(0.0), 1e-6},
                                         Placement{"Scale1e6", glm::dvec3(0.0), 1e6},
                                         Placement{"Offset1e7Scale1e_3", glm::dvec3(1e7, 0.0, -1e7), 1e-3}),
                         [](const auto& info) { return info.param.name; });

// ---- Near plane 1e-6, far plane 1e9 -----------------------------------------------------------

// A 90° camera at the origin looking down −Z with near 1e-6 and far 1e9 (a ratio of 1e15).
Camera extremeCamera() { return perspectiveCamera(glm::dmat4(1.0), glm::radians(90.0), 1e-6, 1e9, 32, 32); }

// The quad scaled to cover the whole view at distance d.
glm::dmat4 quadAt(double distance) {
  return glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.0, -distance)), glm::dvec3(2.0 * distance));
}

// Expected: at every distance from 2e-6 to 9e8 the quad covers all 32×32 pixels with the depth
// windowDepth gives in double, rounded to float. Measured: within 1.7e-8 (asserted: 1.2e-7, two
// float ulps below 1). Float depth resolves distances only while near/d exceeds its ulp: from d ≈ 10
// on, depths are within a few ulps of 1, so only the ordering test below says what then happens.
TEST(StabilityRaster, NearPlane1e_6AndFarPlane1e9GiveFiniteDepthsAtEveryDistance) {
  const Camera camera = extremeCamera();
  QuadInput input;
  double depthError = 0.0;
  for (const double distance : {2e-6, 1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6, 1e8, 9e8}) {
    SCOPED_TRACE(testing::Message() << "distance " << distance);
    input.worldFromObject = quadAt(distance);
    const Framebuffer framebuffer = drawQuad(input, camera, kAllChannels);
    expectFiniteFramebuffer(framebuffer);
    ASSERT_EQ(coveredCount(framebuffer), 32u * 32u);
    const double expected = windowDepth(camera, glm::dvec3(0.0, 0.0, -distance));
    for (std::size_t p = 0; p < framebuffer.pixelCount(); ++p) {
      depthError = std::max(depthError, std::abs(double(framebuffer.depth[p]) - expected));
      ASSERT_NEAR(framebuffer.position[p].z, -distance, distance * 1e-6);
    }
    // The rays through the corner pixels stay finite and unit length, as the ray caster needs.
    for (const auto& [x, y] : {std::pair{0.5, 0.5}, std::pair{31.5, 31.5}}) {
      const Ray ray = windowRay(camera, x, y);
      EXPECT_TRUE(stability::finite(glm::vec3(ray.origin)) && stability::finite(glm::vec3(ray.direction)));
      EXPECT_NEAR(glm::length(ray.direction), 1.0, 1e-12);
    }
  }
  stability::recordMeasured("max_depth_error", depthError);
  EXPECT_LE(depthError, 1.2e-7);
}

// Expected: two quads at d and 2d, the farther drawn first. The nearer wins wherever its float depth
// is smaller; where float cannot tell the two apart, the less test keeps the first (the farther) one:
// z-fighting is decided by submission order, deterministically. Measured: resolved up to d = 1 (depth
// gap 5e-7), tied from d = 100 on; the last resolved distance is recorded as a property.
TEST(StabilityRaster, NearPlane1e_6AndFarPlane1e9OrderSurfacesWhileFloatDepthCanTellThemApart) {
  const Camera camera = extremeCamera();
  QuadInput farQuad, nearQuad;
  double lastResolved = 0.0;
  for (const double distance : {2e-6, 1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6, 4e8}) {
    farQuad.worldFromObject = quadAt(2.0 * distance);
    nearQuad.worldFromObject = quadAt(distance);
    TriangleDraw draws[] = {farQuad.triangles(), nearQuad.triangles()};
    draws[1].nodeId = 9;
    Framebuffer framebuffer = makeFramebuffer(32, 32, kChannelIds);
    drawTriangles(framebuffer, camera, draws);
    const float nearDepth = float(windowDepth(camera, glm::dvec3(0.0, 0.0, -distance)));
    const float farDepth = float(windowDepth(camera, glm::dvec3(0.0, 0.0, -2.0 * distance)));
    const std::uint32_t winner = nearDepth < farDepth ? 9u : 1u;
    if (winner == 9u) lastResolved = distance;
    for (std::size_t p = 0; p < framebuffer.pixelCount(); ++p)
      ASSERT_EQ(framebuffer.ids[p].node, winner) << "distance " << distance;
  }
  stability::recordMeasured("last_resolved_distance", lastResolved);
  EXPECT_GE(lastResolved, 1.0);
}

// Expected: floors spanning z from +1e9 (behind the eye) to −3e9 (beyond the far plane) are clipped at
// both planes; what remains is finite, and its positions lie on the floor near the exact ray hits.
// The floor at y = −5e-7 meets the near plane inside the view. Positions travel in float planes
// relative to the clipped vertices (coordinates up to 1e9), so their error scales with those: measured
// ≤ 1.3 units on a floor reaching 1e9 away, 1e-9 of its extent (asserted: 10 units).
TEST(StabilityRaster, NearPlane1e_6AndFarPlane1e9ClipCrossingTriangles) {
  const Camera camera = extremeCamera();
  for (const float height : {-1.0f, -5e-7f}) {
    SCOPED_TRACE(testing::Message() << "floor at y = " << height);
    QuadInput input;
    input.positions = {{-1e9f, height, 1e9f}, {1e9f, height, 1e9f}, {1e9f, height, -3e9f}, {-1e9f, height, -3e9f}};
    const Framebuffer framebuffer = drawQuad(input, camera, kAllChannels);
    expectFiniteFramebuffer(framebuffer);
    EXPECT_GT(coveredCount(framebuffer), 32u * 7u);
    double worst = 0.0;
    for (std::uint32_t y = 0; y < 32; ++y) {
      for (std::uint32_t x = 0; x < 32; ++x) {
        const std::size_t p = std::size_t(y) * 32 + x;
        if (!framebuffer.covered(p)) continue;
        const Ray ray = windowRay(camera, x + 0.5, y + 0.5);
        const glm::dvec3 hit = ray.origin + (double(height) / ray.direction.y) * ray.direction;
        worst = std::max(worst, glm::length(glm::dvec3(framebuffer.position[p]) - hit));
      }
    }
    stability::recordMeasured(height < -0.5f ? "max_position_error_floor_1" : "max_position_error_floor_5e_7", worst);
    EXPECT_LE(worst, 10.0);
  }
}

// ---- Viewports of 1×1 and 16384×16384 ---------------------------------------------------------

// Expected: a 1×1 viewport holds one sample at (0.5, 0.5): a point of any drawable size on it
// covers it, one beside it does not; a size of 4096 is clamped and still covers the one pixel.
TEST(StabilityRaster, OneByOneViewportDrawsItsOnePixel) {
  const Camera camera = test::windowCamera(1, 1);
  for (const float size : {0.5f, 1.0f, 3.0f, 4096.0f, 1e9f}) {
    for (const bool round : {false, true}) {
      Framebuffer framebuffer = makeFramebuffer(1, 1, kChannelIds);
      const glm::vec3 position(0.5f, 0.5f, -0.5f);
      const PointSet set{.positions = {&position, 1}, .pointSize = size};
      drawPoints(framebuffer, camera, {&set, 1}, PointOptions{round});
      EXPECT_TRUE(framebuffer.covered(0)) << "size " << size;
      EXPECT_EQ(framebuffer.depth[0], 0.5f);
    }
  }
  // The ray through the one sample is the view axis.
  const Ray ray = windowRay(perspectiveCamera(glm::dmat4(1.0), 1.0, 0.1, 10.0, 1, 1), 0.5, 0.5);
  EXPECT_NEAR(ray.direction.z, -1.0, 1e-15);
}

// Expected: the largest viewport (16384², 1 GiB of depth alone; no other channel is allocated to
// keep the test within memory) takes a full-screen sloped quad on every pixel, with window depth
// from the plane within float interpolation error, and a 4096-pixel square splat covers exactly
// 4096² pixels. Window coordinates reach 16384 · 256 = 2^22 in snapped units, well inside the
// rasterizer's integer range. Measured depth error against windowDepth in double on every 64th
// row and 61st column: ≤ 5.3e-8 (asserted: 1e-6 of the [0, 1] range).
TEST(StabilityRaster, LargestViewportCoversEveryPixelWithAccurateDepth) {
  constexpr std::uint32_t kSize = 16384;
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0, 0.0, 3.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const Camera camera = perspectiveCamera(view, glm::radians(60.0), 0.5, 10.0, kSize, kSize);
  QuadInput input;
  input.worldFromObject = glm::rotate(glm::scale(glm::dmat4(1.0), glm::dvec3(4.0)), 0.4, glm::dvec3(1.0, 0.0, 0.0));
  Framebuffer framebuffer = drawQuad(input, camera, 0);
  ASSERT_EQ(coveredCount(framebuffer), std::size_t(kSize) * kSize);
  double depthError = 0.0;
  const glm::dmat4 objectFromWorld = glm::inverse(input.worldFromObject);
  for (std::uint32_t y = 0; y < kSize; y += 64) {
    for (std::uint32_t x = 0; x < kSize; x += 61) {
      // Where the ray through the pixel centre meets the quad's plane (object z = 0).
      const Ray ray = windowRay(camera, x + 0.5, y + 0.5);
      const glm::dvec3 o(objectFromWorld * glm::dvec4(ray.origin, 1.0));
      const glm::dvec3 d(objectFromWorld * glm::dvec4(ray.direction, 0.0));
      const glm::dvec3 hit = ray.origin + (-o.z / d.z) * ray.direction;
      const double expected = windowDepth(camera, hit);
      depthError = std::max(depthError, std::abs(double(framebuffer.depth[std::size_t(y) * kSize + x]) - expected));
    }
  }
  stability::recordMeasured("max_depth_error", depthError);
  EXPECT_LE(depthError, 1e-6);

  clearFramebuffer(framebuffer);
  const Camera window = test::windowCamera(kSize, kSize);
  const glm::vec3 position(5000.0f, 9000.0f, -0.5f);
  const PointSet set{.positions = {&position, 1}, .pointSize = 4096.0f};
  drawPoints(framebuffer, window, {&set, 1});
  EXPECT_EQ(coveredCount(framebuffer), 4096u * 4096u);
  EXPECT_TRUE(framebuffer.covered(std::size_t(9000 - 2048) * kSize + (5000 - 2048)));
  EXPECT_FALSE(framebuffer.covered(std::size_t(9000 - 2049) * kSize + (5000 - 2048)));
}

// ---- NaN and Inf anywhere in the input --------------------------------------------------------

// Where a NaN or Inf goes, and what must come out: nothing drawn, or the clean input's pixels with
// a defined fallback for the attribute (face normal, texel at the origin, zero point normal).
struct NonFiniteCase {
  std::string name;
  std::function<void(QuadInput&, Camera&)> spoil;
  bool drawsNothing;
};
void PrintTo(const NonFiniteCase& c, std::ostream* out) { *out << c.name; }

class StabilityNonFiniteInput : public testing::TestWithParam<NonFiniteCase> {};

Camera quadCamera() {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.2, 0.1, 3.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  return perspectiveCamera(view, glm::radians(60.0), 0.5, 10.0, 48, 40);
}

// Expected: no NaN or Inf in any channel; the coverage of the clean input or none, per case; the same
// bytes for 1, 2 and 4 threads.
TEST_P(StabilityNonFiniteInput, NeverReachesTheFramebuffer) {
  const NonFiniteCase& c = GetParam();
  QuadInput clean;
  const Camera cleanCamera = quadCamera();
  QuadInput input;
  Camera camera = cleanCamera;
  c.spoil(input, camera);
  for (const bool points : {false, true}) {
    SCOPED_TRACE(points ? "points" : "triangles");
    const auto draw = [&](const QuadInput& in, const Camera& cam) {
      return points ? drawQuadPoints(in, cam, kAllChannels, 2.0f) : drawQuad(in, cam, kAllChannels);
    };
    const Framebuffer framebuffer =
        sameBytesForOneTwoAndFourThreads([&] { return draw(input, camera); }, framebufferBytes);
    expectFiniteFramebuffer(framebuffer);
    const Framebuffer expected = draw(clean, cleanCamera);
    ASSERT_GT(coveredCount(expected), 0u);
    EXPECT_EQ(test::coveredPixels(framebuffer), c.drawsNothing ? test::PixelSet{} : test::coveredPixels(expected));
  }
}

void spoilMatrix(glm::dmat4& m, double value) { m[3][1] = value; }

INSTANTIATE_TEST_SUITE_P(
    Cases, StabilityNonFiniteInput,
    testing::Values(
        // Vertex normals: the face normal stands in (pixels unit length, checked by the helper's finiteness).
        NonFiniteCase{"NormalNaN",
                      [](QuadInput& q, Camera&) {
                        q.normals[1].x = kNaN;
                        q.pointNormals[5].y = kNaN;
                      },
                      false},
        NonFiniteCase{"NormalInf",
                      [](QuadInput& q, Camera&) {
                        q.normals[2].z = kInf;
                        q.pointNormals[7].z = -kInf;
                      },
                      false},
        // Texture coordinates: NaN samples the texel at the origin, Inf is clamped; colour stays RGBA8.
        NonFiniteCase{"UvNaN", [](QuadInput& q, Camera&) { q.uvs[0] = glm::vec2(kNaN); }, false},
        NonFiniteCase{"UvInf", [](QuadInput& q, Camera&) { q.uvs[3] = glm::vec2(kInf, -kInf); }, false},
        // Transforms and camera matrices: every clip position is non-finite, nothing is drawn.
        NonFiniteCase{"NodeTransformNaN", [](QuadInput& q, Camera&) { spoilMatrix(q.worldFromObject, kNaN); }, true},
        NonFiniteCase{"NodeTransformInf", [](QuadInput& q, Camera&) { spoilMatrix(q.worldFromObject, kInf); }, true},
        NonFiniteCase{"ViewNaN", [](QuadInput&, Camera& c) { spoilMatrix(c.view, kNaN); }, true},
        NonFiniteCase{"ViewInf", [](QuadInput&, Camera& c) { spoilMatrix(c.view, -kInf); }, true},
        NonFiniteCase{"ProjectionNaN", [](QuadInput&, Camera& c) { c.projection[2][2] = kNaN; }, true},
        NonFiniteCase{"ProjectionInf", [](QuadInput&, Camera& c) { c.projection[0][0] = kInf; }, true}),
    [](const auto& info) { return info.param.name; });

// Expected: a mesh with no triangles (vertices but no indices, or nothing at all) draws nothing and
// leaves every channel cleared.
TEST(StabilityRaster, MeshWithNoTrianglesDrawsNothing) {
  QuadInput input;
  input.indices.clear();
  input.parts = {{0, 0, 0}};
  Framebuffer framebuffer = drawQuad(input, quadCamera(), kAllChannels);
  const std::string cleared = framebufferBytes(makeFramebuffer(48, 40, kAllChannels));
  EXPECT_EQ(framebufferBytes(framebuffer), cleared);
  input.positions.clear();
  input.normals.clear();
  input.uvs.clear();
  input.parts.clear();
  framebuffer = drawQuad(input, quadCamera(), kAllChannels);
  EXPECT_EQ(framebufferBytes(framebuffer), cleared);
}

}  // namespace
}  // namespace pbs
