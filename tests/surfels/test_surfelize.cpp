// Whole-scene surfels: which nodes get arrays, sharing between instances, the frame arrays live in,
// determinism across thread counts, capturing from children's surfels, and `pbs surfelize`.
#include "test_fixtures.hpp"
#include "cli_scenes.hpp"
#include "shard_runs.hpp"
#include "test_support.hpp"

#include <pbs/raster/box_view.hpp>
#include <pbs/raster/points.hpp>
#include <pbs/raster/raster_limits.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/generate.hpp>
#include <pbs/scene/gltf_export.hpp>
#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/scene_draws.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/scene/subtree_classes.hpp>
#include <pbs/scene/surface_area.hpp>
#include <pbs/raster/hash64.hpp>
#include <pbs/surfels/capture.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/prefilter_colors.hpp>
#include <pbs/surfels/scene_surfels.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>

namespace pbs {
namespace {

using test::groupsFile;
using test::ScratchDir;
using test::twoIdenticalGroups;

SurfelizeOptions smallOptions(std::uint64_t threshold) {
  SurfelizeOptions options;
  options.file.threshold = threshold;
  options.file.maxSurfels = 2000;
  options.file.resolution = 128;
  return options;
}

TEST(SubtreeClasses, IdenticalSubtreesShareAClassWhateverTheirPlacement) {
  const Scene scene = twoIdenticalGroups();
  const std::vector<std::uint32_t> classes = subtreeClasses(scene, analyzeHierarchy(scene));
  EXPECT_EQ(classes[1], classes[2]) << "groups A and B differ only in their own placement";
  EXPECT_EQ(classes[3], classes[4]) << "instances of one mesh with no children";
  EXPECT_EQ(classes[3], classes[6]);
  EXPECT_NE(classes[0], classes[1]);
  EXPECT_NE(classes[1], classes[3]);
  EXPECT_EQ(classes[0], 0u) << "numbered in preorder of first appearance";

  Scene changed = scene;
  changed.nodes[6].local[3][0] += 1e-12;  // one child of B moves a little
  const std::vector<std::uint32_t> after = subtreeClasses(changed, analyzeHierarchy(changed));
  EXPECT_NE(after[1], after[2]);
  EXPECT_EQ(after[5], after[6]) << "a node's own placement is not part of its class";
}

TEST(AnalyzeSubtree, SeesTheSubtreeFromTheNodesOwnFrame) {
  const Scene scene = twoIdenticalGroups();
  const Hierarchy world = analyzeHierarchy(scene);
  const Hierarchy own = analyzeSubtree(scene, 2);
  EXPECT_EQ(own.world[2], glm::dmat4(1.0));
  EXPECT_EQ(own.parent[2], -1);
  EXPECT_EQ(own.preorder, (std::vector<std::uint32_t>{2, 5, 6}));
  EXPECT_EQ(own.subtreeTriangles[2], world.subtreeTriangles[2]);
  // A leaf's box in its own frame is its mesh's box.
  const Hierarchy leaf = analyzeSubtree(scene, 5);
  EXPECT_EQ(leaf.worldBounds[5].min, glm::dvec3(scene.meshes[0].bounds.min));
  EXPECT_EQ(leaf.worldBounds[5].max, glm::dvec3(scene.meshes[0].bounds.max));
  // Groups A and B see identical subtrees from their own frames.
  const Hierarchy a = analyzeSubtree(scene, 1);
  EXPECT_EQ(a.worldBounds[1].min, own.worldBounds[2].min);
  EXPECT_EQ(a.worldBounds[1].max, own.worldBounds[2].max);
}

TEST(SurfaceArea, OwnFrameAreasOfAllNodesMatchTheOneNodeSum) {
  const Scene scene = twoIdenticalGroups();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  const std::vector<double> areas = ownFrameSurfaceAreas(scene, hierarchy);
  for (std::uint32_t n : hierarchy.preorder)
    EXPECT_NEAR(areas[n], subtreeSurfaceArea(scene, analyzeSubtree(scene, n), n), 1e-12 * areas[n]) << n;
  EXPECT_NEAR(areas[3], 24.0, 1e-9) << "a box [-1, 1]³ in its own frame";
}

// The area under a linear map by its definition, in long double: each triangle's vertices mapped, then crossed.
double mappedTriangleArea(const Mesh& mesh, const glm::dmat3& linear) {
  using Vector = std::array<long double, 3>;
  const auto map = [&](const glm::vec3& p) {
    Vector v{};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) v[r] += (long double)linear[c][r] * (long double)p[c];
    return v;
  };
  long double area = 0.0L;
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const Vector a = map(mesh.positions[mesh.indices[i]]), b = map(mesh.positions[mesh.indices[i + 1]]),
                 c = map(mesh.positions[mesh.indices[i + 2]]);
    const Vector u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Vector n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    area += 0.5L * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
  return double(area);
}

// TriangleAreaVectors takes each triangle's cross product through the map's cofactor matrix: the definition's value
// under shears, non-uniform and singular (zero-thickness) scales, and a degenerate triangle adds nothing.
TEST(SurfaceArea, MeshAreaUnderAnyLinearMapIsTheMappedTrianglesArea) {
  Mesh mesh;
  SeededRandom rng(3);
  for (int i = 0; i < 300; ++i)
    mesh.positions.emplace_back(rng.unit() * 4.0 - 2.0, rng.unit() * 4.0 - 2.0, rng.unit() * 4.0 - 2.0);
  for (std::uint32_t i = 0; i + 2 < 300; i += 3) mesh.indices.insert(mesh.indices.end(), {i, i + 1, i + 2});
  mesh.indices.insert(mesh.indices.end(), {5, 5, 7});  // degenerate
  const glm::dmat3 shear(glm::dvec3(2.0, 0.0, 0.0), glm::dvec3(0.7, 0.5, 0.0), glm::dvec3(-0.3, 0.2, 3.0));
  const glm::dmat3 flat(glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(0.0, 0.0, 0.0));
  const glm::dmat3 stretched =
      glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.4, glm::dvec3(1.0, 2.0, 0.5))) *
      glm::dmat3(glm::dvec3(1e6, 0.0, 0.0), glm::dvec3(0.0, 1e-3, 0.0), glm::dvec3(0.0, 0.0, 1.0));
  const TriangleAreaVectors vectors(mesh);
  for (const glm::dmat3& linear : {shear, flat, stretched, glm::dmat3(-1.0)}) {
    const double expected = mappedTriangleArea(mesh, linear);
    EXPECT_NEAR(vectors.areaUnder(linear), expected, 1e-12 * expected);
  }
  EXPECT_NEAR(vectors.areaUnder(glm::dmat3(1.0)), mappedTriangleArea(mesh, glm::dmat3(1.0)),
              1e-12 * vectors.areaUnder(glm::dmat3(1.0)));
  EXPECT_EQ(vectors.areaUnder(glm::dmat3(0.0)), 0.0);
}

TEST(Surfelize, InstancesShareArraysAndNodesGetStablePaths) {
  const Scene scene = twoIdenticalGroups();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  SurfelizeStats stats;
  const SurfelFile file = surfelize(scene, hierarchy, smallOptions(1000), &stats);
  // Every node holds ≥ 1,200 triangles; three classes: root, the groups, the box instances.
  EXPECT_EQ(stats.nodesWithSurfels, 7u);
  EXPECT_EQ(stats.arrays, 3u);
  ASSERT_EQ(file.arrays.size(), 3u);
  ASSERT_EQ(file.nodes.size(), 7u);
  const std::vector<std::string> paths = {"/0", "/0/0", "/0/0/0", "/0/0/1", "/0/1", "/0/1/0", "/0/1/1"};
  // Numbered children first: the boxes, the groups, the root.
  const std::vector<std::uint32_t> arrays = {2, 1, 0, 0, 1, 0, 0};
  for (std::size_t i = 0; i < paths.size(); ++i) {
    EXPECT_EQ(file.nodes[i].path, paths[i]);
    EXPECT_EQ(file.nodes[i].array, arrays[i]) << paths[i];
  }
  EXPECT_EQ(file.sceneFingerprint, sceneFingerprint(scene));
  std::uint64_t surfels = 0;
  for (const SurfelArray& array : file.arrays) {
    EXPECT_EQ(array.surfels.size(), 2000u);
    EXPECT_GT(array.coverage, 0.0);
    EXPECT_LE(array.coverage, 1.0);
    EXPECT_GT(array.packing, 0.0);
    surfels += array.surfels.size();
  }
  EXPECT_EQ(stats.surfels, surfels);
  // The shared box array lies in the mesh's own frame: on the surface of the box [-1, 1]³ (positions
  // are relative to the box centre, 0 here), whichever instance it was captured for.
  for (const Surfel& s : file.arrays[0].surfels) {
    const glm::vec3 a = glm::abs(s.position);
    EXPECT_NEAR(std::max({a.x, a.y, a.z}), 1.0f, 1e-4f);
  }
  // A box of area 6 · 2² = 24 in its own frame; group A holds two boxes, one scaled by (1, 2, 0.5). Each
  // times the sides its captures saw (CaptureResult::sidesSeen, 1 to 2): this box's faces are wound half
  // inward, so its normals say nearly two.
  const double boxSides = file.arrays[0].area / 24.0;
  const double groupSides = file.arrays[1].area / (24.0 + 2 * (2 * 1 + 1 * 0.5 + 2 * 0.5) * 4);
  EXPECT_GT(boxSides, 1.5);
  EXPECT_LE(boxSides, 2.0);
  EXPECT_GE(groupSides, 1.0);
  EXPECT_LE(groupSides, 2.0);
}

TEST(Surfelize, ASceneWithNothingComplexNeedsNoArrays) {
  const Scene scene = twoIdenticalGroups();
  SurfelizeStats stats;
  int progressCalls = 0;
  SurfelizeOptions options = smallOptions(1'000'000);
  options.onProgress = [&](const SurfelizeProgress&) { ++progressCalls; };
  const SurfelFile file = surfelize(scene, analyzeHierarchy(scene), options, &stats);
  EXPECT_TRUE(file.arrays.empty());
  EXPECT_TRUE(file.nodes.empty());
  EXPECT_EQ(stats.arrays, 0u);
  EXPECT_EQ(progressCalls, 0);
}

TEST(Surfelize, ProgressCountsEveryArrayOnce) {
  const Scene scene = twoIdenticalGroups();
  SurfelizeOptions options = smallOptions(1000);
  std::vector<SurfelizeProgress> seen;
  options.onProgress = [&](const SurfelizeProgress& p) { seen.push_back(p); };
  surfelize(scene, analyzeHierarchy(scene), options);
  ASSERT_EQ(seen.size(), 3u);
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i].arraysDone, i + 1);
  EXPECT_EQ(seen.back().trianglesDone, seen.back().trianglesTotal);
  EXPECT_EQ(seen.back().surfels, 6000u);
}

enum class Writing { AtTheEnd, AsItGoes };

// The bytes of the .surfels file surfelize gives for `scene` with `threads` threads, written from the
// whole SurfelFile or by surfelizeToFile.
std::string surfelFileBytes(const Scene& scene, const SurfelizeOptions& options, int threads,
                            Writing writing = Writing::AtTheEnd) {
  ScratchDir scratch;
  const std::filesystem::path path = scratch / "out.surfels";
  runWithThreads(threads, [&] {
    const Hierarchy hierarchy = analyzeHierarchy(scene);
    if (writing == Writing::AsItGoes)
      surfelizeToFile(scene, hierarchy, options, path);
    else
      writeSurfelFile(path, surfelize(scene, hierarchy, options));
  });
  return test::readFile(path);
}

// Also: the file written as the arrays finish (in whatever order the threads finish them, children's
// arrays freed as their parents are captured) is the same bytes.
// The memory estimate counts the arrays the schedule holds, not every array: captured from triangles,
// each array is written and freed as it is made, so a fan of 64 children needs no more than one of 4;
// captured from the children's surfels, the parent holds all of them until it is made.
TEST(Surfelize, MemoryEstimateCountsTheArraysHeldNotEveryArray) {
  auto fan = [](std::uint32_t children) {
    Scene scene;
    scene.materials.push_back(Material{"plain", glm::vec4(0.8f), -1});
    scene.nodes.push_back(Node{"fan", glm::dmat4(1.0), {}, -1});
    scene.roots.push_back(0);
    for (std::uint32_t c = 0; c < children; ++c) {
      scene.meshes.push_back(test::tessellatedBox(6 + c % 3));  // each child its own mesh: its own array
      scene.nodes[0].children.push_back(std::uint32_t(scene.nodes.size()));
      scene.nodes.push_back(Node{"leaf",
                                 glm::translate(glm::dmat4(1.0), glm::dvec3(3.0 * c, 0, 0)),
                                 {},
                                 std::int32_t(scene.meshes.size() - 1)});
    }
    validateScene(scene, "fan");
    return scene;
  };
  SurfelizeOptions options;
  options.file.threshold = 100;
  const std::uint64_t arrayBytes = std::uint64_t(options.file.maxSurfels) * (sizeof(Surfel) + kSurfelBytes);
  auto estimate = [&](std::uint32_t children, CaptureSource source) {
    const Scene scene = fan(children);
    options.source = source;
    return surfelizeMemoryEstimate(scene, analyzeHierarchy(scene), options, 2);
  };
  // The fan's own capture draws every child's triangles, and each of the two workers may keep the
  // rasterizer's buffers for that many.
  auto rasterizer = [&](std::uint32_t children) {
    const Scene scene = fan(children);
    const std::uint64_t triangles = analyzeHierarchy(scene).subtreeTriangles[0];
    return 2 * std::min<std::uint64_t>(triangles * kTriangleBufferBytesPerTriangle, kKeptTriangleBufferBytes);
  };
  ASSERT_GT(rasterizer(64), rasterizer(4));
  const std::uint64_t fewTriangles = estimate(4, CaptureSource::Triangles);
  const std::uint64_t manyTriangles = estimate(64, CaptureSource::Triangles);
  EXPECT_LT(manyTriangles - fewTriangles, arrayBytes + rasterizer(64) - rasterizer(4)) << "60 more arrays, none held";
  const std::uint64_t fewChildren = estimate(4, CaptureSource::ChildSurfels);
  const std::uint64_t manyChildren = estimate(64, CaptureSource::ChildSurfels);
  EXPECT_GE(manyChildren - fewChildren, 60 * arrayBytes) << "the fan's parent holds its 64 children";
}

TEST(Surfelize, BitIdenticalFileForOneTwoAndFourThreads) {
  const Scene scene = twoIdenticalGroups();
  for (CaptureSource source : {CaptureSource::Triangles, CaptureSource::ChildSurfels, CaptureSource::Auto}) {
    for (SurfelOrdering ordering : {SurfelOrdering::Farthest, SurfelOrdering::Dart}) {
      SurfelizeOptions options = smallOptions(1000);
      options.source = source;
      options.file.ordering = ordering;
      const std::string one = surfelFileBytes(scene, options, 1);
      ASSERT_GT(one.size(), 3 * 2000 * surfelBytes(SurfelColorEncoding::Constant)) << "three arrays of 2000 or more";
      EXPECT_EQ(one, surfelFileBytes(scene, options, 2));
      EXPECT_EQ(one, surfelFileBytes(scene, options, 4));
      EXPECT_EQ(one, surfelFileBytes(scene, options, 1, Writing::AsItGoes));
      EXPECT_EQ(one, surfelFileBytes(scene, options, 4, Writing::AsItGoes));
    }
  }
}

// An open sheet (one-sided mesh, drawn two-sided) seen from both sides: a renderer culling back faces
// draws one side's surfels, so each side's share of every prefix must cover the sheet on its own.
TEST(Surfelize, EachSideOfAThinSurfaceIsSpreadOnItsOwn) {
  Mesh sheet = test::gridSheet(80, [](float, float) { return 0.0f; });  // 12,800 triangles at z = 0
  const Scene scene = test::sceneOf(std::move(sheet), {glm::dmat4(1.0)});
  const SurfelFile file = surfelize(scene, analyzeHierarchy(scene), smallOptions(1000));
  ASSERT_EQ(file.arrays.size(), 1u);
  const std::vector<Surfel>& surfels = file.arrays[0].surfels;
  for (const std::size_t k : {std::size_t(40), std::size_t(160)}) {
    for (const float side : {-1.0f, 1.0f}) {
      std::vector<glm::vec2> own;
      for (std::size_t i = 0; i < k; ++i)
        if (surfels[i].normal.z * side > 0.5f) own.emplace_back(surfels[i].position);
      ASSERT_GE(own.size(), k / 3) << "side " << side << " of prefix " << k;
      // The covering radius: the farthest any point of the sheet is from this side's surfels.
      double covering = 0.0;
      for (int y = 0; y <= 40; ++y)
        for (int x = 0; x <= 40; ++x) {
          const glm::vec2 p(-1.0f + x / 20.0f, -1.0f + y / 20.0f);
          double nearest = 1e9;
          for (const glm::vec2& q : own) nearest = std::min(nearest, double(glm::length(p - q)));
          covering = std::max(covering, nearest);
        }
      // Hexagonal packing of m points on area 4 leaves a covering radius of 0.62 √(4 / m); farthest-point
      // sets stay within twice the best.
      EXPECT_LT(covering, 2.0 * 0.62 * std::sqrt(4.0 / double(own.size()))) << "side " << side << " of prefix " << k;
    }
  }
}

// Twins: the same surface seen from its two sides. An open sheet captured from above and below has them
// everywhere, a closed box none, whatever the winding of its faces (the fixture's box is wound half
// inward, so its captures see half its faces from behind); the file records the share, and only the sheet
// is drawn as one.
TEST(Surfelize, OpenSheetsHaveTwinsAndClosedMeshesNone) {
  const Scene sheet =
      test::sceneOf(test::gridSheet(80, [](float x, float) { return 0.1f * x * x; }), {glm::dmat4(1.0)});
  const Scene box = test::sceneOf(test::tessellatedBox(40), {glm::dmat4(1.0)});
  const SurfelFile sheetFile = surfelize(sheet, analyzeHierarchy(sheet), smallOptions(1000));
  const SurfelFile boxFile = surfelize(box, analyzeHierarchy(box), smallOptions(1000));
  ASSERT_EQ(sheetFile.arrays.size(), 1u);
  ASSERT_EQ(boxFile.arrays.size(), 1u);
  EXPECT_GT(sheetFile.arrays[0].twoSidedShare, 0.9f);
  EXPECT_LT(boxFile.arrays[0].twoSidedShare, 0.05f);
  EXPECT_TRUE(splatArrayOf(sheetFile.arrays[0]).openSheet);
  EXPECT_FALSE(splatArrayOf(boxFile.arrays[0]).openSheet);

  // By hand: two parallel planes of opposite normals are twins within reach of their gap, not beyond it;
  // surfels without a normal count for neither.
  std::vector<Surfel> shell;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      shell.push_back({glm::vec3(x, y, 0.0f), glm::vec3(0, 0, 1), glm::u8vec4(255)});
      shell.push_back({glm::vec3(x + 0.5f, y + 0.5f, -0.4f), glm::vec3(0, 0, -1), glm::u8vec4(255)});
    }
  EXPECT_DOUBLE_EQ(twoSidedShare(shell, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(twoSidedShare(shell, 0.5), 0.0) << "the nearest twin is √(0.5 + 0.16) = 0.81 away";
  shell.push_back({glm::vec3(20.0f), glm::vec3(0.0f), glm::u8vec4(255)});
  EXPECT_DOUBLE_EQ(twoSidedShare(shell, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(twoSidedShare({}, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(twoSidedShare(shell, 0.0), 0.0);
}

TEST(Surfelize, SeedChangesTheOrderNotTheSurface) {
  const Scene scene = twoIdenticalGroups();
  SurfelizeOptions a = smallOptions(1000), b = smallOptions(1000);
  b.file.seed = 2;
  const SurfelFile fa = surfelize(scene, analyzeHierarchy(scene), a);
  const SurfelFile fb = surfelize(scene, analyzeHierarchy(scene), b);
  EXPECT_NE(fa.arrays[2].surfels.front().position, fb.arrays[2].surfels.front().position);
  EXPECT_EQ(fa.arrays[2].coverage, fb.arrays[2].coverage);
}

// The tessellated box with a colour per face, alone in its scene: its root's array is captured from
// its triangles in the frame of the scene, so a test can repeat the capture and the ordering.
Scene sixColourBox() {
  Mesh box = test::tessellatedBox(10);
  const std::uint32_t perFace = std::uint32_t(box.indices.size() / 6);
  box.parts.clear();
  for (std::uint32_t face = 0; face < 6; ++face) box.parts.push_back(MeshPart{face * perFace, perFace, face});
  Scene scene = test::sceneOf(std::move(box), {glm::dmat4(1.0)});
  for (std::uint32_t face = 0; face < 6; ++face)
    scene.materials[face].baseColorFactor =
        glm::vec4(face & 1 ? 0.9f : 0.1f, face & 2 ? 0.8f : 0.2f, face & 4 ? 0.7f : 0.3f, 1.0f);
  return scene;
}

// --colors pixel keeps each surfel's own captured pixel, as before the colour filter; prefiltered
// changes the colours only, to prefilteredColors of the same candidates and order.
TEST(Surfelize, PixelColorsAreTheCapturedOnesAndPrefilteredTheirFilter) {
  const Scene scene = sixColourBox();
  const Hierarchy hierarchy = analyzeHierarchy(scene);
  SurfelizeOptions options = smallOptions(1000);
  options.file.colors = SurfelColors::Pixel;
  const SurfelFile pixel = surfelize(scene, hierarchy, options);
  options.file.colors = SurfelColors::Prefiltered;
  const SurfelFile filtered = surfelize(scene, hierarchy, options);
  ASSERT_EQ(pixel.arrays.size(), 1u);
  ASSERT_EQ(filtered.arrays.size(), 1u);
  ASSERT_EQ(pixel.nodes.at(0).path, "/0");

  // The capture and ordering surfelize makes for the root, repeated.
  const CaptureResult captured =
      captureNode(scene, analyzeSubtree(scene, 0), 0,
                  {.resolution = options.file.resolution, .directions = options.file.directions});
  const std::vector<glm::vec3> positions = orderingPositions(captured.surfels);
  Hash64 seed(options.file.seed);
  seed.string("/0");
  const std::vector<std::uint32_t> order =
      orderPoints(options.file.ordering, positions, options.file.maxSurfels, seed.digest());
  const std::vector<glm::u8vec4> colors = prefilteredColors(positions, captured.surfels, order);

  const std::vector<Surfel>& a = pixel.arrays[0].surfels;
  const std::vector<Surfel>& b = filtered.arrays[0].surfels;
  ASSERT_EQ(a.size(), order.size());
  ASSERT_EQ(b.size(), order.size());
  std::size_t changed = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Surfel& candidate = captured.surfels[order[i]];
    ASSERT_EQ(a[i].position, candidate.position) << i;
    ASSERT_EQ(a[i].normal, candidate.normal) << i;
    ASSERT_EQ(a[i].color, candidate.color) << i;
    ASSERT_EQ(b[i].position, candidate.position) << i;
    ASSERT_EQ(b[i].normal, candidate.normal) << i;
    ASSERT_EQ(b[i].color, colors[i]) << i;
    changed += b[i].color != a[i].color;
  }
  // The first surfel mixes all six faces; late ones near an edge mix two or three.
  EXPECT_NE(b[0].color, a[0].color);
  EXPECT_GT(changed, 10u);
}

// What drawing an array's surfels (splats as wide as their spacing) misses or adds against the exact
// triangles, over four views of the array's node: the fraction of pixels covered by exactly one of
// the two, and the RMSE of the base colour over the pixels either covers (0…255 per channel).
struct SplatError {
  double mismatch = 0.0;
  double colorRmse = 0.0;
};

SplatError splatError(const Scene& scene, std::uint32_t node, const SurfelArray& array) {
  const Hierarchy frame = analyzeSubtree(scene, node);
  const std::vector<std::uint32_t> nodes = subtreeNodes(scene, node);
  const SplatArray drawable = splatArrayOf(array);
  const double spacing = drawable.spacing(drawable.size());
  std::uint64_t mismatched = 0, either = 0;
  double squared = 0.0;
  const std::vector<glm::dvec3> views = {{1, 0.3, 0.2}, {-0.4, 1, 0.5}, {0.2, -0.5, -1}, {-1, -1, 1}};
  for (const glm::dvec3& direction : views) {
    const Camera camera = boxViewCamera(array.box, glm::normalize(direction), 256);
    const double pixel = 2.0 / (camera.projection[0][0] * camera.width);
    Framebuffer exact = makeFramebuffer(camera.width, camera.height, kChannelColor);
    drawNodeTriangles(scene, frame, nodes, camera, exact);
    Framebuffer splats = makeFramebuffer(camera.width, camera.height, kChannelColor);
    const PointSet set{.positions = drawable.positions,
                       .normals = drawable.normals,
                       .colors = drawable.colors,
                       .worldFromObject = glm::translate(glm::dmat4(1.0), array.box.center()),
                       .pointSize = float(std::max(1.0, 1.25 * spacing / pixel))};
    drawPoints(splats, camera, std::span(&set, 1));
    for (std::size_t i = 0; i < exact.pixelCount(); ++i) {
      if (!exact.covered(i) && !splats.covered(i)) continue;
      ++either;
      if (exact.covered(i) != splats.covered(i)) ++mismatched;
      const glm::dvec4 d = glm::dvec4(exact.color[i]) - glm::dvec4(splats.color[i]);
      squared += glm::dot(glm::dvec3(d), glm::dvec3(d)) / 3.0;
    }
  }
  return {double(mismatched) / double(either), std::sqrt(squared / double(either))};
}

// The capture of inner nodes from their children's surfels instead of their triangles: how much image
// error it adds, on a city of two shared meshes (root and blocks are inner nodes, the instances leaves).
TEST(Surfelize, ChildSurfelCaptureErrorOnSharedScene) {
  PBS_SHARED_SCENE(spot, "spot.glb");
  PBS_SHARED_SCENE(teapot, "teapot.glb");
  const Scene city =
      generateCity({importGltf(spot).scene, importGltf(teapot).scene}, CityOptions{.levels = 2, .fanout = 4});
  validateScene(city, "city");
  const Hierarchy hierarchy = analyzeHierarchy(city);
  SurfelizeOptions options;
  options.file.threshold = 5000;
  options.file.maxSurfels = 10000;
  options.file.resolution = 256;
  options.source = CaptureSource::Triangles;
  const SurfelFile exact = surfelize(city, hierarchy, options);
  options.source = CaptureSource::ChildSurfels;
  const SurfelFile fromChildren = surfelize(city, hierarchy, options);
  ASSERT_EQ(exact.nodes.size(), fromChildren.nodes.size());
  ASSERT_EQ(exact.nodes.front().path, "/0");

  const std::uint32_t root = city.roots.front();
  const SplatError e = splatError(city, root, exact.arrays[exact.nodes.front().array]);
  const SplatError c = splatError(city, root, fromChildren.arrays[fromChildren.nodes.front().array]);
  std::printf(
      "root drawn from its surfels vs its triangles (4 views, 256 px):\n"
      "  captured from triangles:       coverage mismatch %.4f, colour RMSE %.2f\n"
      "  captured from child surfels:   coverage mismatch %.4f, colour RMSE %.2f\n",
      e.mismatch, e.colorRmse, c.mismatch, c.colorRmse);
  RecordProperty("triangles_mismatch", std::to_string(e.mismatch));
  RecordProperty("children_mismatch", std::to_string(c.mismatch));
  // Both represent the root: splats overhang silhouettes by up to half a splat, and 10,000 surfels
  // for sixteen models make wide splats at 256 px (measured: about 0.17 of the pixels either covers
  // disagree, both ways), and the child-surfel capture costs at most a little more.
  EXPECT_LT(e.mismatch, 0.25);
  EXPECT_LT(c.mismatch, 0.25);
  EXPECT_LT(c.mismatch, e.mismatch * 1.5 + 0.01);
  EXPECT_LT(c.colorRmse, e.colorRmse * 1.5 + 5.0);
  // Leaves have no children with arrays: both ways capture them from triangles, identically.
  const std::uint32_t leafArray = exact.nodes.back().array;
  EXPECT_EQ(exact.arrays[leafArray].surfels.size(), fromChildren.arrays[leafArray].surfels.size());
  EXPECT_EQ(exact.arrays[leafArray].surfels.front().position, fromChildren.arrays[leafArray].surfels.front().position);
}

// The thresholds are named by their unit (--min-triangles, render's --threshold-pixels); the old shared
// spelling --threshold still works, says what to write instead on stderr, and gives the same results.
TEST(SurfelizeCli, OldThresholdSpellingStillWorksWithAWarning) {
  ScratchDir scratch;
  const std::string scene = groupsFile(scratch);
  const auto run = [&](const std::string& arguments) { return test::runPbs(arguments); };
  const std::string surfelize = "surfelize " + scene + " --max-surfels 300 --resolution 48 --quiet -o '";
  const test::CommandResult current = run(surfelize + (scratch / "new.surfels").string() + "' --min-triangles 1000");
  ASSERT_EQ(current.status, 0) << current.err;
  EXPECT_TRUE(current.err.empty()) << current.err;
  const test::CommandResult old = run(surfelize + (scratch / "old.surfels").string() + "' --threshold 1000");
  ASSERT_EQ(old.status, 0) << old.err;
  EXPECT_EQ(old.err, "warning: --threshold is deprecated here: write --min-triangles\n");
  EXPECT_EQ(test::readFile(scratch / "old.surfels"), test::readFile(scratch / "new.surfels"));

  const std::string render =
      "render " + scene + " --surfels '" + (scratch / "new.surfels").string() + "' --size 96x64 --json ";
  const test::CommandResult pixels = run(render + "--threshold-pixels 40");
  const test::CommandResult oldPixels = run(render + "--threshold 40");
  ASSERT_EQ(pixels.status, 0) << pixels.err;
  ASSERT_EQ(oldPixels.status, 0) << oldPixels.err;
  EXPECT_EQ(oldPixels.err, "warning: --threshold is deprecated here: write --threshold-pixels\n");
  EXPECT_EQ(nlohmann::json::parse(oldPixels.out)["surfels"], nlohmann::json::parse(pixels.out)["surfels"]);
  EXPECT_EQ(run(render + "--threshold 0").status, 2) << "the old spelling keeps the check";
}

TEST(SurfelizeCli, WritesTheFileAndReportsJson) {
  ScratchDir scratch;
  groupsFile(scratch);
  const auto out = scratch / "groups.surfels";
  const test::CommandResult run =
      test::runPbs("surfelize '" + (scratch / "groups.glb").string() + "' -o '" + out.string() +
                   "' --min-triangles 1000 --max-surfels 500 --resolution 96 --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(run.out);
  for (const char* key : {"nodes_with_surfels", "arrays", "surfels", "captures", "seconds", "bytes"})
    EXPECT_TRUE(report.contains(key)) << key;
  EXPECT_EQ(report["nodes_with_surfels"], 7);
  EXPECT_EQ(report["arrays"], 3);
  EXPECT_EQ(report["captures"], 3);
  EXPECT_EQ(report["surfels"], 1500);
  EXPECT_EQ(report["bytes"], std::filesystem::file_size(out));
  // One plain material: every array one colour, stored once (12 bytes a surfel).
  EXPECT_EQ(report["color_encodings"]["constant"], 3) << report["color_encodings"];
  EXPECT_EQ(report["color_encodings"]["rgb"], 0);
  EXPECT_EQ(report["color_encodings"]["rgba"], 0);
  const nlohmann::json gbuffer = {"depth", "color", "position", "normal"}, cleared = {"depth"};
  EXPECT_EQ(report["used"]["capture_gbuffer"], gbuffer) << "no ids or coverage in a capture";
  EXPECT_EQ(report["used"]["cleared_each_view"], cleared);
  EXPECT_EQ(report["used"]["color_encodings"], report["color_encodings"]);
  EXPECT_LT(report["bytes_per_surfel"].get<double>(), 13.0 + 2000.0 / 1500.0) << "12 a surfel, and the tables";
  EXPECT_EQ(run.err, "") << "--json implies no progress output";

  SurfelFileReader reader(out);
  EXPECT_EQ(reader.nodes().size(), 7u);
  EXPECT_EQ(reader.arrays().size(), 3u);
  EXPECT_EQ(reader.options().maxSurfels, 500u);
  EXPECT_EQ(reader.options().resolution, 96u);
  EXPECT_EQ(reader.readPrefix(2, 100).size(), 100u);
}

TEST(SurfelizeCli, ColorsOptionIsRecordedInTheFile) {
  ScratchDir scratch;
  const std::string scene = groupsFile(scratch);
  const auto out = scratch / "pixel.surfels";
  const std::string common = " --min-triangles 1000 --max-surfels 300 --resolution 64 --quiet";
  const test::CommandResult run =
      test::runPbs("surfelize " + scene + " -o '" + out.string() + "' --colors prefiltered --json" + common);
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(nlohmann::json::parse(run.out)["colors"], "prefiltered");
  EXPECT_EQ(SurfelFileReader(out).options().colors, SurfelColors::Prefiltered);
  const test::CommandResult analyzed = test::runPbs("analyze '" + out.string() + "' --no-spectrum");
  ASSERT_EQ(analyzed.status, 0) << analyzed.err;
  EXPECT_NE(analyzed.out.find("prefiltered colours"), std::string::npos) << analyzed.out;

  const auto byDefault = scratch / "default.surfels";
  ASSERT_EQ(test::runPbs("surfelize " + scene + " -o '" + byDefault.string() + "'" + common).status, 0);
  EXPECT_EQ(SurfelFileReader(byDefault).options().colors, SurfelColors::Pixel);

  const test::CommandResult bad =
      test::runPbs("surfelize " + scene + " -o '" + out.string() + "' --colors mean" + common);
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.err.find("--colors"), std::string::npos) << bad.err;
}

TEST(SurfelizeCli, ProgressLinesWhenStderrIsNotATerminal) {
  ScratchDir scratch;
  const std::string scene = groupsFile(scratch);
  const test::CommandResult run = test::runPbs("surfelize " + scene + " -o '" + (scratch / "d.surfels").string() +
                                               "' --min-triangles 1000 --max-surfels 100 --resolution 64");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.err.find("surfelize: 100%"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find('\r'), std::string::npos) << "no bar redraws in a log";
  EXPECT_NE(run.out.find("arrays"), std::string::npos);
  const test::CommandResult quiet = test::runPbs("surfelize " + scene + " -o '" + (scratch / "q.surfels").string() +
                                                 "' --min-triangles 1000 --max-surfels 100 --resolution 64 --quiet");
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(test::readFile(scratch / "d.surfels"), test::readFile(scratch / "q.surfels"));
}

TEST(SurfelizeCli, SaysSoWhenNoNodeNeedsSurfels) {
  ScratchDir scratch;
  const auto out = scratch / "none.surfels";
  const test::CommandResult run =
      test::runPbs("surfelize " + groupsFile(scratch) + " -o '" + out.string() + "' --min-triangles 1000000000");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("no surfels needed"), std::string::npos) << run.out;
  SurfelFileReader reader(out);
  EXPECT_TRUE(reader.arrays().empty());
}

TEST(SurfelizeCli, AnalyzeReadsTheFileAndChecksItsScene) {
  ScratchDir scratch;
  const std::string scene = groupsFile(scratch);
  const auto out = scratch / "groups.surfels";
  ASSERT_EQ(test::runPbs("surfelize " + scene + " -o '" + out.string() +
                         "' --min-triangles 1000 --max-surfels 800 "
                         "--resolution 96 --quiet")
                .status,
            0);
  const test::CommandResult analyzed =
      test::runPbs("analyze '" + out.string() + "' --scene " + scene + " --no-spectrum --json");
  ASSERT_EQ(analyzed.status, 0) << analyzed.err;
  const nlohmann::json report = nlohmann::json::parse(analyzed.out);
  ASSERT_EQ(report["nodes"].size(), 7u);
  for (const nlohmann::json& node : report["nodes"]) {
    EXPECT_EQ(node["count"], 800);
    EXPECT_GT(node["rho_min"].get<double>(), 0.0);
    EXPECT_GT(node["area"].get<double>(), 0.0);
  }
  EXPECT_EQ(report["nodes"][2]["rho_min"], report["nodes"][3]["rho_min"]) << "shared array, same values";

  // The same file against another scene: one error line naming the file and its header.
  Scene other = twoIdenticalGroups();
  other.nodes[1].local[3][1] += 1.0;
  writeGlb(other, scratch / "other.glb");
  const test::CommandResult mismatch =
      test::runPbs("analyze '" + out.string() + "' --scene '" + (scratch / "other.glb").string() + "' --no-spectrum");
  EXPECT_EQ(mismatch.status, 1);
  EXPECT_EQ(mismatch.err.rfind("error: " + out.string() + ": header: made for another scene", 0), 0u) << mismatch.err;
}

TEST(SurfelizeCli, BadInputGivesOneErrorLine) {
  ScratchDir scratch;
  const test::CommandResult missing =
      test::runPbs("surfelize '" + (scratch / "nope.glb").string() + "' -o '" + (scratch / "x.surfels").string() + "'");
  EXPECT_EQ(missing.status, 1);
  EXPECT_EQ(missing.err.rfind("error: ", 0), 0u) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(scratch / "x.surfels"));
  const test::CommandResult badOrdering = test::runPbs("surfelize default -o x.surfels --ordering best");
  EXPECT_EQ(badOrdering.status, 2);
  const test::CommandResult noDir =
      test::runPbs("surfelize " + groupsFile(scratch) + " -o '" + (scratch / "missing" / "x.surfels").string() + "'");
  EXPECT_EQ(noDir.status, 1);
  EXPECT_NE(noDir.err.find("missing"), std::string::npos) << noDir.err;
}

// The default scene in 1, 2, 3 and 7 shards, merged: the one-machine file. Options small enough for a
// test (2.5 s a run) and such that most arrays are captured from triangles, so the shards share them out.
TEST(SurfelizeShards, DefaultSceneMergesToTheSingleRunFor1237Shards) {
  ScratchDir scratch;
  test::expectShardsMergeToTheSingleRun("default", scratch,
                                        " --min-triangles 100000 --resolution 32 --max-surfels 100000 --quiet");
}

}  // namespace
}  // namespace pbs
