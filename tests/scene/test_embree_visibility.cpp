// The Embree ray caster against analytic answers, and against the rasterizer (drawSceneTriangles)
// on the shared scenes and on synthetic instanced scenes: the check of the rasterizer's visibility.
#include "pbs/raster/box_view.hpp"
#include "pbs/raster/supersampling.hpp"
#include "pbs/raster/thread_arena.hpp"
#include "pbs/scene/embree_caster.hpp"
#include "pbs/scene/load_scene.hpp"
#include "pbs/scene/scene_draws.hpp"
#include "gbuffer_agreement.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pbs {
namespace {

using test::AgreementRange;
using test::compareViews;
using test::sceneOf;

using test::quadMesh;

glm::dmat4 lookFrom(const glm::dvec3& eye, const glm::dvec3& target) {
  return glm::lookAt(eye, target, glm::dvec3(0, 1, 0));
}

// Where the ray meets the plane z = planeZ (world), or nothing when it runs parallel.
std::optional<glm::dvec3> hitPlaneZ(const Ray& ray, double planeZ) {
  if (ray.direction.z == 0.0) return std::nullopt;
  const double t = (planeZ - ray.origin.z) / ray.direction.z;
  if (t < 0.0) return std::nullopt;
  return ray.origin + t * ray.direction;
}

constexpr ChannelMask kAllChannels = kChannelColor | kChannelPosition | kChannelNormal | kChannelIds;

// Renders the quad moved by `shift` with an orthographic and a perspective camera and checks every
// pixel against the analytic intersection of windowRay with its plane.
void checkQuadAgainstAnalyticRays(const glm::dvec3& shift) {
  const Scene scene = sceneOf(quadMesh(), {glm::translate(glm::dmat4(1.0), shift)});
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const EmbreeScene embree(scene, hierarchy);

  const glm::dmat4 view = lookFrom(shift + glm::dvec3(0.3, -0.2, 4.0), shift + glm::dvec3(0.1, -0.4, 0.0));  // tilted
  const std::vector<Camera> cameras{
      orthographicCamera(view, -2.0, 2.0, -1.5, 1.5, 1.0, 9.0, 97, 73),
      perspectiveCamera(view, glm::radians(50.0), 0.5, 20.0, 97, 73),
  };
  for (const Camera& camera : cameras) {
    Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, kAllChannels, shift + glm::dvec3(1, 2, 3));
    embree.render(camera, framebuffer);
    std::uint64_t covered = 0;
    for (std::uint32_t py = 0; py < camera.height; ++py) {
      for (std::uint32_t px = 0; px < camera.width; ++px) {
        const std::size_t pixel = std::size_t(py) * camera.width + px;
        const auto hit = hitPlaneZ(windowRay(camera, px + 0.5, py + 0.5), shift.z);
        const glm::dvec2 local = hit ? glm::dvec2(*hit - shift) : glm::dvec2(9.0);
        // Embree intersects in float: a pixel centre within a few float steps of an edge could go
        // either way.
        const double margin = std::min(1.0 - std::abs(local.x), 1.0 - std::abs(local.y));
        if (std::abs(margin) < 1e-5 || std::abs(local.x - local.y) < 1e-5) continue;
        ASSERT_EQ(framebuffer.covered(pixel), margin > 0.0) << px << "," << py;
        if (margin < 0.0) {
          EXPECT_EQ(framebuffer.ids[pixel], PixelIds{});
          EXPECT_EQ(framebuffer.color[pixel], glm::u8vec4(0));
          continue;
        }
        ++covered;
        EXPECT_NEAR(framebuffer.depth[pixel], windowDepth(camera, *hit), 1e-6);
        EXPECT_EQ(framebuffer.ids[pixel], (PixelIds{0, 0, local.y < local.x ? 0u : 1u}));
        EXPECT_EQ(framebuffer.color[pixel], glm::u8vec4(51, 102, 153, 255));
        EXPECT_LT(glm::distance(glm::dvec3(framebuffer.position[pixel]), *hit - framebuffer.positionOrigin), 1e-5);
        EXPECT_LT(glm::distance(framebuffer.normal[pixel], glm::vec3(0, 0, 1)), 1e-6f);
      }
    }
    EXPECT_GT(covered, camera.width * camera.height / 8);
  }
}

TEST(EmbreeCaster, QuadMatchesAnalyticRaysForBothProjections) { checkQuadAgainstAnalyticRays({0.25, -0.5, 0.0}); }

// Embree works in float: far from the world origin only its origin-relative frame keeps the digits.
TEST(EmbreeCaster, QuadFarFromTheOriginKeepsItsPrecision) { checkQuadAgainstAnalyticRays({3e6 + 0.25, -2e6, 1e6}); }

TEST(EmbreeCaster, HitsOutsideTheNearFarRangeAreSkipped) {
  // Two instances of the quad, at z = 0 (node 0) and z = −2 (node 1), seen from z = 5.
  const Scene scene = sceneOf(quadMesh(), {glm::dmat4(1.0), glm::translate(glm::dmat4(1.0), {0.0, 0.0, -2.0})});
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const EmbreeScene embree(scene, hierarchy);
  const glm::dmat4 view = lookFrom({0, 0, 5}, {0, 0, 0});
  const auto nodeSeen = [&](double near, double far) {
    const Camera camera = orthographicCamera(view, -0.5, 0.5, -0.5, 0.5, near, far, 8, 8);
    Framebuffer framebuffer = makeFramebuffer(8, 8, kChannelIds);
    embree.render(camera, framebuffer);
    for (std::size_t pixel = 1; pixel < framebuffer.pixelCount(); ++pixel)
      EXPECT_EQ(framebuffer.ids[pixel].node, framebuffer.ids[0].node);
    return framebuffer.ids[0].node;
  };
  EXPECT_EQ(nodeSeen(1.0, 10.0), 0u);
  EXPECT_EQ(nodeSeen(6.0, 10.0), 1u);              // the nearer quad lies before the near plane
  EXPECT_EQ(nodeSeen(1.0, 4.0), PixelIds{}.node);  // both lie beyond the far plane
  EXPECT_EQ(nodeSeen(5.5, 6.5), PixelIds{}.node);  // between the two
}

TEST(EmbreeCaster, ColourIsBaseColourTimesBilinearTextureWithWrapModes) {
  // A 2×1 texture, black then white, across the quad's u; its base colour halves green.
  Scene scene = sceneOf(quadMesh(), {glm::dmat4(1.0)});
  scene.textures.push_back(Texture{"ramp", 2, 1, {0, 0, 0, 255, 255, 255, 255, 255}});
  scene.materials[0] = Material{"textured", glm::vec4(1.0f, 0.5f, 1.0f, 1.0f), 0};
  const Camera camera = orthographicCamera(lookFrom({0, 0, 5}, {0, 0, 0}), -1, 1, -1, 1, 1, 10, 64, 64);
  for (const TextureWrap wrap : {TextureWrap::Repeat, TextureWrap::ClampToEdge}) {
    scene.textures[0].wrapS = wrap;
    const Hierarchy hierarchy = analyzeHierarchy(scene);
    const EmbreeScene embree(scene, hierarchy);
    Framebuffer framebuffer = makeFramebuffer(64, 64, kChannelColor);
    embree.render(camera, framebuffer);
    for (std::uint32_t px = 0; px < 64; ++px) {
      // Pixel column px samples u = (px + 0.5)/64, texel coordinate 2u − 0.5 between the centres.
      const double x = 2.0 * (px + 0.5) / 64.0 - 0.5;
      const double white = wrap == TextureWrap::ClampToEdge ? std::clamp(x, 0.0, 1.0)
                                                            : (x < 0   ? -x
                                                               : x > 1 ? 2 - x
                                                                       : x);
      const glm::u8vec4 color = framebuffer.color[32 * 64 + px];
      EXPECT_NEAR(color.r, white * 255.0, 1.0) << px;
      EXPECT_NEAR(color.g, white * 127.5, 1.0) << px;
      EXPECT_EQ(color.a, 255);
    }
  }
  // Without uvs the texture cannot be sampled: the base colour alone.
  scene.meshes[0].uvs.clear();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  Framebuffer framebuffer = makeFramebuffer(64, 64, kChannelColor);
  EmbreeScene(scene, hierarchy).render(camera, framebuffer);
  EXPECT_EQ(framebuffer.color[32 * 64 + 5], glm::u8vec4(255, 128, 255, 255));
}

TEST(EmbreeCaster, MinifiedTexturesAreFilteredAsTheRasterizerFiltersThem) {
  // A checkerboard of 1-texel squares on a quad seen at a slant, perspective: from about one texel a pixel
  // at the near edge to many at the far one. Both renderers pick the mip level from the triangle's
  // projection at the sample, so they agree; and where a pixel spans several texels it shows their mean
  // (grey), not one texel's black or white.
  constexpr std::uint32_t kSize = 96;
  const Scene scene = test::slantedChecker();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const EmbreeScene embree(scene, hierarchy);
  const Camera camera = test::slantedCheckerCamera(kSize);
  Camera isotropic = camera;
  isotropic.textureProbes = 1;
  for (const Camera& view : {camera, isotropic, subpixelCamera(camera, glm::dvec2(0.3, 0.6), 16)}) {
    Framebuffer raster = makeFramebuffer(kSize, kSize, kChannelColor);
    drawSceneTriangles(scene, hierarchy, view, raster);
    Framebuffer rays = makeFramebuffer(kSize, kSize, kChannelColor);
    embree.render(view, rays);
    std::size_t both = 0, close = 0, grey = 0, far = 0;
    for (std::size_t pixel = 0; pixel < raster.pixelCount(); ++pixel) {
      if (raster.depth[pixel] >= kClearDepth || rays.depth[pixel] >= kClearDepth) continue;
      ++both;
      const int difference = std::abs(int(raster.color[pixel].r) - int(rays.color[pixel].r));
      close += difference <= 2;
      EXPECT_LE(difference, 24) << "pixel " << pixel;
      if (pixel / kSize < kSize / 2) {  // the far part, the upper half: several texels a pixel
        ++far;
        grey += std::abs(int(rays.color[pixel].r) - 128) <= 12 && std::abs(int(raster.color[pixel].r) - 128) <= 12;
      }
    }
    ASSERT_GT(both, kSize * kSize / 3);
    ASSERT_GT(far, kSize * 4);
    EXPECT_GE(double(close), 0.99 * double(both)) << "spacing " << view.sampleSpacing;
    // Probes along the slant sample finer levels, where the checker shows through at the far part's near end.
    if (view.sampleSpacing == 1.0 && view.textureProbes == 1) {
      EXPECT_EQ(grey, far) << "a pixel of many texels is their mean";
    } else if (view.sampleSpacing == 1.0) {
      EXPECT_GE(double(grey), 0.75 * double(far)) << "four probes: 83 % grey when written";
    }
  }
}

TEST(EmbreeCaster, RejectsAFramebufferOfAnotherSize) {
  const Scene scene = sceneOf(quadMesh(), {glm::dmat4(1.0)});
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const Camera camera = orthographicCamera(lookFrom({0, 0, 5}, {0, 0, 0}), -1, 1, -1, 1, 1, 10, 16, 16);
  Framebuffer framebuffer = makeFramebuffer(16, 15, 0);
  EXPECT_THROW(EmbreeScene(scene, hierarchy).render(camera, framebuffer), std::invalid_argument);
}

// ---- The rasterizer against the ray caster -------------------------------------------------------

constexpr ChannelMask kCompared = kChannelColor | kChannelNormal | kChannelIds;

test::Agreement renderBothAndCompare(const Scene& scene, const Hierarchy& hierarchy, const EmbreeScene& embree,
                                     const Camera& camera) {
  Framebuffer raster = makeFramebuffer(camera.width, camera.height, kCompared);
  drawSceneTriangles(scene, hierarchy, camera, raster);
  Framebuffer rays = makeFramebuffer(camera.width, camera.height, kCompared);
  embree.render(camera, rays);
  return compareViews(scene, hierarchy, camera, raster, rays);
}

Bounds sceneBounds(const Scene& scene, const Hierarchy& hierarchy) {
  Bounds bounds;
  for (std::uint32_t root : scene.roots) bounds.extend(hierarchy.worldBounds[root]);
  return bounds;
}

// The eight capture views of the scene's box (orthographic, from the corners, 512 px).
AgreementRange compareCaptureViews(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t resolution) {
  const EmbreeScene embree(scene, hierarchy);
  const Bounds box = sceneBounds(scene, hierarchy);
  AgreementRange range;
  for (const glm::dvec3& direction : boxCornerDirections())
    range.add(renderBothAndCompare(scene, hierarchy, embree, boxViewCamera(box, direction, resolution)));
  return range;
}

TEST(EmbreeVisibility, SharedScenesAgreeWithTheRasterizer) {
  PBS_SHARED_SCENE(dir, "");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".glb" || entry.path().extension() == ".gltf") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty());
  for (const std::filesystem::path& file : files) {
    const ImportResult imported = loadScene(file.string());
    const Hierarchy hierarchy = analyzeHierarchy(imported.scene);
    const AgreementRange range = compareCaptureViews(imported.scene, hierarchy, 512);
    range.print(file.filename().string());
    range.expectWithinThresholds(file.filename().string());
  }
}

// A torus (two parts, two materials), outward normals, uvs around both circles.
Mesh torusMesh() {
  constexpr std::uint32_t kAround = 48, kTube = 24;
  constexpr float kPi = 3.14159265358979f;
  Mesh mesh;
  mesh.name = "torus";
  for (std::uint32_t i = 0; i < kAround; ++i) {
    for (std::uint32_t j = 0; j < kTube; ++j) {
      const float a = 2.0f * kPi * float(i) / kAround, b = 2.0f * kPi * float(j) / kTube;
      const glm::vec3 ring(std::cos(a), std::sin(a), 0.0f);
      const glm::vec3 normal = std::cos(b) * ring + glm::vec3(0, 0, std::sin(b));
      mesh.positions.push_back(ring + 0.35f * normal);
      mesh.normals.push_back(normal);
      mesh.uvs.emplace_back(float(i) / kAround, float(j) / kTube);
    }
  }
  const auto vertex = [&](std::uint32_t i, std::uint32_t j) { return (i % kAround) * kTube + (j % kTube); };
  for (std::uint32_t i = 0; i < kAround; ++i) {
    for (std::uint32_t j = 0; j < kTube; ++j) {
      const std::uint32_t q[4] = {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)};
      mesh.indices.insert(mesh.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    }
  }
  const auto half = std::uint32_t(mesh.indices.size() / 2);
  mesh.parts = {MeshPart{0, half, 0}, MeshPart{half, std::uint32_t(mesh.indices.size()) - half, 1}};
  updateMeshBounds(mesh);
  return mesh;
}

// Two instances of the torus under a shared parent moved by `offset`: one rotated and scaled
// non-uniformly, one mirrored; they interpenetrate, so depth decides what each pixel shows.
Scene instancedScene(const glm::dvec3& offset) {
  Scene scene;
  scene.meshes.push_back(torusMesh());
  scene.materials.push_back(Material{"red", glm::vec4(0.8f, 0.2f, 0.1f, 1.0f), -1});
  scene.materials.push_back(Material{"blue", glm::vec4(0.1f, 0.3f, 0.9f, 1.0f), -1});
  const glm::dmat4 identity(1.0);
  const glm::dmat4 stretched =
      glm::rotate(identity, 0.7, glm::dvec3(1, 2, 0.5)) * glm::scale(identity, {1.6, 0.7, 1.1});
  const glm::dmat4 mirrored = glm::translate(identity, {0.9, 0.3, -0.2}) *
                              glm::rotate(identity, -1.1, glm::dvec3(0.3, 1, 0.2)) *
                              glm::scale(identity, {-1.0, 1.3, 0.8});
  scene.nodes.push_back(Node{"parent", glm::translate(identity, offset), {1, 2}, -1});
  scene.nodes.push_back(Node{"stretched", stretched, {}, 0});
  scene.nodes.push_back(Node{"mirrored", mirrored, {}, 0});
  scene.roots = {0};
  validateScene(scene, "instanced scene");
  return scene;
}

void checkInstancedScene(const glm::dvec3& offset, const std::string& name) {
  const Scene scene = instancedScene(offset);
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const AgreementRange capture = compareCaptureViews(scene, hierarchy, 256);
  capture.print(name + " (capture)");
  capture.expectWithinThresholds(name);

  const EmbreeScene embree(scene, hierarchy);
  const Bounds box = sceneBounds(scene, hierarchy);
  const Camera camera = perspectiveCamera(lookFrom(box.center() + glm::dvec3(2.5, 1.5, 3.5), box.center()),
                                          glm::radians(55.0), 0.5, 30.0, 320, 240);
  AgreementRange perspective;
  perspective.add(renderBothAndCompare(scene, hierarchy, embree, camera));
  perspective.print(name + " (perspective)");
  perspective.expectWithinThresholds(name);
  // Both instances must show, or the comparison above proves little.
  Framebuffer rays = makeFramebuffer(camera.width, camera.height, kChannelIds);
  embree.render(camera, rays);
  EXPECT_TRUE(std::any_of(rays.ids.begin(), rays.ids.end(), [](const PixelIds& ids) { return ids.node == 1; }));
  EXPECT_TRUE(std::any_of(rays.ids.begin(), rays.ids.end(), [](const PixelIds& ids) { return ids.node == 2; }));
}

TEST(EmbreeVisibility, InstancedSceneAgreesWithTheRasterizer) { checkInstancedScene({0.0, 0.0, 0.0}, "instanced"); }

TEST(EmbreeVisibility, FarFromOriginInstancedSceneAgreesWithTheRasterizer) {
  checkInstancedScene({2e5, -3e5, 1e5}, "instanced, far");
}

// A 7 × 7 grid of tori around a perspective camera: instances behind it, beside it and cut by the
// near plane; culling must drop only what cannot show.
TEST(EmbreeVisibility, CulledSceneAgreesWithTheRasterizer) {
  Scene scene = sceneOf(torusMesh(), {});
  for (int i = 0; i < 49; ++i) {
    const glm::dvec3 at(2.5 * (i % 7 - 3), 2.5 * (i / 7 - 3), 0.3 * (i % 3));
    scene.roots.push_back(std::uint32_t(scene.nodes.size()));
    scene.nodes.push_back(
        Node{"torus", glm::rotate(glm::translate(glm::dmat4(1.0), at), 0.4 * i, glm::dvec3(1, 1, 0)), {}, 0});
  }
  validateScene(scene, "grid");
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const EmbreeScene embree(scene, hierarchy);
  const Camera camera =
      perspectiveCamera(lookFrom({0.3, 0.2, 0.5}, {4.0, 1.0, 0.2}), glm::radians(60.0), 0.2, 12.0, 320, 200);

  std::uint32_t culled = 0;
  for (std::uint32_t node = 0; node < scene.nodes.size(); ++node)
    culled += outsideClipVolume(camera, instanceWorldBounds(scene, hierarchy, node)) ? 1 : 0;
  EXPECT_GT(culled, 20u);
  EXPECT_LT(culled, 45u);

  AgreementRange range;
  range.add(renderBothAndCompare(scene, hierarchy, embree, camera));
  range.print("grid (perspective, culled)");
  range.expectWithinThresholds("grid");
}

// More instances than EmbreeScene keeps boxes for (kCoveringCells³ = 4,096: it casts rays only where the union of
// each grid cell's instances shows), seen from afar, where the field covers a small part of the image, and from
// inside it, with instances behind the eye and across the near plane: every pixel a triangle covers is hit.
TEST(EmbreeVisibility, ManyInstancesFromAfarAndFromInsideAgreeWithTheRasterizer) {
  constexpr int kSide = 72;  // 5,184 quads, 3 apart, at heights (by row) and turns (by column) that vary
  Scene scene = sceneOf(quadMesh(), {});
  for (int i = 0; i < kSide * kSide; ++i) {
    const glm::dvec3 at(3.0 * (i % kSide), 3.0 * (i / kSide), 0.7 * (i / kSide % 5));
    scene.roots.push_back(std::uint32_t(scene.nodes.size()));
    scene.nodes.push_back(
        Node{"quad", glm::rotate(glm::translate(glm::dmat4(1.0), at), 0.05 * (i % 7), glm::dvec3(1, 0, 0)), {}, 0});
  }
  validateScene(scene, "field");
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const EmbreeScene embree(scene, hierarchy);
  const glm::dvec3 middle(3.0 * kSide / 2, 3.0 * kSide / 2, 0.0);
  const Camera afar = perspectiveCamera(lookFrom(middle + glm::dvec3(120, -280, 360), middle), glm::radians(40.0), 10.0,
                                        3000.0, 640, 480);
  const Camera inside = perspectiveCamera(lookFrom(middle + glm::dvec3(0, 0, 4), middle + glm::dvec3(60, 30, 0)),
                                          glm::radians(70.0), 0.5, 400.0, 320, 240);
  for (const Camera& camera : {afar, inside}) {
    Framebuffer rays = makeFramebuffer(camera.width, camera.height, kChannelIds);
    embree.render(camera, rays);
    Framebuffer raster = makeFramebuffer(camera.width, camera.height, kChannelIds);
    drawSceneTriangles(scene, hierarchy, camera, raster);
    std::uint64_t covered = 0, uncovered = 0, disagree = 0;
    for (std::size_t pixel = 0; pixel < rays.pixelCount(); ++pixel) {
      covered += rays.covered(pixel);
      uncovered += !rays.covered(pixel);
      disagree += rays.covered(pixel) != raster.covered(pixel);
    }
    // Edges aside (a pixel centre on an edge may go either way), rays cover what the rasterizer covers, and
    // both views hold covered and empty pixels, so that skipping the empty ones is tested.
    EXPECT_GT(covered, rays.pixelCount() / 20);
    EXPECT_GT(uncovered, rays.pixelCount() / 20);
    EXPECT_LT(disagree, covered / 200 + 4) << "covered " << covered;
  }
  AgreementRange range;
  range.add(renderBothAndCompare(scene, hierarchy, embree, afar));
  range.add(renderBothAndCompare(scene, hierarchy, embree, inside));
  range.print("field of 5,184 instances");
  range.expectWithinThresholds("field");
}

TEST(SceneDraws, OutsideClipVolumeIsConservative) {
  const Camera camera = perspectiveCamera(lookFrom({0, 0, 0}, {0, 0, -1}), glm::radians(90.0), 1.0, 10.0, 64, 64);
  const auto box = [](glm::dvec3 lo, glm::dvec3 hi) { return Bounds{lo, hi}; };
  EXPECT_FALSE(outsideClipVolume(camera, box({-0.5, -0.5, -5.5}, {0.5, 0.5, -4.5})));  // in view
  EXPECT_FALSE(outsideClipVolume(camera, box({-0.5, -0.5, -1.5}, {0.5, 0.5, 0.5})));   // across the near plane
  EXPECT_FALSE(outsideClipVolume(camera, box({-20, -20, -11}, {20, 20, -9})));         // across the far plane
  EXPECT_FALSE(outsideClipVolume(camera, box({4.9, -0.1, -5.1}, {5.1, 0.1, -4.9})));   // on the side plane
  EXPECT_TRUE(outsideClipVolume(camera, box({-0.5, -0.5, 1.0}, {0.5, 0.5, 2.0})));     // behind the eye
  EXPECT_TRUE(outsideClipVolume(camera, box({-0.5, -0.5, -0.9}, {0.5, 0.5, -0.1})));   // before the near plane
  EXPECT_TRUE(outsideClipVolume(camera, box({-0.5, -0.5, -12}, {0.5, 0.5, -11})));     // beyond the far plane
  EXPECT_TRUE(outsideClipVolume(camera, box({6.0, -0.1, -5.1}, {7.0, 0.1, -4.9})));    // beside the view
  EXPECT_TRUE(outsideClipVolume(camera, Bounds{}));                                    // empty
}

// Embree's own count of what it allocates: a scene's BVHs take bytes in proportion to its triangles,
// and the estimate a command checks against --max-memory lies above what the build used.
TEST(EmbreeCaster, AllocationsAreCountedAndTheEstimateBoundsThem) {
  for (const int subdivisions : {4, 40}) {
    Scene scene = test::twoIdenticalGroups();
    scene.meshes[0] = test::tessellatedBox(subdivisions);
    const Hierarchy hierarchy = analyzeHierarchy(scene);
    const EmbreeScene embree(scene, hierarchy);
    EXPECT_GT(embree.peakBytes(), scene.meshes[0].triangleCount() * 8) << subdivisions;
    EXPECT_LE(embree.bytes(), embree.peakBytes());
    EXPECT_GE(embreeMemoryEstimate(scene, hierarchy), embree.peakBytes()) << subdivisions;
  }
}

TEST(EmbreeCaster, SameImageForAnyThreadCount) {
  const Scene scene = instancedScene({0.0, 0.0, 0.0});
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const Camera camera = boxViewCamera(sceneBounds(scene, hierarchy), boxCornerDirections()[3], 200);
  const auto renderWith = [&](int threads) {
    Framebuffer framebuffer = makeFramebuffer(camera.width, camera.height, kAllChannels);
    runWithThreads(threads, [&] { EmbreeScene(scene, hierarchy).render(camera, framebuffer); });
    return framebuffer;
  };
  const Framebuffer one = renderWith(1), all = renderWith(0);
  EXPECT_EQ(one.depth, all.depth);
  EXPECT_EQ(one.color, all.color);
  EXPECT_EQ(one.position, all.position);
  EXPECT_EQ(one.normal, all.normal);
  EXPECT_EQ(one.ids, all.ids);
}

}  // namespace
}  // namespace pbs
