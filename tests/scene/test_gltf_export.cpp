// Tests of the glTF writers: round trips through importGltf keep hierarchy, transforms, meshes,
// materials, texture pixels and samplers; the file is compact; writes are whole or not at all; a .gltf
// with .bin files, written mesh by mesh, imports as the .glb does.
#include <pbs/scene/generate.hpp>
#include <pbs/scene/gltf_export.hpp>
#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene_fingerprint.hpp>

#include "test_support.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <cstring>
#include <functional>

namespace pbs {
namespace {

namespace fs = std::filesystem;

// A closed box with flat faces, uvs per face and one part.
Mesh boxMesh(glm::vec3 half) {
  Mesh mesh;
  mesh.name = "box";
  for (int axis = 0; axis < 3; ++axis) {
    for (float side : {-1.0f, 1.0f}) {
      glm::vec3 normal(0.0f), u(0.0f);
      normal[axis] = side;
      u[(axis + 1) % 3] = 1.0f;
      const glm::vec3 v = glm::cross(normal, u);  // (u, v, normal) right-handed: corners run counter-clockwise
      const auto base = std::uint32_t(mesh.positions.size());
      for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
        mesh.positions.push_back(half * (normal + c.x * u + c.y * v));
        mesh.normals.push_back(normal);
        mesh.uvs.push_back(c * 0.5f + 0.5f);
      }
      mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
  mesh.parts = {{0, std::uint32_t(mesh.indices.size()), 0}};
  updateMeshBounds(mesh);
  return mesh;
}

// A wavy height field of n × n vertices without uvs: n > 256 needs 32-bit indices.
Mesh gridMesh(std::uint32_t n) {
  Mesh mesh;
  mesh.name = "grid";
  for (std::uint32_t y = 0; y < n; ++y)
    for (std::uint32_t x = 0; x < n; ++x)
      mesh.positions.push_back({float(x) * 0.1f, 0.05f * std::sin(float(x * 7 + y * 3)), float(y) * 0.1f});
  for (std::uint32_t y = 0; y + 1 < n; ++y) {
    for (std::uint32_t x = 0; x + 1 < n; ++x) {
      const std::uint32_t a = y * n + x;
      mesh.indices.insert(mesh.indices.end(), {a, a + n, a + 1, a + 1, a + n, a + n + 1});
    }
  }
  mesh.normals = computeVertexNormals(mesh.positions, mesh.indices);
  mesh.parts = {{0, std::uint32_t(mesh.indices.size()), 1}};
  updateMeshBounds(mesh);
  return mesh;
}

Texture patternTexture(std::string name, std::uint32_t width, std::uint32_t height, std::uint32_t seed) {
  Texture texture;
  texture.name = std::move(name);
  texture.width = width;
  texture.height = height;
  for (std::uint32_t i = 0; i < width * height * 4; ++i)
    texture.rgba8.push_back(std::uint8_t((i * 37 + seed * 101) ^ (i >> 3)));
  return texture;
}

// Everything the writer must keep: three levels of nodes with turns, non-uniform and mirroring
// scales; a mesh used by two nodes; a mesh of two parts; a mesh with 32-bit indices and no uvs;
// textured and plain materials; samplers of every kind.
Scene makeTestScene() {
  Scene scene;
  Texture stripes = patternTexture("stripes", 5, 3, 1);
  Texture checks = patternTexture("checks", 4, 4, 2);
  checks.wrapS = TextureWrap::ClampToEdge;
  checks.wrapT = TextureWrap::MirroredRepeat;
  checks.magFilter = TextureFilter::Nearest;
  checks.minFilter = TextureFilter::Nearest;
  checks.mipmap = TextureMipmap::Linear;
  scene.textures = {stripes, checks};
  scene.materials = {{"painted", glm::vec4(1.0f), 0},
                     {"plain", glm::vec4(0.2f, 0.4f, 0.6f, 1.0f), -1},
                     {"tinted", glm::vec4(0.5f, 0.25f, 1.0f, 0.75f), 1}};

  Mesh twoParts = boxMesh({1.0f, 2.0f, 0.5f});
  twoParts.name = "two parts";
  twoParts.parts = {{0, 18, 0}, {18, 18, 2}};
  scene.meshes = {boxMesh({0.5f, 0.5f, 0.5f}), twoParts, gridMesh(300)};

  const auto node = [&](std::string name, glm::dmat4 local, std::int32_t mesh, std::vector<std::uint32_t> children) {
    scene.nodes.push_back({std::move(name), local, std::move(children), mesh});
  };
  const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(0.3, 1.0, 0.2));
  node("root", glm::dmat4(1.0), -1, {1, 4});
  node("group", glm::translate(glm::dmat4(1.0), {1.5, -2.0, 1e5}) * turn, -1, {2, 3});
  node("first user", glm::scale(glm::dmat4(1.0), {2.0, 0.5, 1.0 / 3.0}), 0, {});
  node("second user", glm::scale(glm::dmat4(1.0), {-1.0, 1.0, 1.0}), 0, {});
  node("two parts", turn, 1, {});
  node("grid", glm::translate(glm::dmat4(1.0), {0.0, 0.0, -10.0}), 2, {});
  scene.roots = {0, 5};
  return scene;
}

// Calls `visit(a, b)` on the nodes of two scenes in step, depth first from their roots, after
// checking that the shapes of the hierarchies agree.
void walkTogether(const Scene& a, const Scene& b, const std::function<void(const Node&, const Node&)>& visit) {
  ASSERT_EQ(a.roots.size(), b.roots.size());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack;
  for (std::size_t r = a.roots.size(); r-- > 0;) stack.emplace_back(a.roots[r], b.roots[r]);
  while (!stack.empty()) {
    const auto [na, nb] = stack.back();
    stack.pop_back();
    const Node& x = a.nodes[na];
    const Node& y = b.nodes[nb];
    ASSERT_EQ(x.children.size(), y.children.size()) << x.name;
    visit(x, y);
    for (std::size_t c = x.children.size(); c-- > 0;) stack.emplace_back(x.children[c], y.children[c]);
  }
}

void expectSameTexture(const Texture& a, const Texture& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_TRUE(a.rgba8 == b.rgba8) << a.name << ": pixels differ";
  EXPECT_EQ(a.wrapS, b.wrapS);
  EXPECT_EQ(a.wrapT, b.wrapT);
  EXPECT_EQ(a.magFilter, b.magFilter);
  EXPECT_EQ(a.minFilter, b.minFilter);
  EXPECT_EQ(a.mipmap, b.mipmap);
}

void expectSameMaterial(const Scene& a, std::uint32_t ma, const Scene& b, std::uint32_t mb) {
  const Material& x = a.materials[ma];
  const Material& y = b.materials[mb];
  EXPECT_EQ(x.name, y.name);
  EXPECT_EQ(x.baseColorFactor, y.baseColorFactor);
  ASSERT_EQ(x.baseColorTexture < 0, y.baseColorTexture < 0) << x.name;
  if (x.baseColorTexture >= 0)
    expectSameTexture(a.textures[std::size_t(x.baseColorTexture)], b.textures[std::size_t(y.baseColorTexture)]);
}

// Same triangles, corner by corner, with the same vertex data and materials, and no vertex stored
// twice: the parts of a mesh share one vertex array in the file and after the import.
void expectSameMesh(const Scene& a, const Mesh& x, const Scene& b, const Mesh& y) {
  EXPECT_EQ(x.name, y.name);
  EXPECT_EQ(x.positions.size(), y.positions.size()) << x.name;
  ASSERT_EQ(x.parts.size(), y.parts.size()) << x.name;
  ASSERT_EQ(x.indices.size(), y.indices.size()) << x.name;
  ASSERT_EQ(x.uvs.empty(), y.uvs.empty()) << x.name;
  for (std::size_t p = 0; p < x.parts.size(); ++p) {
    EXPECT_EQ(x.parts[p].firstIndex, y.parts[p].firstIndex);
    EXPECT_EQ(x.parts[p].indexCount, y.parts[p].indexCount);
    expectSameMaterial(a, x.parts[p].material, b, y.parts[p].material);
  }
  std::size_t differences = 0;
  for (std::size_t i = 0; i < x.indices.size(); ++i) {
    const std::uint32_t u = x.indices[i], v = y.indices[i];
    const bool same = x.positions[u] == y.positions[v] &&
                      glm::all(glm::lessThan(glm::abs(x.normals[u] - y.normals[v]), glm::vec3(1e-6f))) &&
                      (x.uvs.empty() || x.uvs[u] == y.uvs[v]);
    differences += same ? 0 : 1;
  }
  EXPECT_EQ(differences, 0u) << x.name << ": corners whose vertex data changed";
}

Scene roundTrip(const Scene& scene, const fs::path& file) {
  writeGlb(scene, file);
  ImportResult imported = importGltf(file);
  EXPECT_TRUE(imported.warnings.empty()) << imported.warnings.front();
  validateScene(imported.scene, file.string());
  return std::move(imported.scene);
}

std::vector<std::string> folderEntries(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The JSON chunk of a .glb.
nlohmann::json glbJson(const fs::path& file) {
  const std::string bytes = test::readFile(file);
  EXPECT_GE(bytes.size(), 20u);
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  return nlohmann::json::parse(bytes.substr(20, length));
}

TEST(GltfExport, RoundTripKeepsHierarchyTransformsAndNames) {
  test::ScratchDir scratch;
  const Scene scene = makeTestScene();
  const Scene back = roundTrip(scene, scratch / "scene.glb");
  ASSERT_EQ(back.nodes.size(), scene.nodes.size());
  walkTogether(scene, back, [&](const Node& x, const Node& y) {
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.mesh < 0, y.mesh < 0) << x.name;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        EXPECT_NEAR(x.local[c][r], y.local[c][r], 1e-7 * std::max(1.0, std::abs(x.local[c][r]))) << x.name;
  });
}

TEST(GltfExport, RoundTripKeepsMeshesPartsMaterialsAndTextures) {
  test::ScratchDir scratch;
  const Scene scene = makeTestScene();
  const Scene back = roundTrip(scene, scratch / "scene.glb");
  ASSERT_EQ(back.meshes.size(), scene.meshes.size());
  ASSERT_EQ(back.materials.size(), scene.materials.size());
  ASSERT_EQ(back.textures.size(), scene.textures.size());
  walkTogether(scene, back, [&](const Node& x, const Node& y) {
    if (x.mesh >= 0) expectSameMesh(scene, scene.meshes[std::size_t(x.mesh)], back, back.meshes[std::size_t(y.mesh)]);
  });
}

TEST(GltfExport, SharedMeshStaysOneMesh) {
  test::ScratchDir scratch;
  const Scene back = roundTrip(makeTestScene(), scratch / "scene.glb");
  std::vector<std::int32_t> users;
  for (const Node& node : back.nodes)
    if (node.name == "first user" || node.name == "second user") users.push_back(node.mesh);
  ASSERT_EQ(users.size(), 2u);
  EXPECT_GE(users[0], 0);
  EXPECT_EQ(users[0], users[1]);
}

TEST(GltfExport, FileIsCompactAndFollowsTheSpecification) {
  test::ScratchDir scratch;
  const Scene scene = makeTestScene();
  writeGlb(scene, scratch / "scene.glb");
  const nlohmann::json gltf = glbJson(scratch / "scene.glb");
  EXPECT_EQ(gltf["asset"]["version"], "2.0");
  EXPECT_EQ(gltf["scene"], 0);
  ASSERT_EQ(gltf["buffers"].size(), 1u);
  EXPECT_FALSE(gltf["buffers"][0].contains("uri"));  // the binary chunk
  ASSERT_EQ(gltf["meshes"].size(), 3u);

  // Identity transforms are left out; the others are matrices.
  EXPECT_FALSE(gltf["nodes"][0].contains("matrix"));
  EXPECT_EQ(gltf["nodes"][1]["matrix"].size(), 16u);

  const nlohmann::json& accessors = gltf["accessors"];
  const auto indexType = [&](int mesh) {
    return accessors[gltf["meshes"][mesh]["primitives"][0]["indices"].get<int>()]["componentType"];
  };
  EXPECT_EQ(indexType(0), 5123);  // UNSIGNED_SHORT: 24 vertices
  EXPECT_EQ(indexType(2), 5125);  // UNSIGNED_INT: 90,000 vertices
  for (const nlohmann::json& mesh : gltf["meshes"]) {
    const nlohmann::json& first = mesh["primitives"][0];
    for (const nlohmann::json& primitive : mesh["primitives"])
      EXPECT_EQ(primitive["attributes"], first["attributes"]) << "parts share the vertex accessors";
    const nlohmann::json& position = accessors[first["attributes"]["POSITION"].get<int>()];
    ASSERT_TRUE(position.contains("min") && position.contains("max"));
    EXPECT_EQ(position["min"].size(), 3u);
  }
  EXPECT_EQ(gltf["meshes"][1]["primitives"].size(), 2u);
  for (const nlohmann::json& image : gltf["images"]) {
    EXPECT_EQ(image["mimeType"], "image/png");
    EXPECT_TRUE(image.contains("bufferView"));
  }
}

TEST(GltfExport, DefaultPlantAndCityStayCompact) {
  test::ScratchDir scratch;
  const Scene plant = generateDefaultScene();
  writeGlb(plant, scratch / "plant.glb");
  EXPECT_LT(fs::file_size(scratch / "plant.glb"), 40u << 20);

  // About 20,000 instances of two small meshes: the nodes cost bytes, the meshes are stored once.
  std::vector<Scene> prototypes;
  for (const Mesh& mesh : plant.meshes) {
    if (mesh.name != "valve" && mesh.name != "pump") continue;
    Scene prototype;
    prototype.materials = plant.materials;
    prototype.textures = plant.textures;
    prototype.meshes = {mesh};
    prototype.nodes = {Node{"prototype", glm::dmat4(1.0), {}, 0}};
    prototype.roots = {0};
    prototypes.push_back(std::move(prototype));
  }
  ASSERT_EQ(prototypes.size(), 2u);
  const Scene city = generateCity(prototypes, CityOptions{3, 27, 5});
  const Scene back = roundTrip(city, scratch / "city.glb");
  EXPECT_LT(fs::file_size(scratch / "city.glb"), 6u << 20);
  EXPECT_EQ(back.nodes.size(), city.nodes.size());
  EXPECT_EQ(back.meshes.size(), 2u);
}

TEST(GltfExport, MissingFolderThrowsAndLeavesNothing) {
  test::ScratchDir scratch;
  const fs::path file = scratch / "missing" / "scene.glb";
  try {
    writeGlb(makeTestScene(), file);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(file.string()), std::string::npos) << error.what();
  }
  EXPECT_FALSE(fs::exists(scratch / "missing"));
  EXPECT_TRUE(folderEntries(scratch.path()).empty());
}

TEST(GltfExport, ExistingFileIsReplacedWhole) {
  test::ScratchDir scratch;
  const Scene scene = makeTestScene();
  writeGlb(scene, scratch / "fresh.glb");
  test::writeFile(scratch / "scene.glb", std::string(8 << 20, 'x'));  // longer than the new file
  writeGlb(scene, scratch / "scene.glb");
  EXPECT_EQ(test::readFile(scratch / "scene.glb"), test::readFile(scratch / "fresh.glb"));
  EXPECT_EQ(folderEntries(scratch.path()), (std::vector<std::string>{"fresh.glb", "scene.glb"}));
}

TEST(GltfExport, FailedRenameRemovesTheTemporaryFile) {
  // The target is a folder that is not empty: the data is written, the rename fails.
  test::ScratchDir scratch;
  fs::create_directory(scratch / "scene.glb");
  test::writeFile(scratch / "scene.glb" / "keep", "keep");
  EXPECT_THROW(writeGlb(makeTestScene(), scratch / "scene.glb"), std::runtime_error);
  EXPECT_EQ(folderEntries(scratch.path()), std::vector<std::string>{"scene.glb"});
  EXPECT_EQ(test::readFile(scratch / "scene.glb" / "keep"), "keep");
}

TEST(GltfExport, InvalidSceneThrowsAndKeepsTheOldFile) {
  test::ScratchDir scratch;
  test::writeFile(scratch / "scene.glb", "old");
  Scene scene = makeTestScene();
  scene.meshes[0].indices[0] = 1000;
  EXPECT_THROW(writeGlb(scene, scratch / "scene.glb"), std::runtime_error);
  EXPECT_EQ(test::readFile(scratch / "scene.glb"), "old");
  EXPECT_EQ(folderEntries(scratch.path()), std::vector<std::string>{"scene.glb"});
}

// A .gltf whose data is split over several .bin files (a small cap here), each mesh read as it is
// written, imports as the scene's .glb; the files named are those written.
TEST(GltfExport, GltfWithBinFilesImportsAsTheGlb) {
  test::ScratchDir scratch;
  const Scene scene = makeTestScene();
  std::vector<std::uint32_t> read;
  const MeshReader counting = [&](std::uint32_t m) {
    read.push_back(m);
    return loadedMeshes(scene)(m);
  };
  const std::vector<fs::path> files = writeGltf(scene, counting, scratch / "scene.gltf", 4096);
  std::vector<std::uint32_t> inOrder(scene.meshes.size());
  for (std::uint32_t m = 0; m < inOrder.size(); ++m) inOrder[m] = m;
  EXPECT_EQ(read, inOrder) << "each mesh once, in order";
  ASSERT_GE(files.size(), 3u) << "the .gltf and at least two .bin files";
  EXPECT_EQ(files.front(), scratch / "scene.gltf");
  for (std::size_t k = 1; k < files.size(); ++k) {
    EXPECT_EQ(files[k], scratch / ("scene." + std::to_string(k - 1) + ".bin"));
    EXPECT_TRUE(fs::exists(files[k]));
  }
  EXPECT_EQ(folderEntries(scratch.path()).size(), files.size()) << "no temporaries left";
  writeGlb(scene, scratch / "scene.glb");
  const ImportResult gltf = importGltf(scratch / "scene.gltf"), glb = importGltf(scratch / "scene.glb");
  EXPECT_TRUE(gltf.warnings.empty());
  EXPECT_EQ(sceneFingerprint(gltf.scene), sceneFingerprint(glb.scene));
}

// A mesh that cannot be made stops the write with the .gltf's name; neither it nor a .bin is left.
TEST(GltfExport, GltfWriteThatFailsLeavesNothing) {
  test::ScratchDir scratch;
  const Scene scene = makeTestScene();
  const MeshReader failing = [&](std::uint32_t m) -> std::shared_ptr<const Mesh> {
    if (m + 1 == scene.meshes.size()) throw std::runtime_error("cannot bake");
    return loadedMeshes(scene)(m);
  };
  try {
    writeGltf(scene, failing, scratch / "scene.gltf", 64);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find((scratch / "scene.gltf").string()), std::string::npos) << error.what();
  }
  EXPECT_TRUE(folderEntries(scratch.path()).empty());
}

}  // namespace
}  // namespace pbs
