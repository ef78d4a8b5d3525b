// Numerical stability of the surfel layer: capture and surfelize of far, scaled, flat, tiny, empty and
// duplicated geometry, the .surfels file with non-finite values, and the LOD renderer at the edges.
#include "stability_checks.hpp"

#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/raster/projected_box.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/surfels/capture.hpp>
#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/scene_surfels.hpp>
#include <pbs/surfels/surfelize.hpp>

#include "forged_surfel_file.hpp"

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
using stability::expectFiniteSurfels;
using stability::framebufferBytes;
using stability::sameBytesForOneTwoAndFourThreads;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Mesh meshOf(std::vector<glm::vec3> positions, std::vector<std::uint32_t> indices) {
  Mesh mesh;
  mesh.name = "stiff";
  mesh.positions = std::move(positions);
  mesh.indices = std::move(indices);
  mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
  mesh.parts = {MeshPart{0, std::uint32_t(mesh.indices.size()), 0}};
  updateMeshBounds(mesh);
  return mesh;
}

// root → one child holding `mesh` at `local`: the root's surfels are made in its own frame, so the
// child's transform (far offsets, extreme scales) reaches the capture and the stored positions.
Scene rootOver(Mesh mesh, const glm::dmat4& local, int copies = 1) {
  Scene scene = test::sceneOf(std::move(mesh), {});
  scene.nodes = {Node{"root", glm::dmat4(1.0), {}, -1}};
  for (int c = 0; c < copies; ++c) {
    scene.nodes[0].children.push_back(std::uint32_t(scene.nodes.size()));
    scene.nodes.push_back(Node{"copy", local, {}, 0});
  }
  scene.roots = {0};
  validateScene(scene, "stiff scene");
  return scene;
}

SurfelizeOptions smallOptions() {
  SurfelizeOptions options;
  options.file.threshold = 0;  // every node with a triangle gets surfels
  options.file.maxSurfels = 3000;
  options.file.resolution = 64;
  return options;
}

// ---- Capture ----------------------------------------------------------------------------------

// Expected: a node whose triangles all have zero area (a segment: zero thickness in two axes) or that
// are collinear draws nothing in any view: no surfels, coverage 0 (never 0/0), with either backend.
TEST(StabilitySurfels, CaptureOfZeroAreaGeometryGivesNoSurfelsAndZeroCoverage) {
  const Mesh segment = meshOf({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 0}}, {0, 1, 2, 1, 2, 3});
  const Mesh point = meshOf({{3, 3, 3}, {3, 3, 3}, {3, 3, 3}}, {0, 1, 2});
  for (const Mesh& mesh : {segment, point}) {
    const Scene scene = test::sceneOf(mesh, {glm::dmat4(1.0)});
    const Hierarchy hierarchy = analyzeHierarchy(scene);
    for (const auto backend : {CaptureOptions::Backend::Raster, CaptureOptions::Backend::Embree}) {
      const CaptureResult result = captureNode(scene, hierarchy, 0, {.resolution = 32, .backend = backend});
      EXPECT_TRUE(result.surfels.empty());
      EXPECT_EQ(result.coverage, 0.0);
      EXPECT_TRUE(std::isfinite(double(result.origin.x)));
    }
  }
}

// ---- Surfelize and the .surfels file ----------------------------------------------------------

struct SurfelizeCase {
  std::string name;
  Mesh mesh;
  glm::dmat4 local;
  int copies = 1;
  bool coversPixels = true;  // false: thinner than a capture pixel, so its array is empty
};
// gtest prints a parameter in test listings (ctest names): its name, not its bytes.
void PrintTo(const SurfelizeCase& c, std::ostream* out) { *out << c.name; }

// The same bytes for 1, 2 and 4 threads; returns the file as read back.
SurfelFile surfelizeAndRead(const Scene& scene, const test::ScratchDir& dir) {
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const std::filesystem::path path = dir / "stiff.surfels";
  sameBytesForOneTwoAndFourThreads(
      [&] {
        writeSurfelFile(path, surfelize(scene, hierarchy, smallOptions()));
        return test::readFile(path);
      },
      [](const std::string& bytes) { return bytes; });
  return readSurfelFile(path);
}

class StabilitySurfelize : public testing::TestWithParam<SurfelizeCase> {};

// Expected: every array has a finite box, coverage in [0, 1], finite packing and area, and surfels
// that decode finite and inside the box; the file is the same bytes for 1, 2 and 4 threads.
// Quantized positions (21 bits per axis against the array's box): the decoded surfel lies within half
// a step, extent / (2^21 − 1) / 2 = 2.38e-7 of the extent, plus float rounding, of what surfelize
// produced. Measured: ≤ 2.5e-7 of the box extent per axis, float rounding included (asserted: 2.4e-7
// of the extent plus 2 float ulps of the value).
TEST_P(StabilitySurfelize, FileIsFiniteDeterministicAndWithinTheQuantizationBound) {
  const SurfelizeCase& c = GetParam();
  const Scene scene = rootOver(c.mesh, c.local, c.copies);
  test::ScratchDir dir;
  const SurfelFile read = surfelizeAndRead(scene, dir);
  const SurfelFile made = surfelize(scene, analyzeHierarchy(scene), smallOptions());
  ASSERT_EQ(read.arrays.size(), made.arrays.size());
  ASSERT_FALSE(read.arrays.empty());
  double worst = 0.0;
  for (std::size_t a = 0; a < read.arrays.size(); ++a) {
    const SurfelArray& array = read.arrays[a];
    EXPECT_TRUE(stability::finite(glm::vec3(array.box.min)) && stability::finite(glm::vec3(array.box.max)));
    EXPECT_TRUE(array.coverage >= 0.0 && array.coverage <= 1.0) << array.coverage;
    EXPECT_TRUE(std::isfinite(array.packing) && std::isfinite(array.area));
    EXPECT_EQ(array.surfels.empty(), !c.coversPixels) << "array " << a;
    expectFiniteSurfels(array.surfels);
    const glm::dvec3 extent = array.box.size();
    ASSERT_EQ(array.surfels.size(), made.arrays[a].surfels.size());
    for (std::size_t i = 0; i < array.surfels.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const double original = made.arrays[a].surfels[i].position[k];
        const double decoded = array.surfels[i].position[k];
        const double ulp = std::numeric_limits<float>::epsilon() * std::max(std::abs(original), std::abs(decoded));
        ASSERT_LE(std::abs(decoded - original), 2.4e-7 * extent[k] + 2.0 * ulp) << "axis " << k;
        ASSERT_LE(std::abs(decoded), 0.5 * extent[k] * (1.0 + 1e-6));  // inside the box
        if (extent[k] > 0.0) worst = std::max(worst, std::abs(decoded - original) / extent[k]);
      }
    }
  }
  stability::recordMeasured("max_quantization_error_of_extent", worst);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, StabilitySurfelize,
    testing::Values(
        SurfelizeCase{"Offset1e6", test::tessellatedBox(3),
                      glm::translate(glm::dmat4(1.0), glm::dvec3(1e6, -1e6, 1e6))},
        SurfelizeCase{"Offset1e7", test::tessellatedBox(3), glm::translate(glm::dmat4(1.0), glm::dvec3(-1e7, 0, 1e7))},
        SurfelizeCase{"Scale1e_6", test::tessellatedBox(3), glm::scale(glm::dmat4(1.0), glm::dvec3(1e-6))},
        SurfelizeCase{"Scale1e6", test::tessellatedBox(3), glm::scale(glm::dmat4(1.0), glm::dvec3(1e6))},
        // A flat quad: zero thickness in z; decoded z is exactly the box's (the codec's zero-extent rule).
        SurfelizeCase{"ZeroThickness", meshOf({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {0, 1, 2, 0, 2, 3}),
                      glm::dmat4(1.0)},
        SurfelizeCase{"OneTriangle", meshOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2}), glm::dmat4(1.0)},
        // Slivers 1e-2 and 1e-4 as wide as long: 0.6 and 0.006 capture pixels wide. The first gives
        // a few surfels; the second covers no pixel centre in any view and gets an empty array.
        SurfelizeCase{"Sliver", meshOf({{0, 0, 0}, {1, 0, 0}, {1, 1e-2f, 0}}, {0, 1, 2}), glm::dmat4(1.0)},
        SurfelizeCase{"SubPixelSliver", meshOf({{0, 0, 0}, {1, 0, 0}, {1, 1e-4f, 0}}, {0, 1, 2}), glm::dmat4(1.0), 1,
                      false},
        // Two coincident copies of the box: every capture pixel a depth tie, decided by draw order.
        SurfelizeCase{"DuplicatedGeometry", test::tessellatedBox(3), glm::dmat4(1.0), 2}),
    [](const auto& info) { return info.param.name; });

// Expected: a scene whose meshes have no triangles has no node above any threshold: a file with no
// arrays, still written whole and read back.
TEST(StabilitySurfels, MeshWithNoTrianglesGetsNoArrays) {
  const Scene scene = rootOver(meshOf({{0, 0, 0}, {1, 0, 0}}, {}), glm::dmat4(1.0));
  test::ScratchDir dir;
  writeSurfelFile(dir / "empty.surfels", surfelize(scene, analyzeHierarchy(scene), smallOptions()));
  EXPECT_TRUE(readSurfelFile(dir / "empty.surfels").arrays.empty());
}

// An array of `count` identical surfels (duplicated surfels) in a unit box.
SurfelFile duplicatedSurfels(std::size_t count) {
  SurfelFile file;
  SurfelArray array;
  array.box = Bounds{glm::dvec3(-1.0), glm::dvec3(1.0)};
  array.coverage = 0.5;
  array.surfels.assign(count, Surfel{glm::vec3(0.25f), glm::vec3(0, 0, 1), glm::u8vec4(255)});
  file.arrays.push_back(array);
  file.nodes = {{"/0", 0}};
  return file;
}

// Expected: writing an array with a NaN or Inf box, coverage, packing or area is refused
// (std::invalid_argument naming the array) rather than stored, and a file that holds one anyway (forged
// with correct checksums) is an InputError naming the node, so no non-finite value reaches a renderer.
TEST(StabilitySurfels, NonFiniteArrayValuesAreNeverWrittenNorRead) {
  test::ScratchDir dir;
  const auto spoilers = std::vector<std::function<void(SurfelArray&)>>{
      [](SurfelArray& a) { a.box.min.x = kNaN; }, [](SurfelArray& a) { a.box.max.z = kInf; },
      [](SurfelArray& a) { a.coverage = kNaN; }, [](SurfelArray& a) { a.packing = kInf; },
      [](SurfelArray& a) { a.area = -kInf; }};
  for (std::size_t s = 0; s < spoilers.size(); ++s) {
    SCOPED_TRACE(testing::Message() << "spoiler " << s);
    SurfelFile file = duplicatedSurfels(3);
    spoilers[s](file.arrays[0]);
    EXPECT_THROW(writeSurfelFile(dir / "bad.surfels", file), std::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.surfels"));
  }
  // Forged: a good file with one value made non-finite and the array table's checksum re-sealed.
  using stability::ArrayField;
  for (const ArrayField field :
       {ArrayField::BoxMinX, ArrayField::BoxMaxZ, ArrayField::Coverage, ArrayField::Packing, ArrayField::Area}) {
    SCOPED_TRACE(testing::Message() << "field " << std::size_t(field));
    writeSurfelFile(dir / "forged.surfels", duplicatedSurfels(3));
    std::string bytes = test::readFile(dir / "forged.surfels");
    stability::forgeArrayValue(bytes, 0, field, field == ArrayField::Packing ? kInf : kNaN);
    test::writeFile(dir / "forged.surfels", bytes);
    try {
      readSurfelFile(dir / "forged.surfels");
      ADD_FAILURE() << "a non-finite value was read";
    } catch (const InputError& error) {
      EXPECT_TRUE(std::string(error.what()).starts_with((dir / "forged.surfels").string() + ": node /0: "))
          << error.what();
      EXPECT_NE(std::string(error.what()).find("is not finite"), std::string::npos) << error.what();
    }
  }
}

// Expected: duplicated surfels (all at one point) round-trip to one point, bit for bit alike; their
// packing (nearest-neighbour distance 0) and any prefix length stay finite and within the array.
TEST(StabilitySurfels, DuplicatedSurfelsRoundTripAndGiveBoundedPrefixes) {
  test::ScratchDir dir;
  writeSurfelFile(dir / "dup.surfels", duplicatedSurfels(2000));
  const SurfelFile read = readSurfelFile(dir / "dup.surfels");
  const std::vector<Surfel>& surfels = read.arrays.at(0).surfels;
  ASSERT_EQ(surfels.size(), 2000u);
  for (const Surfel& s : surfels) EXPECT_EQ(s.position, surfels[0].position);
  EXPECT_NEAR(surfels[0].position.x, 0.25f, 2.0 / ((1u << kPositionBits) - 1));
  const SplatArray splats = splatArrayOf(read.arrays[0]);
  for (const PrefixRule rule : {PrefixRule::Coverage, PrefixRule::Packing}) {
    LodOptions options;
    options.prefixRule = rule;
    for (const double size : {0.0, 1.0, 1e300, kInf, kNaN})
      for (const double pixel : {0.0, 1e-300, 1.0, kInf, kNaN})
        for (const double scale : {0.0, 1e-300, 1.0, kInf, kNaN})
          EXPECT_LE(prefixLength(splats, size, pixel, scale, options), splats.size());
  }
}

// ---- LOD rendering ----------------------------------------------------------------------------

struct SurfeledScene {
  Scene scene;
  Hierarchy hierarchy;
  SceneSurfels surfels;
};

// Two groups of two boxes (test::twoIdenticalGroups) moved to `offset`, with surfels for every node.
SurfeledScene surfeledGroups(const glm::dvec3& offset) {
  SurfeledScene s{test::twoIdenticalGroups(), {}, {}};
  s.scene.nodes[0].local = glm::translate(glm::dmat4(1.0), offset);
  s.hierarchy = analyzeHierarchy(s.scene);
  SurfelizeOptions options = smallOptions();
  options.file.threshold = 1000;
  s.surfels = sceneSurfelsOf(surfelize(s.scene, s.hierarchy, options), s.scene, s.hierarchy, "groups");
  return s;
}

Framebuffer renderGroups(const SurfeledScene& s, const Camera& camera, const glm::dvec3& positionOrigin) {
  Framebuffer framebuffer =
      makeFramebuffer(camera.width, camera.height, kChannelColor | kChannelPosition | kChannelNormal, positionOrigin);
  renderLod(s.scene, s.hierarchy, s.surfels, camera, framebuffer, LodOptions{});
  return framebuffer;
}

Camera groupsCamera(const glm::dvec3& offset, const glm::dvec3& eye, double near, double far) {
  const glm::dmat4 view = glm::lookAt(offset + eye, offset, glm::dvec3(0.0, 1.0, 0.0));
  return perspectiveCamera(view, glm::radians(60.0), near, far, 96, 64);
}

// Expected: seen from far enough that the root draws surfels, the scene at 1e7 gives exactly the
// pixels it gives at the origin (surfels are relative to their box centres, placed in double), finite,
// the same bytes for 1, 2 and 4 threads. Measured: identical coverage, depth within 1 float ulp.
TEST(StabilitySurfels, LodRenderFarFromTheOriginMatchesTheOrigin) {
  const glm::dvec3 eye(40.0, 20.0, 60.0);
  const SurfeledScene origin = surfeledGroups(glm::dvec3(0.0));
  const Framebuffer reference = renderGroups(origin, groupsCamera(glm::dvec3(0.0), eye, 1.0, 500.0), glm::dvec3(0.0));
  const LodDraws draws = traverseLod(origin.scene, origin.hierarchy, origin.surfels,
                                     groupsCamera(glm::dvec3(0.0), eye, 1.0, 500.0), LodOptions{});
  ASSERT_FALSE(draws.surfels.empty()) << "the view must draw surfels to test them";
  const glm::dvec3 offset(1e7, -1e7, 1e7);
  const SurfeledScene far = surfeledGroups(offset);
  const Camera camera = groupsCamera(offset, eye, 1.0, 500.0);
  const Framebuffer moved =
      sameBytesForOneTwoAndFourThreads([&] { return renderGroups(far, camera, offset); }, framebufferBytes);
  expectFiniteFramebuffer(moved);
  EXPECT_EQ(test::coveredPixels(moved), test::coveredPixels(reference));
  for (std::size_t p = 0; p < moved.pixelCount(); ++p) {
    if (!moved.covered(p) || !reference.covered(p)) continue;
    EXPECT_NEAR(moved.depth[p], reference.depth[p], 1.2e-7f);
  }
}

// Expected: with the camera inside the root's box (and inside a group's), the box has no finite
// projected size (+Inf, projected_box.hpp), so those nodes are descended to geometry, never drawn as
// surfels; near 1e-6 and far 1e9 change nothing but depth. The image is finite and thread-independent.
TEST(StabilitySurfels, LodRenderWithTheCameraInsideANodesBox) {
  const SurfeledScene s = surfeledGroups(glm::dvec3(0.0));
  const glm::dvec3 inside = s.hierarchy.worldBounds[1].center() + glm::dvec3(0.0, 0.0, 0.1);
  for (const auto& [near, far] : {std::pair{0.01, 100.0}, std::pair{1e-6, 1e9}}) {
    SCOPED_TRACE(testing::Message() << "near " << near << " far " << far);
    const Camera camera = perspectiveCamera(
        glm::lookAt(inside, inside + glm::dvec3(1.0, 0.2, 0.1), glm::dvec3(0.0, 1.0, 0.0)), 1.2, near, far, 96, 64);
    EXPECT_EQ(projectedBoxPixels(camera, s.hierarchy.worldBounds[0]), kInf);
    const LodDraws draws = traverseLod(s.scene, s.hierarchy, s.surfels, camera, LodOptions{});
    for (const auto& d : draws.surfels) EXPECT_NE(d.node, 0u) << "the root surrounds the eye";
    for (const auto& d : draws.surfels) EXPECT_NE(d.node, 1u) << "group A surrounds the eye";
    const Framebuffer framebuffer =
        sameBytesForOneTwoAndFourThreads([&] { return renderGroups(s, camera, inside); }, framebufferBytes);
    expectFiniteFramebuffer(framebuffer);
    EXPECT_FALSE(test::coveredPixels(framebuffer).empty());
  }
}

// Expected: a NaN or Inf in the camera's view or projection draws nothing (every clip position is
// non-finite) and nothing non-finite reaches the framebuffer; the traversal never crashes.
TEST(StabilitySurfels, LodRenderWithANonFiniteCameraDrawsNothing) {
  const SurfeledScene s = surfeledGroups(glm::dvec3(0.0));
  for (const double bad : {kNaN, kInf}) {
    for (const bool inProjection : {false, true}) {
      Camera camera = groupsCamera(glm::dvec3(0.0), glm::dvec3(40.0, 20.0, 60.0), 1.0, 500.0);
      (inProjection ? camera.projection[0][0] : camera.view[3][2]) = bad;
      const Framebuffer framebuffer = renderGroups(s, camera, glm::dvec3(0.0));
      expectFiniteFramebuffer(framebuffer);
      EXPECT_TRUE(test::coveredPixels(framebuffer).empty()) << bad << (inProjection ? " projection" : " view");
    }
  }
}

}  // namespace
}  // namespace pbs
