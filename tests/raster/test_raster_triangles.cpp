// Tests of cameras and drawTriangles: projection conventions, coverage and the fill rule, clipping,
// culling, interpolation, texturing, channels, depth order, streaming and thread determinism.
#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/raster/thread_arena.hpp"
#include "pbs/raster/triangles.hpp"
#include "reference_rasterizer.hpp"

#include "test_fixtures.hpp"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <thread>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

namespace pbs {
namespace {

using test::coveredPixels;
using test::PixelSet;
using test::windowCamera;

// A camera at `eye` looking at the origin, y up.
Camera lookCamera(const glm::dvec3& eye, bool perspective, std::uint32_t width, std::uint32_t height) {
  const glm::dmat4 view = glm::lookAt(eye, glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  const double aspect = double(width) / height;
  return perspective ? perspectiveCamera(view, glm::radians(60.0), 0.5, 20.0, width, height)
                     : orthographicCamera(view, -2.0 * aspect, 2.0 * aspect, -2.0, 2.0, 0.5, 20.0, width, height);
}

// A mesh owning its arrays, drawn as one part with one material unless told otherwise.
struct TestMesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<std::uint32_t> indices;
  std::vector<MeshPart> parts;
  std::vector<SurfaceMaterial> materials{SurfaceMaterial{}};

  void addTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    for (const glm::vec3& p : {a, b, c}) {
      indices.push_back(std::uint32_t(positions.size()));
      positions.push_back(p);
    }
  }

  TriangleDraw draw(const glm::dmat4& worldFromObject = glm::dmat4(1.0)) {
    if (parts.empty()) parts.push_back({0, std::uint32_t(indices.size()), 0});
    TriangleDraw draw;
    draw.positions = positions;
    draw.normals = normals;
    draw.uvs = uvs;
    draw.indices = indices;
    draw.parts = parts;
    draw.materials = materials;
    draw.worldFromObject = worldFromObject;
    return draw;
  }
};

Framebuffer render(const Camera& camera, TestMesh& mesh, ChannelMask channels, const TriangleOptions& options = {},
                   const glm::dmat4& worldFromObject = glm::dmat4(1.0)) {
  Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, channels);
  const TriangleDraw draw = mesh.draw(worldFromObject);
  drawTriangles(framebuffer, camera, {&draw, 1}, options);
  return framebuffer;
}

// A point at window position (x, y) and depth d for windowCamera.
glm::vec3 at(float x, float y, float depth = 0.5f) { return {x, y, -depth}; }

double distanceToRay(const Ray& ray, const glm::dvec3& p) {
  const glm::dvec3 d = p - ray.origin;
  return glm::length(d - glm::dot(d, ray.direction) * ray.direction);
}

// ---- Cameras ----------------------------------------------------------------------------------

TEST(Camera, PixelCentreConvention) {
  const Camera camera = windowCamera(8, 4);
  // World (x, y) is window (x, y) here, so the centre of pixel (2, 1) is (2.5, 1.5) and row 0 is on top.
  const glm::dvec3 window = windowFromClip(camera, camera.clipFromWorld() * glm::dvec4(2.5, 1.5, -0.25, 1.0));
  EXPECT_DOUBLE_EQ(window.x, 2.5);
  EXPECT_DOUBLE_EQ(window.y, 1.5);
  EXPECT_DOUBLE_EQ(window.z, 0.25);
  // A y-up camera puts the world's top at row 0.
  const Camera up = orthographicCamera(glm::dmat4(1.0), 0.0, 8.0, 0.0, 4.0, 0.0, 1.0, 8, 4);
  EXPECT_DOUBLE_EQ(windowFromClip(up, up.clipFromWorld() * glm::dvec4(2.5, 3.5, -0.5, 1.0)).y, 0.5);
  // A triangle covering exactly that pixel centre draws exactly that pixel.
  TestMesh mesh;
  mesh.addTriangle(at(2.4f, 1.4f), at(2.7f, 1.4f), at(2.4f, 1.7f));
  EXPECT_EQ(coveredPixels(render(camera, mesh, 0)), (PixelSet{{2, 1}}));
}

TEST(Camera, ProjectUnprojectRoundTrips) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  for (const bool perspective : {false, true}) {
    const Camera camera = lookCamera({1.0, 2.0, 5.0}, perspective, 320, 200);
    EXPECT_EQ(camera.isOrthographic(), !perspective);
    for (int i = 0; i < 100; ++i) {
      const glm::dvec3 world(coordinate(random), coordinate(random), coordinate(random));
      const glm::dvec3 window = windowFromClip(camera, camera.clipFromWorld() * glm::dvec4(world, 1.0));
      const Ray ray = windowRay(camera, window.x, window.y);
      EXPECT_NEAR(glm::length(ray.direction), 1.0, 1e-12);
      EXPECT_LT(distanceToRay(ray, world), 1e-9);
      EXPECT_GT(glm::dot(world - ray.origin, ray.direction), 0.0);  // in front of the ray's origin
      EXPECT_NEAR(windowDepth(camera, world), window.z, 1e-12);
      if (!perspective) {
        EXPECT_NEAR(windowDepth(camera, ray.origin), 0.0, 1e-9);  // starts on the near plane
      }
    }
    if (perspective) {
      EXPECT_LT(glm::distance(windowRay(camera, 3.0, 4.0).origin, glm::dvec3(1.0, 2.0, 5.0)), 1e-12);
    }
  }
}

// Depth as rasterized equals windowDepth of the surface point seen through the pixel centre, up to
// float and the snapping of vertices to 1/256 pixel (a shift of the plane by a fraction of that).
TEST(Camera, WindowDepthAgreesWithRasterizedDepth) {
  for (const bool perspective : {false, true}) {
    const Camera camera = lookCamera({0.5, 1.0, 4.0}, perspective, 64, 48);
    TestMesh mesh;  // a tilted plane through the origin
    const glm::vec3 a(-3, -2, -1.5f), b(3, -2, -1.5f), c(3, 2, 1.0f), d(-3, 2, 1.0f);
    mesh.addTriangle(a, b, c);
    mesh.addTriangle(a, c, d);
    const Framebuffer framebuffer = render(camera, mesh, 0);
    const glm::dvec3 normal = glm::normalize(glm::cross(glm::dvec3(b - a), glm::dvec3(c - a)));
    int checked = 0;
    for (std::uint32_t y = 0; y < camera.height; ++y) {
      for (std::uint32_t x = 0; x < camera.width; ++x) {
        const std::size_t pixel = std::size_t(y) * camera.width + x;
        if (!framebuffer.covered(pixel)) continue;
        const auto surfaceDepth = [&](double wx, double wy) {
          const Ray ray = windowRay(camera, wx, wy);
          const double t = glm::dot(glm::dvec3(a) - ray.origin, normal) / glm::dot(ray.direction, normal);
          return windowDepth(camera, ray.origin + t * ray.direction);
        };
        const double expected = surfaceDepth(x + 0.5, y + 0.5);
        const double perPixel =
            std::abs(surfaceDepth(x + 1.5, y + 0.5) - expected) + std::abs(surfaceDepth(x + 0.5, y + 1.5) - expected);
        EXPECT_NEAR(framebuffer.depth[pixel], expected, 2e-6 + perPixel / 32.0);
        ++checked;
      }
    }
    EXPECT_GT(checked, 1000);
  }
}

// ---- Coverage and the fill rule ---------------------------------------------------------------

TEST(TriangleCoverage, FullScreenQuadCoversEveryPixelOnce) {
  const Camera camera = windowCamera(37, 23);
  TestMesh mesh;
  mesh.addTriangle(at(0, 0), at(37, 0), at(37, 23));
  mesh.addTriangle(at(0, 0), at(37, 23), at(0, 23));
  std::vector<int> count(camera.width * camera.height, 0);
  for (std::uint32_t first = 0; first < 6; first += 3) {
    mesh.parts = {{first, 3, 0}};
    const Framebuffer framebuffer = render(camera, mesh, kChannelIds);
    for (std::size_t pixel = 0; pixel < count.size(); ++pixel) {
      if (!framebuffer.covered(pixel)) continue;
      ++count[pixel];
      EXPECT_EQ(framebuffer.ids[pixel].primitive, first / 3);
    }
  }
  for (std::size_t pixel = 0; pixel < count.size(); ++pixel) ASSERT_EQ(count[pixel], 1) << "pixel " << pixel;
}

// Triangles fanned around a point share all inner edges at arbitrary slopes: drawn one at a time,
// no pixel is covered twice, and the disc they tile has no holes.
TEST(TriangleCoverage, SharedEdgesOfAFanCoverEachPixelOnce) {
  const Camera camera = windowCamera(64, 64);
  std::mt19937 random(3);
  std::uniform_real_distribution<float> radius(20.0f, 30.0f), jitter(-0.3f, 0.3f);
  const glm::vec3 centre = at(31.3f, 32.7f);
  std::vector<glm::vec3> rim;
  constexpr int kSpokes = 29;
  for (int i = 0; i < kSpokes; ++i) {
    const float angle = 6.2831853f * (i + jitter(random)) / kSpokes;
    const float r = radius(random);
    rim.push_back(centre + glm::vec3(r * std::cos(angle), r * std::sin(angle), 0.0f));
  }
  std::vector<int> count(64 * 64, 0);
  for (int i = 0; i < kSpokes; ++i) {
    TestMesh mesh;
    mesh.addTriangle(centre, rim[i], rim[(i + 1) % kSpokes]);
    const Framebuffer framebuffer = render(camera, mesh, 0);
    for (std::size_t pixel = 0; pixel < count.size(); ++pixel) count[pixel] += framebuffer.covered(pixel);
  }
  for (std::size_t pixel = 0; pixel < count.size(); ++pixel) {
    ASSERT_LE(count[pixel], 1) << "pixel " << pixel;
    const glm::vec2 p(pixel % 64 + 0.5f, pixel / 64 + 0.5f);
    if (glm::distance(p, glm::vec2(centre)) < 19.0f) {
      ASSERT_EQ(count[pixel], 1) << "hole at pixel " << pixel;
    }
  }
}

TEST(TriangleCoverage, KnownCoverageSet) {
  const Camera camera = windowCamera(8, 8);
  TestMesh mesh;
  // Centres strictly inside x + y < 4 are covered; those on the slanted edge x + y = 4 belong to
  // no top or left edge and are not.
  mesh.addTriangle(at(0, 0), at(4, 0), at(0, 4));
  EXPECT_EQ(coveredPixels(render(camera, mesh, 0)), (PixelSet{{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {0, 2}}));
}

TEST(TriangleCoverage, TopLeftRuleOnPixelCentreAlignedEdges) {
  const Camera camera = windowCamera(8, 8);
  // A square whose edges run through pixel centres: its left column and top row are in, its
  // right column and bottom row out, and the diagonal is shared without overlap.
  TestMesh mesh;
  mesh.addTriangle(at(1.5f, 1.5f), at(5.5f, 1.5f), at(5.5f, 5.5f));
  mesh.addTriangle(at(1.5f, 1.5f), at(5.5f, 5.5f), at(1.5f, 5.5f));
  PixelSet expected;
  for (int y = 1; y < 5; ++y)
    for (int x = 1; x < 5; ++x) expected.emplace(x, y);
  const Framebuffer framebuffer = render(camera, mesh, kChannelIds);
  EXPECT_EQ(coveredPixels(framebuffer), expected);
  // Centres on the shared diagonal go to the triangle for which it is a left edge (interior to
  // its right): the upper one.
  EXPECT_EQ(framebuffer.ids[2 * 8 + 2].primitive, 0u);
  EXPECT_EQ(framebuffer.ids[3 * 8 + 2].primitive, 1u);
  // Vertex order does not matter: the same square wound the other way covers the same pixels.
  TestMesh reversed;
  reversed.addTriangle(at(1.5f, 1.5f), at(5.5f, 5.5f), at(5.5f, 1.5f));
  reversed.addTriangle(at(1.5f, 1.5f), at(1.5f, 5.5f), at(5.5f, 5.5f));
  EXPECT_EQ(coveredPixels(render(camera, reversed, 0)), expected);
  // A horizontal edge through centres is drawn when the triangle lies below it (top edge) only.
  TestMesh below, above;
  below.addTriangle(at(0.5f, 2.5f), at(6.5f, 2.5f), at(0.5f, 6.5f));
  above.addTriangle(at(0.5f, 2.5f), at(6.5f, 2.5f), at(0.5f, 0.1f));
  EXPECT_TRUE(coveredPixels(render(camera, below, 0)).count({1, 2}));
  EXPECT_FALSE(coveredPixels(render(camera, above, 0)).count({1, 2}));
}

// Random triangles, many of them with vertices on the pixel grid, against the reference.
TEST(TriangleCoverage, MatchesReferenceRasterizer) {
  std::mt19937 random(11);
  std::uniform_int_distribution<int> grid(-8, 8 * 2 * 40);
  for (const bool perspective : {false, true}) {
    const Camera camera = perspective ? lookCamera({0.0, 0.0, 3.0}, true, 40, 30) : windowCamera(40, 30);
    std::uniform_real_distribution<float> spread(-1.5f, 1.5f);
    std::vector<std::uint8_t> expected(camera.width * camera.height);
    for (int i = 0; i < 300; ++i) {
      std::array<glm::vec3, 3> triangle;
      for (glm::vec3& p : triangle)
        p = perspective ? glm::vec3(spread(random), spread(random), spread(random))
                        : at(grid(random) / 16.0f, grid(random) / 16.0f);
      std::fill(expected.begin(), expected.end(), 0);
      test::referenceCoverage(camera, glm::dmat4(1.0), triangle, expected);
      TestMesh mesh;
      mesh.addTriangle(triangle[0], triangle[1], triangle[2]);
      const Framebuffer framebuffer = render(camera, mesh, 0);
      for (std::size_t pixel = 0; pixel < expected.size(); ++pixel)
        ASSERT_EQ(framebuffer.covered(pixel), expected[pixel] != 0) << "triangle " << i << ", pixel " << pixel;
    }
  }
}

TEST(TriangleCoverage, TinyAndHugeViewports) {
  TestMesh mesh;
  mesh.addTriangle({-1, -1, 0}, {1, -1, 0}, {1, 1, 0});
  mesh.addTriangle({-1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
  const glm::dmat4 identity(1.0);
  for (const auto& [width, height] : {std::pair{1u, 1u}, {16384u, 3u}, {5u, 16384u}}) {
    const Camera camera = orthographicCamera(identity, -1, 1, -1, 1, -1, 1, width, height);
    const Framebuffer framebuffer = render(camera, mesh, kChannelIds);
    for (std::size_t pixel = 0; pixel < framebuffer.pixelCount(); ++pixel) ASSERT_TRUE(framebuffer.covered(pixel));
  }
}

// ---- Clipping, culling, degenerate input ------------------------------------------------------

TEST(TriangleClipping, NearAndFarPlanes) {
  const Camera camera = perspectiveCamera(glm::dmat4(1.0), glm::radians(90.0), 1.0, 10.0, 48, 32);
  const auto check = [&](const std::array<glm::vec3, 3>& triangle, bool expectPixels) {
    std::vector<std::uint8_t> expected(camera.width * camera.height, 0);
    test::referenceCoverage(camera, glm::dmat4(1.0), triangle, expected);
    TestMesh mesh;
    mesh.addTriangle(triangle[0], triangle[1], triangle[2]);
    const Framebuffer framebuffer = render(camera, mesh, kChannelPosition);
    int covered = 0;
    for (std::size_t pixel = 0; pixel < expected.size(); ++pixel) {
      ASSERT_EQ(framebuffer.covered(pixel), expected[pixel] != 0) << "pixel " << pixel;
      if (!framebuffer.covered(pixel)) continue;
      ++covered;
      EXPECT_GE(framebuffer.depth[pixel], 0.0f);
      EXPECT_LE(framebuffer.depth[pixel], 1.0f);
      // What is drawn lies between the planes (eye z in [−10, −1]).
      EXPECT_LE(framebuffer.position[pixel].z, -1.0f + 1e-4f);
      EXPECT_GE(framebuffer.position[pixel].z, -10.0f - 1e-3f);
    }
    EXPECT_EQ(covered > 0, expectPixels);
  };
  check({glm::vec3(-1, -1, -0.5f), glm::vec3(1, -1, -0.5f), glm::vec3(0, 1, -4)}, true);      // crosses near
  check({glm::vec3(-1, -1, 0.5f), glm::vec3(1, -1, 0.5f), glm::vec3(0, 1, 2)}, false);        // behind the eye
  check({glm::vec3(-1, -1, -0.5f), glm::vec3(1, -1, -0.5f), glm::vec3(0, 1, 3)}, false);      // behind the near plane
  check({glm::vec3(-1, -1, -5), glm::vec3(1, -1, -5), glm::vec3(0, 1, -30)}, true);           // crosses far
  check({glm::vec3(-1, -1, -15), glm::vec3(1, -1, -15), glm::vec3(0, 1, -30)}, false);        // beyond far
  check({glm::vec3(-50, -1, -0.1f), glm::vec3(50, -1, -0.1f), glm::vec3(0, 30, -30)}, true);  // both
}

TEST(TriangleCulling, BackFacesAndMirroredTransforms) {
  const Camera camera = lookCamera({0.0, 0.0, 5.0}, false, 32, 32);
  TestMesh front, back;  // counter-clockwise seen from +z (the camera) is the front
  front.addTriangle({-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
  back.addTriangle({-1, -1, 0}, {0, 1, 0}, {1, -1, 0});
  const TriangleOptions cull{.cullBackFaces = true};
  const glm::dmat4 mirror = glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 1.0, 1.0));
  EXPECT_FALSE(coveredPixels(render(camera, front, 0, cull)).empty());
  EXPECT_TRUE(coveredPixels(render(camera, back, 0, cull)).empty());
  EXPECT_FALSE(coveredPixels(render(camera, back, 0)).empty());  // culling is off by default
  // Mirrored, the front triangle turns clockwise on screen yet stays a front face.
  EXPECT_FALSE(coveredPixels(render(camera, front, 0, cull, mirror)).empty());
  EXPECT_TRUE(coveredPixels(render(camera, back, 0, cull, mirror)).empty());
}

// A draw's own sides (TriangleDraw::sides): front or back alone, mirrored or not, and with the options'
// back-face culling on top (back alone then draws nothing).
TEST(TriangleCulling, EachDrawsSidesAlone) {
  const Camera camera = lookCamera({0.0, 0.0, 5.0}, false, 32, 32);
  TestMesh front, back;
  front.addTriangle({-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
  back.addTriangle({-1, -1, 0}, {0, 1, 0}, {1, -1, 0});
  const auto covers = [&](TestMesh& mesh, FaceSides sides, const glm::dmat4& world, const TriangleOptions& options) {
    Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, 0);
    TriangleDraw draw = mesh.draw(world);
    draw.sides = sides;
    drawTriangles(framebuffer, camera, {&draw, 1}, options);
    return !coveredPixels(framebuffer).empty();
  };
  const glm::dmat4 mirror = glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 1.0, 1.0));
  for (const glm::dmat4& world : {glm::dmat4(1.0), mirror}) {
    EXPECT_TRUE(covers(front, FaceSides::front, world, {}));
    EXPECT_FALSE(covers(back, FaceSides::front, world, {}));
    EXPECT_FALSE(covers(front, FaceSides::back, world, {}));
    EXPECT_TRUE(covers(back, FaceSides::back, world, {}));
    EXPECT_TRUE(covers(front, FaceSides::both, world, {}) && covers(back, FaceSides::both, world, {}));
    EXPECT_FALSE(covers(front, FaceSides::none, world, {}) || covers(back, FaceSides::none, world, {}));
    EXPECT_FALSE(covers(back, FaceSides::back, world, {.cullBackFaces = true}));
  }
}

TEST(TriangleDegenerate, DrawNothingAndNeverNaN) {
  const Camera camera = windowCamera(16, 16);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  TestMesh mesh;
  mesh.addTriangle(at(1, 1), at(8, 8), at(15, 15));          // collinear
  mesh.addTriangle(at(2, 3), at(2, 3), at(9, 12));           // repeated vertex
  mesh.addTriangle(at(4, 4), at(4.001f, 4), at(4, 4.001f));  // snaps to a point
  mesh.addTriangle(at(1, 1), at(nan, 8), at(15, 1));
  mesh.addTriangle(at(1, 1), at(inf, 8), at(15, 1));
  mesh.indices.insert(mesh.indices.end(), {0, 1, 1000});  // index out of range
  Framebuffer framebuffer = render(camera, mesh, kChannelColor | kChannelPosition | kChannelNormal | kChannelIds);
  EXPECT_TRUE(coveredPixels(framebuffer).empty());
  // A sliver thinner than a pixel but not degenerate still yields finite, unit normals.
  TestMesh sliver;
  sliver.addTriangle(at(0, 3.5f), at(16, 3.5f), at(16, 3.52f));
  sliver.normals.assign(3, glm::vec3(0.0f));  // no direction to interpolate: the face normal serves
  framebuffer = render(camera, sliver, kChannelNormal | kChannelPosition);
  ASSERT_FALSE(coveredPixels(framebuffer).empty());
  for (std::size_t pixel = 0; pixel < framebuffer.pixelCount(); ++pixel) {
    if (!framebuffer.covered(pixel)) continue;
    EXPECT_NEAR(glm::length(framebuffer.normal[pixel]), 1.0f, 1e-5f);
    EXPECT_TRUE(std::isfinite(framebuffer.position[pixel].x));
  }
}

// ---- Attributes -------------------------------------------------------------------------------

// Perspective-correct positions lie on the drawn plane and on the ray through the pixel centre (up
// to the snapping of vertices to 1/256 pixel); affine interpolation would miss it by pixels here.
TEST(TriangleAttributes, PerspectiveCorrectPositionOnAnalyticPlane) {
  const Camera camera = lookCamera({0.0, 0.5, 3.0}, true, 64, 48);
  const glm::dvec3 origin(10.0, -20.0, 30.0);
  Framebuffer framebuffer = makeFramebuffer(64, 48, kChannelPosition | kChannelNormal, origin);
  TestMesh mesh;
  const glm::vec3 a(-4, -2, -6), b(4, -2, -6), c(4, 1, 1.5f), d(-4, 1, 1.5f);
  mesh.addTriangle(a, b, c);
  mesh.addTriangle(a, c, d);
  const glm::vec3 up = glm::normalize(glm::cross(b - a, c - a));
  mesh.normals.assign(mesh.positions.size(), up);
  const TriangleDraw draw = mesh.draw();
  drawTriangles(framebuffer, camera, {&draw, 1});
  int checked = 0;
  for (std::uint32_t y = 0; y < 48; ++y) {
    for (std::uint32_t x = 0; x < 64; ++x) {
      const std::size_t pixel = std::size_t(y) * 64 + x;
      if (!framebuffer.covered(pixel)) continue;
      const glm::dvec3 world = glm::dvec3(framebuffer.position[pixel]) + origin;
      EXPECT_NEAR(glm::dot(world - glm::dvec3(a), glm::dvec3(up)), 0.0, 1e-4);
      const Ray ray = windowRay(camera, x + 0.5, y + 0.5);
      const double pixelSize = glm::distance(world, ray.origin) * 2.0 * std::tan(glm::radians(30.0)) / 48.0;
      EXPECT_LT(distanceToRay(ray, world), pixelSize / 64.0);
      EXPECT_LT(glm::distance(framebuffer.normal[pixel], up), 1e-5f);
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

// World positions and inverse-transpose normals under a non-uniform, mirroring instance transform.
TEST(TriangleAttributes, TransformedPositionsAndNormals) {
  const Camera camera = lookCamera({0.0, 0.0, 5.0}, false, 32, 32);
  TestMesh mesh;
  mesh.addTriangle({-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
  const glm::vec3 slanted = glm::normalize(glm::vec3(1, 0, 1));
  mesh.normals.assign(3, slanted);
  const glm::dmat4 world = glm::scale(glm::dmat4(1.0), glm::dvec3(-2.0, 1.0, 0.5));
  const Framebuffer framebuffer = render(camera, mesh, kChannelPosition | kChannelNormal, {}, world);
  const glm::vec3 expected = glm::normalize(glm::vec3(-0.5f, 0.0f, 2.0f));  // inverse transpose of the scale
  int checked = 0;
  for (std::size_t pixel = 0; pixel < framebuffer.pixelCount(); ++pixel) {
    if (!framebuffer.covered(pixel)) continue;
    EXPECT_LT(glm::distance(framebuffer.normal[pixel], expected), 1e-5f);
    EXPECT_NEAR(framebuffer.position[pixel].z, 0.0f, 1e-5f);
    EXPECT_LE(std::abs(framebuffer.position[pixel].x), 2.0f + 1e-4f);
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

// The wrap modes by definition, to check the sampler against.
int wrapTexel(int i, int size, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge: return std::clamp(i, 0, size - 1);
    case TextureWrap::MirroredRepeat: {
      const int period = ((i % (2 * size)) + 2 * size) % (2 * size);
      return period < size ? period : 2 * size - 1 - period;
    }
    case TextureWrap::Repeat: break;
  }
  return ((i % size) + size) % size;
}

TEST(TriangleTexture, WrapModesOnACheckerQuad) {
  const Camera camera = windowCamera(8, 8);
  Texture texture;
  texture.width = 2;
  texture.height = 2;
  texture.magFilter = TextureFilter::Nearest;
  const std::array<glm::u8vec4, 4> texels = {glm::u8vec4(255, 0, 0, 255), glm::u8vec4(0, 255, 0, 255),
                                             glm::u8vec4(0, 0, 255, 255), glm::u8vec4(255, 255, 255, 255)};
  texture.rgba8 = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
  // uv runs from −1 to 2 across the window, so every texel coordinate lies well inside a texel.
  TestMesh mesh;
  mesh.addTriangle(at(0, 0), at(8, 0), at(8, 8));
  mesh.addTriangle(at(0, 0), at(8, 8), at(0, 8));
  const auto uvAt = [](const glm::vec3& p) { return glm::vec2(-1.0f + 3.0f * p.x / 8.0f, -1.0f + 3.0f * p.y / 8.0f); };
  for (const glm::vec3& p : mesh.positions) mesh.uvs.push_back(uvAt(p));
  mesh.materials = {SurfaceMaterial{glm::vec4(1.0f), &texture}};
  for (const TextureWrap wrap : {TextureWrap::Repeat, TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat}) {
    texture.wrapS = texture.wrapT = wrap;
    const Framebuffer framebuffer = render(camera, mesh, kChannelColor);
    for (int y = 0; y < 8; ++y) {
      for (int x = 0; x < 8; ++x) {
        const glm::vec2 uv = uvAt({x + 0.5f, y + 0.5f, 0.0f});
        const int s = wrapTexel(int(std::floor(uv.x * 2.0f)), 2, wrap);
        const int t = wrapTexel(int(std::floor(uv.y * 2.0f)), 2, wrap);
        EXPECT_EQ(framebuffer.color[y * 8 + x], texels[t * 2 + s])
            << "wrap " << int(wrap) << ", pixel " << x << "," << y;
      }
    }
  }
}

TEST(TriangleTexture, BilinearFilterAndBaseColour) {
  const Camera camera = windowCamera(4, 4);
  Texture texture;
  texture.width = 2;
  texture.height = 1;
  texture.wrapS = texture.wrapT = TextureWrap::ClampToEdge;
  texture.rgba8 = {0, 0, 0, 255, 255, 255, 255, 255};
  TestMesh mesh;
  mesh.addTriangle(at(0, 0), at(4, 0), at(0, 4));
  mesh.uvs.assign(3, glm::vec2(0.5f, 0.5f));  // halfway between the two texel centres
  mesh.materials = {SurfaceMaterial{glm::vec4(1.0f, 0.5f, 1.0f, 1.0f), &texture}};
  Framebuffer framebuffer = render(camera, mesh, kChannelColor);
  EXPECT_EQ(framebuffer.color[0], glm::u8vec4(128, 64, 128, 255));
  // Untextured: the base colour alone, rounded; a texture on a framebuffer without colour costs nothing.
  mesh.materials = {SurfaceMaterial{glm::vec4(0.2f, 0.4f, 0.6f, 1.0f), nullptr}};
  framebuffer = render(camera, mesh, kChannelColor);
  EXPECT_EQ(framebuffer.color[0], glm::u8vec4(51, 102, 153, 255));
  EXPECT_EQ(framebuffer.color[15], glm::u8vec4(0));  // not covered
}

// ---- Channels, depth order, streaming, threads --------------------------------------------------

TEST(TriangleChannels, OnlyRequestedChannelsExist) {
  const Camera camera = windowCamera(16, 16);
  TestMesh mesh;
  mesh.addTriangle(at(0, 0), at(16, 0), at(0, 16));
  const Framebuffer depthOnly = render(camera, mesh, 0);
  EXPECT_EQ(coveredPixels(depthOnly).size(), 120u);  // centres with x + y ≤ 14
  EXPECT_TRUE(depthOnly.color.empty());
  EXPECT_TRUE(depthOnly.position.empty());
  EXPECT_TRUE(depthOnly.normal.empty());
  EXPECT_TRUE(depthOnly.ids.empty());
  const Framebuffer ids = render(camera, mesh, kChannelIds);
  EXPECT_TRUE(ids.color.empty() && ids.position.empty() && ids.normal.empty());
  EXPECT_EQ(ids.ids[0], (PixelIds{0, 0, 0}));
  EXPECT_EQ(ids.ids[15], PixelIds{});
  EXPECT_FLOAT_EQ(depthOnly.depth[0], 0.5f);
  EXPECT_EQ(depthOnly.depth[15], kClearDepth);
}

TEST(TriangleDepth, LessTestAndSubmissionOrderForTies) {
  const Camera camera = windowCamera(8, 8);
  TestMesh mesh;
  mesh.addTriangle(at(0, 0, 0.5f), at(8, 0, 0.5f), at(0, 8, 0.5f));
  mesh.addTriangle(at(0, 0, 0.5f), at(8, 0, 0.5f), at(0, 8, 0.5f));     // the same depth: loses
  mesh.addTriangle(at(0, 0, 0.7f), at(8, 0, 0.7f), at(0, 8, 0.7f));     // behind: loses
  mesh.addTriangle(at(0, 4, 0.25f), at(8, 4, 0.25f), at(0, 8, 0.25f));  // in front: wins its pixels
  const Framebuffer framebuffer = render(camera, mesh, kChannelIds);
  EXPECT_EQ(framebuffer.ids[0].primitive, 0u);
  EXPECT_FLOAT_EQ(framebuffer.depth[0], 0.5f);
  EXPECT_EQ(framebuffer.ids[5 * 8 + 1].primitive, 3u);
  EXPECT_FLOAT_EQ(framebuffer.depth[5 * 8 + 1], 0.25f);
  // Across separate draws in one call the order holds as well, and node and instance ids come along.
  TestMesh other = mesh;
  TriangleDraw draws[2] = {mesh.draw(), other.draw()};
  draws[0].nodeId = 3;
  draws[1].nodeId = 4;
  draws[1].instanceId = 9;
  Framebuffer both = makeFramebuffer(8, 8, kChannelIds);
  drawTriangles(both, camera, draws);
  EXPECT_EQ(both.ids[0], (PixelIds{3, 0, 0}));
}

// Ties between the three ways a tile meets its triangles (tile_bins.hpp): a triangle in that tile alone
// (copied into its bin), one in a few tiles (its id) and one in more than kMaxBinnedTiles (the large
// bin every tile scans). At equal depth the earliest submitted wins, in every submission order.
TEST(TriangleDepth, SubmissionOrderForTiesAcrossBinKinds) {
  const Camera camera = windowCamera(320, 320);                    // 5 × 5 tiles of 64 pixels
  const glm::vec3 sole[3] = {at(4, 4), at(20, 4), at(4, 20)};      // tile (0, 0) only
  const glm::vec3 shared[3] = {at(0, 0), at(100, 0), at(0, 100)};  // tiles (0 … 1, 0 … 1)
  const glm::vec3 large[3] = {at(0, 0), at(640, 0), at(0, 640)};   // all 25 tiles
  const glm::vec3* kinds[3] = {sole, shared, large};
  int order[3] = {0, 1, 2};
  do {
    TestMesh mesh;
    for (int kind : order) mesh.addTriangle(kinds[kind][0], kinds[kind][1], kinds[kind][2]);
    const Framebuffer framebuffer = render(camera, mesh, kChannelIds);
    const auto primitiveOf = [&](int kind) { return std::uint32_t(std::find(order, order + 3, kind) - order); };
    // Pixel (10, 10) lies in all three; (70, 10) in the shared and the large one; (200, 10) in the large one.
    EXPECT_EQ(framebuffer.ids[10 * 320 + 10].primitive, 0u);
    EXPECT_EQ(framebuffer.ids[10 * 320 + 70].primitive, std::min(primitiveOf(1), primitiveOf(2)));
    EXPECT_EQ(framebuffer.ids[10 * 320 + 200].primitive, primitiveOf(2));
  } while (std::next_permutation(order, order + 3));
}

// Each pixel's attributes come from its own triangle where a chunk of setup holds as many spans as
// triangles (one-triangle draws: the shading records name their span relative to the chunk's first,
// shading_records.hpp), mirrored draws among them (the raster order swaps their vertices).
TEST(TriangleShading, ManyOneTriangleDrawsEachShadeTheirOwnPixels) {
  constexpr int kColumns = 60, kRows = 50;  // 3,000 draws: more than one chunk's 2,048 source triangles
  const Camera camera = windowCamera(6 * kColumns, 6 * kRows);
  TestMesh mesh;
  mesh.addTriangle(at(0, 0), at(5, 0), at(0, 5));
  std::vector<TriangleDraw> draws;
  for (int d = 0; d < kColumns * kRows; ++d) {
    const glm::dvec3 cell(6.0 * (d % kColumns), 6.0 * (d / kColumns), 0.0);
    glm::dmat4 world = glm::translate(glm::dmat4(1.0), cell);
    // Odd draws mirrored about x = 2.5: the triangle (5, 0), (0, 0), (5, 5), wound the other way.
    if (d % 2 == 1) world = glm::scale(glm::translate(world, glm::dvec3(5.0, 0.0, 0.0)), glm::dvec3(-1.0, 1.0, 1.0));
    draws.push_back(mesh.draw(world));
    draws.back().nodeId = std::uint32_t(d);
  }
  Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, kChannelPosition | kChannelIds);
  drawTriangles(framebuffer, camera, draws);
  int wrong = 0;
  for (int d = 0; d < kColumns * kRows; ++d) {
    // Pixel (2, 1) of each cell lies inside both windings; its centre is (2.5, 1.5) in the cell.
    const int x = 6 * (d % kColumns) + 2, y = 6 * (d / kColumns) + 1;
    const std::size_t pixel = std::size_t(y) * camera.width + std::size_t(x);
    const glm::vec3 expected(float(x) + 0.5f, float(y) + 0.5f, -0.5f);
    wrong +=
        framebuffer.ids[pixel].node != std::uint32_t(d) || glm::length(framebuffer.position[pixel] - expected) > 1e-3f;
  }
  EXPECT_EQ(wrong, 0);
}

// Random overlapping triangles with every channel, textured and not, some crossing the near plane.
struct RandomScene {
  TestMesh plain, textured;
  Texture texture;

  explicit RandomScene(int triangles, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f), unit(0.0f, 1.0f);
    texture.width = texture.height = 4;
    for (int i = 0; i < 4 * 4 * 4; ++i) texture.rgba8.push_back(std::uint8_t(random()));
    for (int i = 0; i < triangles; ++i) {
      TestMesh& mesh = i % 3 == 0 ? textured : plain;
      const glm::vec3 centre(coordinate(random), coordinate(random), coordinate(random) * 1.5f);
      const float size = 0.05f + 0.6f * unit(random) * unit(random);
      for (int k = 0; k < 3; ++k) {
        mesh.positions.push_back(centre + size * glm::vec3(coordinate(random), coordinate(random), coordinate(random)));
        mesh.normals.push_back(glm::vec3(coordinate(random), coordinate(random), coordinate(random)));
        mesh.uvs.emplace_back(coordinate(random), coordinate(random));
        mesh.indices.push_back(std::uint32_t(mesh.indices.size()));
      }
    }
    plain.materials = {SurfaceMaterial{glm::vec4(0.3f, 0.6f, 0.9f, 1.0f), nullptr}};
    textured.materials = {SurfaceMaterial{glm::vec4(1.0f, 0.8f, 0.6f, 1.0f), &texture}};
  }

  void drawInto(Framebuffer& framebuffer, const Camera& camera, int threads) {
    TriangleDraw draws[2] = {plain.draw(), textured.draw(glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, 0, 0)))};
    draws[1].nodeId = 1;
    runWithThreads(threads, [&] { drawTriangles(framebuffer, camera, draws); });
  }

  Framebuffer draw(const Camera& camera, int threads) {
    Framebuffer framebuffer =
        makeFramebuffer(camera.width, camera.height, kChannelColor | kChannelPosition | kChannelNormal | kChannelIds);
    drawInto(framebuffer, camera, threads);
    return framebuffer;
  }
};

template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expectIdentical(const Framebuffer& a, const Framebuffer& b) {
  EXPECT_TRUE(sameBytes(a.depth, b.depth));
  EXPECT_TRUE(sameBytes(a.color, b.color));
  EXPECT_TRUE(sameBytes(a.position, b.position));
  EXPECT_TRUE(sameBytes(a.normal, b.normal));
  EXPECT_TRUE(sameBytes(a.ids, b.ids));
}

TEST(TriangleDeterminism, SameBytesWithOneTwoAndSevenThreads) {
  RandomScene scene(4000, 5);
  for (const bool perspective : {false, true}) {
    const Camera camera = lookCamera({0.3, 0.2, 3.0}, perspective, 300, 200);
    const Framebuffer one = scene.draw(camera, 1);
    EXPECT_GT(coveredPixels(one).size(), 10000u);
    for (std::size_t pixel = 0; pixel < one.pixelCount(); ++pixel) {
      if (!one.covered(pixel)) continue;
      ASSERT_TRUE(std::isfinite(one.position[pixel].x) && std::isfinite(one.normal[pixel].x));
      ASSERT_NEAR(glm::length(one.normal[pixel]), 1.0f, 1e-4f);
    }
    expectIdentical(one, scene.draw(camera, 2));
    expectIdentical(one, scene.draw(camera, 7));
  }
}

// Meshes of tens of thousands of triangles: vertex projection scans a span's indices and window
// box in parallel pieces (of 2^14), near (attributes per vertex) and far away (the span defers
// its attributes to the few triangles that cover a pixel centre).
TEST(TriangleDeterminism, LargeMeshesScannedInPiecesGiveTheSameBytes) {
  RandomScene scene(60000, 11);
  for (const double distance : {3.0, 150.0}) {
    SCOPED_TRACE("camera at distance " + std::to_string(distance));
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0.1, 0.1, distance), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
    const Camera camera = perspectiveCamera(view, glm::radians(60.0), 0.5, 1000.0, 300, 200);
    const Framebuffer one = scene.draw(camera, 1);
    EXPECT_GT(coveredPixels(one).size(), distance < 10.0 ? 20000u : 4u);
    expectIdentical(one, scene.draw(camera, 2));
    expectIdentical(one, scene.draw(camera, 7));
  }
}

// A thread keeps its last draw call's batch buffers for its next: what a big draw with every channel
// left in them never shows in a smaller draw with other channels, nor the other way round. Each side runs
// on a thread of its own, whose first call finds no buffers.
TEST(TriangleDeterminism, BuffersLeftByEarlierDrawsNeverShow) {
  RandomScene big(60000, 11), small(4000, 5);
  const Camera camera = lookCamera({0.3, 0.2, 3.0}, true, 300, 200);
  const auto drawSmall = [&] {
    Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, kChannelColor);
    small.drawInto(framebuffer, camera, 2);
    return framebuffer;
  };
  Framebuffer fresh, afterBig, bigAfterSmall, bigFresh;
  std::thread([&] { fresh = drawSmall(); }).join();
  std::thread([&] {
    big.draw(camera, 2);
    afterBig = drawSmall();
    bigAfterSmall = big.draw(camera, 2);
  }).join();
  std::thread([&] { bigFresh = big.draw(camera, 2); }).join();
  EXPECT_GT(coveredPixels(fresh).size(), 10000u);
  expectIdentical(fresh, afterBig);
  expectIdentical(bigFresh, bigAfterSmall);
}

// More triangles than one batch (2^18) in one call equal the same triangles in several calls.
TEST(TriangleStreaming, OneHugeCallEqualsSmallerCalls) {
  constexpr std::uint32_t kTriangles = 300000;
  TestMesh mesh;
  std::mt19937 random(9);
  std::uniform_real_distribution<float> coordinate(0.0f, 64.0f), offset(-1.5f, 1.5f), depth(0.1f, 0.9f);
  for (std::uint32_t i = 0; i < kTriangles; ++i) {
    const glm::vec3 centre = at(coordinate(random), coordinate(random), depth(random));
    mesh.addTriangle(centre + glm::vec3(offset(random), offset(random), 0.0f),
                     centre + glm::vec3(offset(random), offset(random), 0.0f),
                     centre + glm::vec3(offset(random), offset(random), 0.0f));
  }
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0, 0, 1));
  const Camera camera = windowCamera(64, 64);
  const Framebuffer whole = render(camera, mesh, kChannelPosition | kChannelNormal | kChannelIds);
  Framebuffer pieces = makeFramebuffer(64, 64, kChannelPosition | kChannelNormal | kChannelIds);
  const TriangleDraw all = mesh.draw();
  for (std::uint32_t first = 0; first < kTriangles; first += 70000) {
    const MeshPart part{first * 3, std::min(70000u, kTriangles - first) * 3, 0};
    TriangleDraw draw = all;
    draw.parts = {&part, 1};
    drawTriangles(pieces, camera, {&draw, 1});
  }
  EXPECT_EQ(coveredPixels(whole).size(), 64u * 64u);
  expectIdentical(whole, pieces);
}

// ---- Clearing --------------------------------------------------------------------------------

TEST(FramebufferClear, ClearsDepthAndTheChannelsAskedFor) {
  Framebuffer framebuffer = makeFramebuffer(4, 3, kAllChannels);
  const auto dirty = [&] {
    std::fill(framebuffer.depth.begin(), framebuffer.depth.end(), 0.25f);
    std::fill(framebuffer.color.begin(), framebuffer.color.end(), glm::u8vec4(9));
    std::fill(framebuffer.position.begin(), framebuffer.position.end(), glm::vec3(7.0f));
    std::fill(framebuffer.normal.begin(), framebuffer.normal.end(), glm::vec3(0.0f, 1.0f, 0.0f));
    std::fill(framebuffer.ids.begin(), framebuffer.ids.end(), PixelIds{1, 2, 3});
  };
  dirty();
  clearFramebuffer(framebuffer, 0);
  for (std::size_t pixel = 0; pixel < framebuffer.pixelCount(); ++pixel) {
    EXPECT_EQ(framebuffer.depth[pixel], kClearDepth);
    EXPECT_EQ(framebuffer.color[pixel], glm::u8vec4(9));
    EXPECT_EQ(framebuffer.position[pixel], glm::vec3(7.0f));
    EXPECT_EQ(framebuffer.ids[pixel], (PixelIds{1, 2, 3}));
  }
  dirty();
  clearFramebuffer(framebuffer, kChannelColor | kChannelIds);
  EXPECT_EQ(framebuffer.depth[5], kClearDepth);
  EXPECT_EQ(framebuffer.color[5], glm::u8vec4(0));
  EXPECT_EQ(framebuffer.ids[5], PixelIds{});
  EXPECT_EQ(framebuffer.position[5], glm::vec3(7.0f));
  EXPECT_EQ(framebuffer.normal[5], glm::vec3(0.0f, 1.0f, 0.0f));
  dirty();
  clearFramebuffer(framebuffer);
  EXPECT_EQ(framebuffer.position[11], glm::vec3(0.0f));
  EXPECT_EQ(framebuffer.normal[11], glm::vec3(0.0f));
  EXPECT_EQ(framebuffer.color[11], glm::u8vec4(0));
}

TEST(FramebufferClear, ResizeKeepsTheChannelsAndSizesThem) {
  Framebuffer framebuffer = makeFramebuffer(0, 0, kChannelColor | kChannelNormal);
  for (const auto& [width, height] : {std::pair{5u, 7u}, std::pair{3u, 2u}, std::pair{16u, 9u}}) {
    resizeFramebuffer(framebuffer, width, height);
    EXPECT_EQ(framebuffer.width, width);
    EXPECT_EQ(framebuffer.height, height);
    EXPECT_EQ(framebuffer.depth.size(), std::size_t(width) * height);
    EXPECT_EQ(framebuffer.color.size(), std::size_t(width) * height);
    EXPECT_EQ(framebuffer.normal.size(), std::size_t(width) * height);
    EXPECT_TRUE(framebuffer.position.empty() && framebuffer.ids.empty());
  }
}

// The capture clears depth alone between views: over whatever an earlier view left, a draw gives
// the same depth, and the same channels wherever a pixel is covered, as into a cleared framebuffer.
TEST(FramebufferClear, DepthAloneGivesTheSameCoveredPixels) {
  RandomScene scene(4000, 5);
  const Camera first = lookCamera({0.3, 0.2, 3.0}, false, 300, 200);
  const Camera second = lookCamera({-5.0, 2.5, 5.0}, true, 300, 200);
  const Framebuffer cleared = scene.draw(second, 2);
  Framebuffer reused = scene.draw(first, 2);
  clearFramebuffer(reused, 0);
  scene.drawInto(reused, second, 2);
  EXPECT_TRUE(sameBytes(cleared.depth, reused.depth));
  std::size_t covered = 0, stale = 0;
  for (std::size_t pixel = 0; pixel < cleared.pixelCount(); ++pixel) {
    if (!cleared.covered(pixel)) {
      stale += reused.position[pixel] != glm::vec3(0.0f);
      continue;
    }
    ++covered;
    ASSERT_EQ(std::memcmp(&cleared.position[pixel], &reused.position[pixel], sizeof(glm::vec3)), 0);
    ASSERT_EQ(std::memcmp(&cleared.normal[pixel], &reused.normal[pixel], sizeof(glm::vec3)), 0);
    ASSERT_EQ(cleared.color[pixel], reused.color[pixel]);
    ASSERT_EQ(cleared.ids[pixel], reused.ids[pixel]);
  }
  EXPECT_GT(covered, 10000u);
  EXPECT_GT(stale, 0u);  // the first view's values are still there where the second drew nothing
}

TEST(TriangleInput, MismatchedFramebufferIsRefused) {
  TestMesh mesh;
  mesh.addTriangle(at(0, 0), at(1, 0), at(0, 1));
  const TriangleDraw draw = mesh.draw();
  Framebuffer framebuffer = makeFramebuffer(8, 8, kChannelColor);
  EXPECT_THROW(drawTriangles(framebuffer, windowCamera(8, 4), {&draw, 1}), std::invalid_argument);
  framebuffer.color.clear();
  EXPECT_THROW(drawTriangles(framebuffer, windowCamera(8, 8), {&draw, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace pbs
