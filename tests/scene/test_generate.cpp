// Tests of the procedural scenes: the default plant (valid, within its triangle budget, deep,
// instanced, closed outward-facing meshes, deterministic) and the city of instances, shared or not.
#include "test_support.hpp"

#include <pbs/raster/headlight_shading.hpp>
#include <pbs/raster/orbit_camera.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/generate.hpp>
#include <pbs/scene/gltf_export.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/scene/load_scene.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/surfels/lod_render.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <set>
#include <unordered_map>

namespace pbs {
namespace {

const Scene& plant() {
  static const Scene scene = generateDefaultScene();
  return scene;
}

double signedVolume(const Mesh& mesh) {
  double volume = 0.0;
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const glm::dvec3 a(mesh.positions[mesh.indices[i]]), b(mesh.positions[mesh.indices[i + 1]]),
        c(mesh.positions[mesh.indices[i + 2]]);
    volume += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return volume;
}

// Directed edges, keyed by the bits of their end positions (so texture seams, which repeat a
// position, still join), that no triangle uses in the opposite direction: zero for a closed,
// consistently wound surface.
std::size_t unmatchedEdges(const Mesh& mesh) {
  using Key = std::array<std::uint32_t, 6>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = 0;
      for (std::uint32_t v : k) h = (h ^ v) * 0x100000001B3ull;
      return h;
    }
  };
  const auto bits = [&](std::uint32_t vertex) {
    const glm::vec3 p = mesh.positions[vertex] + glm::vec3(0.0f);  // -0 and +0 are one place
    return std::array<std::uint32_t, 3>{std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y),
                                        std::bit_cast<std::uint32_t>(p.z)};
  };
  std::unordered_map<Key, int, KeyHash> balance;
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
    const std::size_t next = i % 3 == 2 ? i - 2 : i + 1;
    const auto from = bits(mesh.indices[i]), to = bits(mesh.indices[next]);
    const bool forward = from < to;
    const auto& lo = forward ? from : to;
    const auto& hi = forward ? to : from;
    balance[Key{lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]}] += forward ? 1 : -1;
  }
  std::size_t unmatched = 0;
  for (const auto& [edge, count] : balance) unmatched += std::size_t(std::abs(count));
  return unmatched;
}

// Triangles facing away from the normals of their own corners.
std::size_t trianglesAgainstNormals(const Mesh& mesh) {
  std::size_t against = 0;
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const std::uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
    const glm::vec3 face = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    if (glm::dot(face, mesh.normals[a] + mesh.normals[b] + mesh.normals[c]) <= 0.0f) ++against;
  }
  return against;
}

template <glm::length_t L>
bool finite(const glm::vec<L, float>& v) {
  return !glm::any(glm::isnan(v)) && !glm::any(glm::isinf(v));
}

void expectUnitFiniteNormals(const Mesh& mesh) {
  std::size_t bad = 0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const bool finite = pbs::finite(mesh.positions[v]) && pbs::finite(mesh.normals[v]) &&
                        (mesh.uvs.empty() || pbs::finite(mesh.uvs[v]));
    if (!finite || std::abs(glm::length(mesh.normals[v]) - 1.0f) > 1e-5f) ++bad;
  }
  EXPECT_EQ(bad, 0u) << mesh.name << ": vertices with a non-finite value or a normal not of unit length";
}

void expectSameScene(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t n = 0; n < a.nodes.size(); ++n) {
    EXPECT_EQ(a.nodes[n].name, b.nodes[n].name);
    EXPECT_TRUE(a.nodes[n].local == b.nodes[n].local) << a.nodes[n].name;
    EXPECT_EQ(a.nodes[n].children, b.nodes[n].children);
    EXPECT_EQ(a.nodes[n].mesh, b.nodes[n].mesh);
  }
  EXPECT_EQ(a.roots, b.roots);
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    EXPECT_TRUE(a.meshes[m].positions == b.meshes[m].positions) << a.meshes[m].name;
    EXPECT_TRUE(a.meshes[m].normals == b.meshes[m].normals) << a.meshes[m].name;
    EXPECT_TRUE(a.meshes[m].uvs == b.meshes[m].uvs) << a.meshes[m].name;
    EXPECT_TRUE(a.meshes[m].indices == b.meshes[m].indices) << a.meshes[m].name;
  }
  ASSERT_EQ(a.textures.size(), b.textures.size());
  for (std::size_t t = 0; t < a.textures.size(); ++t) EXPECT_TRUE(a.textures[t].rgba8 == b.textures[t].rgba8);
}

TEST(DefaultScene, IsValidDeepInstancedAndWithinItsBudget) {
  const Scene& scene = plant();
  ASSERT_NO_THROW(validateScene(scene, "default"));
  const SceneSummary summary = summarizeScene(scene, analyzeHierarchy(scene));
  EXPECT_GE(summary.triangles, 10'000'000u);
  EXPECT_LE(summary.triangles, 50'000'000u);
  EXPECT_LE(summary.uniqueTriangles, 1'200'000u);
  EXPECT_GE(summary.maxDepth, 5u);
  EXPECT_GE(summary.meshes, 12u);
  EXPECT_LE(summary.meshes, 40u);
  EXPECT_GE(summary.instances, 20 * summary.meshes);
  EXPECT_LE(summary.instances, 10'000u);
  EXPECT_FALSE(summary.bounds.empty());
  RecordProperty("instanced_triangles", std::to_string(summary.triangles));
  RecordProperty("unique_triangles", std::to_string(summary.uniqueTriangles));
}

TEST(DefaultScene, UsesTexturedAndPlainMaterialsWithUvsWhereTextured) {
  const Scene& scene = plant();
  bool textured = false, plain = false;
  for (const Mesh& mesh : scene.meshes) {
    const bool anyTexture = std::any_of(mesh.parts.begin(), mesh.parts.end(), [&](const MeshPart& part) {
      return scene.materials[part.material].baseColorTexture >= 0;
    });
    EXPECT_EQ(mesh.uvs.empty(), !anyTexture) << mesh.name << ": uvs exactly where a texture reads them";
    for (const MeshPart& part : mesh.parts) {
      const Material& material = scene.materials[part.material];
      if (material.baseColorTexture >= 0) {
        textured = true;
        EXPECT_FALSE(mesh.uvs.empty()) << mesh.name << " is textured but has no uvs";
      } else {
        plain = true;
      }
    }
  }
  EXPECT_TRUE(textured);
  EXPECT_TRUE(plain);
  for (const Texture& texture : scene.textures) {
    EXPECT_EQ(texture.width, 256u);
    EXPECT_EQ(texture.height, 256u);
    EXPECT_EQ(texture.wrapS, TextureWrap::Repeat);
    EXPECT_EQ(texture.wrapT, TextureWrap::Repeat);
    // A pattern, not a flat fill.
    EXPECT_NE(std::adjacent_find(texture.rgba8.begin(), texture.rgba8.end(), std::not_equal_to<>()),
              texture.rgba8.end());
  }
}

TEST(DefaultScene, NormalsAreUnitAndNothingIsNotFinite) {
  for (const Mesh& mesh : plant().meshes) expectUnitFiniteNormals(mesh);
}

TEST(DefaultScene, MeshesAreClosedAndFaceOutward) {
  for (const Mesh& mesh : plant().meshes) {
    EXPECT_EQ(unmatchedEdges(mesh), 0u) << mesh.name << " has holes or inconsistent winding";
    EXPECT_GT(signedVolume(mesh), 0.0) << mesh.name << " faces inward";
    EXPECT_EQ(trianglesAgainstNormals(mesh), 0u) << mesh.name;
  }
}

TEST(DefaultScene, IsDeterministic) {
  const auto start = std::chrono::steady_clock::now();
  const Scene again = generateDefaultScene();
  RecordProperty(
      "generation_ms",
      std::to_string(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()));
  expectSameScene(plant(), again);
}

// A prototype holding the plant's meshes of the given names under a turned parent, each child
// mirrored or not, with all the plant's materials and textures.
Scene prototype(const std::vector<std::pair<std::string, bool>>& children) {
  const Scene& source = plant();
  Scene scene;
  scene.materials = source.materials;
  scene.textures = source.textures;
  scene.nodes.push_back({"prototype", glm::rotate(glm::dmat4(1.0), 0.4, glm::dvec3(0, 1, 0)), {}, -1});
  scene.roots = {0};
  for (const auto& [name, mirrored] : children) {
    const auto mesh = std::find_if(source.meshes.begin(), source.meshes.end(),
                                   [&wanted = name](const Mesh& m) { return m.name == wanted; });
    EXPECT_NE(mesh, source.meshes.end()) << name;
    scene.meshes.push_back(*mesh);
    const glm::dmat4 local = glm::translate(glm::dmat4(1.0), glm::dvec3(double(scene.meshes.size()), 0, 0)) *
                             glm::scale(glm::dmat4(1.0), glm::dvec3(mirrored ? -1.0 : 1.0, 1.0, 1.0));
    scene.nodes[0].children.push_back(std::uint32_t(scene.nodes.size()));
    scene.nodes.push_back({name, local, {}, std::int32_t(scene.meshes.size() - 1)});
  }
  return scene;
}

std::vector<Scene> cityPrototypes() {
  // The pump is mirrored whole, so its flattened mesh shows whether mirroring kept faces outward.
  return {prototype({{"valve", false}, {"flange", true}}), prototype({{"pump", true}}),
          prototype({{"large gear", false}, {"shaft", false}})};
}

std::uint64_t instancedTriangles(const Scene& scene) {
  return summarizeScene(scene, analyzeHierarchy(scene)).triangles;
}

TEST(City, HasFanoutToTheLevelsLeavesAndTheirTriangles) {
  const std::vector<Scene> prototypes = cityPrototypes();
  const Scene city = generateCity(prototypes, CityOptions{3, 7, 11});
  ASSERT_NO_THROW(validateScene(city, "city"));
  const Hierarchy hierarchy = analyzeHierarchy(city);
  const SceneSummary summary = summarizeScene(city, hierarchy);

  std::uint64_t leaves = 0, leafTriangles = 0, mirrored = 0;
  for (std::size_t n = 0; n < city.nodes.size(); ++n) {
    const Node& node = city.nodes[n];
    EXPECT_EQ(node.children.empty(), node.mesh >= 0) << "blocks hold no mesh, leaves do";
    if (node.mesh < 0) continue;
    ++leaves;
    leafTriangles += city.meshes[std::size_t(node.mesh)].triangleCount();
    mirrored += glm::determinant(glm::dmat3(hierarchy.world[n])) < 0.0 ? 1 : 0;
    EXPECT_EQ(hierarchy.depth[n], 3u);
  }
  EXPECT_EQ(leaves, 7u * 7u * 7u);
  EXPECT_EQ(summary.triangles, leafTriangles);
  EXPECT_GT(mirrored, leaves / 10);
  EXPECT_LT(mirrored, leaves * 2 / 5);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_TRUE(std::isfinite(summary.bounds.min[axis]));
    EXPECT_TRUE(std::isfinite(summary.bounds.max[axis]));
  }
  EXPECT_FALSE(summary.bounds.empty());
}

TEST(City, FlattensEachPrototypeIntoOneUnitSizeClosedMesh) {
  const std::vector<Scene> prototypes = cityPrototypes();
  const Scene city = generateCity(prototypes, CityOptions{1, 4, 3});
  ASSERT_EQ(city.meshes.size(), prototypes.size());
  ASSERT_EQ(city.textures.size(), 3 * plant().textures.size());
  ASSERT_EQ(city.materials.size(), 3 * plant().materials.size());
  for (std::size_t p = 0; p < prototypes.size(); ++p) {
    const Mesh& mesh = city.meshes[p];
    EXPECT_EQ(mesh.triangleCount(), instancedTriangles(prototypes[p])) << mesh.name;
    const glm::dvec3 size = mesh.bounds.size();
    EXPECT_NEAR(std::max({size.x, size.y, size.z}), 1.0, 1e-5) << mesh.name;
    EXPECT_NEAR(mesh.bounds.center().x, 0.0, 1e-5) << mesh.name;
    EXPECT_NEAR(mesh.bounds.center().z, 0.0, 1e-5) << mesh.name;
    EXPECT_NEAR(mesh.bounds.min.y, 0.0, 1e-5) << mesh.name;
    expectUnitFiniteNormals(mesh);
    EXPECT_EQ(unmatchedEdges(mesh), 0u) << mesh.name;
    EXPECT_GT(signedVolume(mesh), 0.0) << mesh.name << " faces inward";
    EXPECT_EQ(trianglesAgainstNormals(mesh), 0u) << mesh.name;
    // Materials keep their textures, now the city's copies.
    for (const MeshPart& part : mesh.parts) {
      const Material& material = city.materials[part.material];
      const Material& original = plant().materials[part.material % plant().materials.size()];
      EXPECT_EQ(material.name, original.name);
      if (original.baseColorTexture >= 0) {
        EXPECT_TRUE(city.textures[std::size_t(material.baseColorTexture)].rgba8 ==
                    plant().textures[std::size_t(original.baseColorTexture)].rgba8);
      }
    }
  }
}

TEST(City, IsDeterministicPerSeedAndDiffersAcrossSeeds) {
  const std::vector<Scene> prototypes = cityPrototypes();
  const Scene a = generateCity(prototypes, CityOptions{2, 9, 42});
  expectSameScene(a, generateCity(prototypes, CityOptions{2, 9, 42}));
  const Scene b = generateCity(prototypes, CityOptions{2, 9, 43});
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  std::size_t differentTransforms = 0, differentMeshes = 0;
  for (std::size_t n = 0; n < a.nodes.size(); ++n) {
    differentTransforms += a.nodes[n].local != b.nodes[n].local ? 1 : 0;
    differentMeshes += a.nodes[n].mesh != b.nodes[n].mesh ? 1 : 0;
  }
  EXPECT_GT(differentTransforms, a.nodes.size() / 2);
  EXPECT_GT(differentMeshes, 0u);
}

TEST(City, TwentyThousandLeaves) {
  const Scene city = generateCity(cityPrototypes(), CityOptions{2, 150, 1});
  const SceneSummary summary = summarizeScene(city, analyzeHierarchy(city));
  EXPECT_EQ(summary.instances, 22'500u);
  EXPECT_EQ(summary.nodes, 1u + 150u + 22'500u);
}

TEST(City, LevelsZeroIsOneInstance) {
  const Scene city = generateCity(cityPrototypes(), CityOptions{0, 5, 1});
  ASSERT_EQ(city.nodes.size(), 1u);
  EXPECT_GE(city.nodes[0].mesh, 0);
  EXPECT_EQ(city.roots, std::vector<std::uint32_t>{0});
}

TEST(City, RejectsWhatItCannotBuild) {
  EXPECT_THROW(generateCity({}, CityOptions{}), std::invalid_argument);
  EXPECT_THROW(generateCity(cityPrototypes(), CityOptions{2, 0, 1}), std::invalid_argument);
  EXPECT_THROW(generateCity(cityPrototypes(), CityOptions{40, 10, 1}), std::invalid_argument);
  Scene empty;
  empty.nodes.push_back({"nothing", glm::dmat4(1.0), {}, -1});
  empty.roots = {0};
  EXPECT_THROW(generateCity({empty}, CityOptions{}), InputError);
}

// The unique city against the instanced one of the same options.
struct CityPair {
  Scene instanced, unique;
  Hierarchy instancedHierarchy, uniqueHierarchy;
};

CityPair cityPair(const CityOptions& options) {
  CityOptions unique = options;
  unique.unique = true;
  CityPair pair{generateCity(cityPrototypes(), options), generateCity(cityPrototypes(), unique), {}, {}};
  pair.instancedHierarchy = analyzeHierarchy(pair.instanced);
  pair.uniqueHierarchy = analyzeHierarchy(pair.unique);
  return pair;
}

TEST(UniqueCity, GivesEveryLeafAMeshOfItsOwnWithItsPlacementBakedIn) {
  const CityPair city = cityPair(CityOptions{.levels = 2, .fanout = 6, .seed = 9});
  ASSERT_NO_THROW(validateScene(city.unique, "unique city"));
  ASSERT_EQ(city.unique.nodes.size(), city.instanced.nodes.size());
  std::set<std::int32_t> used;
  std::uint64_t leaves = 0;
  for (std::size_t n = 0; n < city.unique.nodes.size(); ++n) {
    const Node& node = city.unique.nodes[n];
    const Node& original = city.instanced.nodes[n];
    EXPECT_EQ(node.name, original.name);
    EXPECT_EQ(node.children, original.children);
    EXPECT_EQ(node.mesh >= 0, original.mesh >= 0);
    if (node.mesh < 0) {
      EXPECT_TRUE(node.local == original.local) << "blocks keep their placement";
      continue;
    }
    ++leaves;
    EXPECT_TRUE(used.insert(node.mesh).second) << "mesh " << node.mesh << " used twice";
    EXPECT_TRUE(node.local == glm::dmat4(1.0)) << "the placement is in the vertices";
    const Mesh& mesh = city.unique.meshes[std::size_t(node.mesh)];
    const Mesh& prototype = city.instanced.meshes[std::size_t(original.mesh)];
    EXPECT_EQ(mesh.triangleCount(), prototype.triangleCount());
    EXPECT_EQ(mesh.positions.size(), prototype.positions.size());
    EXPECT_EQ(mesh.uvs.size(), prototype.uvs.size());
    expectUnitFiniteNormals(mesh);
    // Mirrored placements reverse the winding, so faces still point along their normals.
    EXPECT_EQ(trianglesAgainstNormals(mesh), 0u) << mesh.name;
    for (std::size_t v = 0; v < mesh.positions.size(); v += 97) {
      const glm::dvec3 placed = glm::dvec3(original.local * glm::dvec4(glm::dvec3(prototype.positions[v]), 1.0));
      EXPECT_LT(glm::length(glm::dvec3(mesh.positions[v]) - placed), 1e-5) << mesh.name;
    }
  }
  EXPECT_EQ(leaves, 36u);
  EXPECT_EQ(city.unique.meshes.size(), leaves) << "no prototype left over, no mesh shared";
  EXPECT_EQ(city.unique.materials.size(), city.instanced.materials.size());
  EXPECT_EQ(city.unique.textures.size(), city.instanced.textures.size());

  const SceneSummary unique = summarizeScene(city.unique, city.uniqueHierarchy);
  const SceneSummary instanced = summarizeScene(city.instanced, city.instancedHierarchy);
  EXPECT_EQ(unique.triangles, instanced.triangles);
  EXPECT_EQ(unique.uniqueTriangles, instanced.triangles) << "every instanced triangle stored once";
  const double diagonal = glm::length(instanced.bounds.size());
  EXPECT_LT(glm::length(unique.bounds.min - instanced.bounds.min), 1e-6 * diagonal);
  EXPECT_LT(glm::length(unique.bounds.max - instanced.bounds.max), 1e-6 * diagonal);
}

TEST(UniqueCity, IsTheSameForAnyThreadCountAndLevelsZeroWorks) {
  CityOptions options{.levels = 2, .fanout = 5, .seed = 3};
  options.unique = true;
  Scene one, two;
  runWithThreads(1, [&] { one = generateCity(cityPrototypes(), options); });
  runWithThreads(2, [&] { two = generateCity(cityPrototypes(), options); });
  expectSameScene(one, two);
  options.levels = 0;
  const Scene single = generateCity(cityPrototypes(), options);
  ASSERT_EQ(single.meshes.size(), 1u);
  EXPECT_EQ(single.nodes[0].mesh, 0);
  EXPECT_TRUE(single.nodes[0].local == glm::dmat4(1.0));
}

// The shaded picture (headlight_shading.hpp) drawn exactly by the rasterizer.
std::vector<glm::vec4> exactPicture(const Scene& scene, const Hierarchy& hierarchy, const Camera& camera) {
  Framebuffer gbuffer = makeFramebuffer(camera.width, camera.height, kChannelColor | kChannelNormal);
  const SceneSurfels none;  // no arrays: every visible mesh is drawn as triangles
  renderLod(scene, hierarchy, none, camera, gbuffer, LodOptions{});
  return shadeHeadlight(gbuffer, camera);
}

TEST(UniqueCity, DrawsTheSamePicture) {
  const CityPair city = cityPair(CityOptions{.levels = 2, .fanout = 9, .seed = 4});
  const Bounds bounds = summarizeScene(city.instanced, city.instancedHierarchy).bounds;
  for (const Orbit& orbit : {Orbit{30.0, 80.0, 1.0}, Orbit{200.0, 30.0, 0.6}, Orbit{100.0, 10.0, 0.3}}) {
    const Camera camera = orbitCamera(bounds.center(), 0.5 * glm::length(bounds.size()), orbit, 240, 160);
    const std::vector<glm::vec4> a = exactPicture(city.instanced, city.instancedHierarchy, camera);
    const std::vector<glm::vec4> b = exactPicture(city.unique, city.uniqueHierarchy, camera);
    std::size_t coveredA = 0, coveredB = 0, differentCoverage = 0, differentColour = 0;
    for (std::size_t p = 0; p < a.size(); ++p) {
      coveredA += a[p].a > 0.0f ? 1 : 0;
      coveredB += b[p].a > 0.0f ? 1 : 0;
      if ((a[p].a > 0.0f) != (b[p].a > 0.0f))
        ++differentCoverage;
      else if (glm::length(glm::vec3(a[p]) - glm::vec3(b[p])) > 0.02f)
        ++differentColour;
    }
    EXPECT_GT(coveredA, a.size() / 20) << "the city is in the picture";
    // Float rounding of the baked vertices moves an edge across a pixel centre now and then.
    EXPECT_LE(differentCoverage, 8u);
    EXPECT_LE(differentColour, a.size() / 500) << "pixels whose colour changed (a different triangle won)";
    RecordProperty("coverage_" + std::to_string(int(orbit.azimuthDegrees)),
                   std::to_string(coveredA) + " vs " + std::to_string(coveredB));
  }
}

TEST(UniqueCity, CommandLineWritesOneMeshPerInstance) {
  test::ScratchDir scratch;
  writeGlb(cityPrototypes()[1], scratch / "pump.glb");
  writeGlb(cityPrototypes()[2], scratch / "gears.glb");
  const std::string output = (scratch / "city.glb").string();
  const test::CommandResult made =
      test::runPbs("generate city --mesh '" + (scratch / "pump.glb").string() + "' --mesh '" +
                   (scratch / "gears.glb").string() + "' --levels 2 --fanout 4 --unique -o '" + output + "'");
  ASSERT_EQ(made.status, 0) << made.err;
  const Scene city = loadScene(output).scene;
  const SceneSummary summary = summarizeScene(city, analyzeHierarchy(city));
  EXPECT_EQ(summary.instances, 16u);
  EXPECT_EQ(summary.meshes, 16u);
  EXPECT_EQ(summary.uniqueTriangles, summary.triangles);
  EXPECT_NE(made.out.find("unique"), std::string::npos) << made.out;
}

// The unbaked city is the baked one before baking: the same nodes, materials and mesh parts, and
// bake(m) gives mesh m bit for bit.
TEST(UniqueCity, UnbakedCityBakesIntoTheSameCity) {
  CityOptions options{.levels = 2, .fanout = 5, .seed = 6};
  options.unique = true;
  const Scene baked = generateCity(cityPrototypes(), options);
  const UnbakedCity unbaked = generateUniqueCity(cityPrototypes(), options);
  ASSERT_EQ(unbaked.scene.meshes.size(), baked.meshes.size());
  EXPECT_EQ(structureFingerprint(unbaked.scene), structureFingerprint(baked)) << "nodes, parts, materials";
  for (std::uint32_t m = 0; m < baked.meshes.size(); ++m) {
    EXPECT_FALSE(unbaked.scene.meshes[m].loaded());
    EXPECT_EQ(unbaked.scene.meshes[m].name, baked.meshes[m].name);
    EXPECT_EQ(unbaked.scene.meshes[m].vertexCount(), baked.meshes[m].positions.size());
    EXPECT_EQ(meshFingerprint(*unbaked.bake(m)), meshFingerprint(baked.meshes[m])) << "mesh " << m;
  }
}

// A unique city written as .gltf one mesh at a time is the one written as .glb.
TEST(UniqueCity, CommandLineWritesAGltfMeshByMesh) {
  test::ScratchDir scratch;
  writeGlb(cityPrototypes()[1], scratch / "pump.glb");
  const std::string base =
      "generate city --mesh '" + (scratch / "pump.glb").string() + "' --levels 2 --fanout 3 --unique -o '";
  const test::CommandResult gltf = test::runPbs(base + (scratch / "city.gltf").string() + "'");
  ASSERT_EQ(gltf.status, 0) << gltf.err;
  const test::CommandResult glb = test::runPbs(base + (scratch / "city.glb").string() + "'");
  ASSERT_EQ(glb.status, 0) << glb.err;
  EXPECT_TRUE(std::filesystem::exists(scratch / "city.0.bin"));
  EXPECT_EQ(sceneFingerprint(loadScene((scratch / "city.gltf").string()).scene),
            sceneFingerprint(loadScene((scratch / "city.glb").string()).scene));
}

TEST(UniqueCity, CommandLineRefusesWhatAGlbCannotHold) {
  // 22,500 copies of a 1.28 M-triangle mesh: far beyond the 4 GiB of one .glb, refused before any baking.
  test::ScratchDir scratch;
  const Scene big = generateTerrain({.triangles = 2 * 800 * 800});
  writeGlb(big, scratch / "grid.glb");
  const test::CommandResult refused =
      test::runPbs("generate city --mesh '" + (scratch / "grid.glb").string() +
                   "' --levels 2 --fanout 150 --unique -o '" + (scratch / "city.glb").string() + "'");
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("4 GiB"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(scratch / "city.glb"));
}

}  // namespace
}  // namespace pbs
