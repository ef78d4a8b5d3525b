// Tests of glTF import on valid input: the shared scenes, and small hand-built files for each
// feature (primitive modes, index and attribute encodings, sparse and strided data, transforms,
// scene choice, instancing, materials and textures, external files, GLB).
#include "gltf_test_files.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_import.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

namespace pbs {
namespace {

using nlohmann::json;
using test::GltfBuilder;

using Triangle = std::array<std::uint32_t, 3>;

// Triangles rotated to start at their smallest index: equal exactly when they have the same corners
// in the same winding.
std::vector<Triangle> canonicalTriangles(const Mesh& mesh) {
  std::vector<Triangle> triangles;
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    Triangle t{mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    triangles.push_back(t);
  }
  return triangles;
}

void expectUnitNormals(const Mesh& mesh) {
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (const glm::vec3& n : mesh.normals) {
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
  }
}

// ---------------------------------------------------------------------------------------------
// The shared scenes

struct SharedScene {
  const char* file;
  std::uint64_t triangles;
  std::size_t vertices;
};

class SharedScenes : public ::testing::TestWithParam<SharedScene> {};

TEST_P(SharedScenes, LoadWithExactCounts) {
  PBS_SHARED_SCENE(path, GetParam().file);
  const ImportResult result = importGltf(path);
  const Scene& scene = result.scene;
  ASSERT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.nodes.size(), 1u);
  ASSERT_EQ(scene.roots, std::vector<std::uint32_t>{0});
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.triangleCount(), GetParam().triangles);
  EXPECT_EQ(mesh.positions.size(), GetParam().vertices);
  expectUnitNormals(mesh);
  test::expectPartsCoverIndices(mesh);
  EXPECT_FALSE(mesh.bounds.empty());
  EXPECT_TRUE(mesh.uvs.empty() || mesh.uvs.size() == mesh.positions.size());
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
}

INSTANTIATE_TEST_SUITE_P(Files, SharedScenes,
                         ::testing::Values(SharedScene{"bunny.glb", 69451, 34834},
                                           SharedScene{"horse.glb", 96966, 48485},
                                           SharedScene{"rocker-arm.glb", 20088, 10044},
                                           SharedScene{"fandisk.glb", 12946, 6475},
                                           SharedScene{"teapot.glb", 6320, 3644}, SharedScene{"spot.glb", 5856, 3225},
                                           SharedScene{"suzanne.glb", 968, 507}),
                         [](const auto& instance) {
                           std::string name = instance.param.file;
                           name = name.substr(0, name.find('.'));
                           std::erase(name, '-');
                           return name;
                         });

TEST(SharedScenes, SpotHasOneTextureWithUvsAndPixels) {
  PBS_SHARED_SCENE(path, "spot.glb");
  const Scene scene = importGltf(path).scene;
  ASSERT_EQ(scene.textures.size(), 1u);
  const Texture& texture = scene.textures[0];
  EXPECT_GT(texture.width, 1u);
  EXPECT_GT(texture.height, 1u);
  ASSERT_EQ(texture.rgba8.size(), std::size_t{texture.width} * texture.height * 4);
  EXPECT_NE(std::count(texture.rgba8.begin(), texture.rgba8.end(), texture.rgba8[0]), std::ssize(texture.rgba8));
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].baseColorTexture, 0);
  const Mesh& mesh = scene.meshes[0];
  ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
  for (const glm::vec2& uv : mesh.uvs) ASSERT_TRUE(std::isfinite(uv.x) && std::isfinite(uv.y));
}

TEST(SharedScenes, BunnyGetsComputedUnitNormals) {
  PBS_SHARED_SCENE(path, "bunny.glb");
  const Mesh mesh = importGltf(path).scene.meshes.at(0);
  expectUnitNormals(mesh);
  // Computed normals point away from the surface: on average outward from the centre.
  double outward = 0.0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    outward += glm::dot(glm::dvec3(mesh.normals[v]), glm::dvec3(mesh.positions[v]) - mesh.bounds.center());
  EXPECT_GT(outward, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Primitive modes and index encodings

// Five vertices zig-zagging in the XY plane, as a strip or as a fan around vertex 0.
GltfBuilder fiveVertexFile(int mode, std::vector<std::uint8_t> indices) {
  GltfBuilder b;
  const int positions =
      b.addAccessor(std::vector<float>{0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0}, test::kFloat, "VEC3");
  json primitive = {{"attributes", {{"POSITION", positions}}}, {"mode", mode}};
  if (!indices.empty()) primitive["indices"] = b.addAccessor(indices, test::kUnsignedByte, "SCALAR");
  b.addMesh(json::array({primitive}));
  b.addNode({{"mesh", 0}});
  b.setScene({0});
  return b;
}

float triangleNormalZ(const Mesh& mesh, std::size_t t) {
  const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                  c = mesh.positions[mesh.indices[3 * t + 2]];
  return glm::cross(b - a, c - a).z;
}

TEST(PrimitiveModes, TriangleStripAlternatesToKeepOneWinding) {
  const Mesh mesh = test::importText(fiveVertexFile(test::kModeStrip, {}).gltf()).scene.meshes.at(0);
  EXPECT_EQ(canonicalTriangles(mesh), (std::vector<Triangle>{{0, 1, 2}, {1, 3, 2}, {2, 3, 4}}));
  for (std::size_t t = 0; t < 3; ++t) EXPECT_LT(triangleNormalZ(mesh, t), 0.0f) << "triangle " << t;
}

TEST(PrimitiveModes, IndexedStripUsesTheIndices) {
  const Mesh mesh = test::importText(fiveVertexFile(test::kModeStrip, {4, 3, 2, 1}).gltf()).scene.meshes.at(0);
  EXPECT_EQ(canonicalTriangles(mesh), (std::vector<Triangle>{{2, 4, 3}, {1, 2, 3}}));
}

TEST(PrimitiveModes, TriangleFanTurnsAroundTheFirstVertex) {
  const Mesh mesh = test::importText(fiveVertexFile(test::kModeFan, {}).gltf()).scene.meshes.at(0);
  EXPECT_EQ(canonicalTriangles(mesh), (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
}

TEST(PrimitiveModes, NonIndexedTriangles) {
  GltfBuilder b;
  const int positions =
      b.addAccessor(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 0, 0, 6, 0, 0, 5, 1, 0}, test::kFloat, "VEC3");
  b.addMesh({{{"attributes", {{"POSITION", positions}}}}});
  b.addNode({{"mesh", 0}});
  b.setScene({0});
  const Mesh mesh = test::importText(b.gltf()).scene.meshes.at(0);
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5}));
}

TEST(PrimitiveModes, AllThreeIndexTypes) {
  for (const int type : {test::kUnsignedByte, test::kUnsignedShort, test::kUnsignedInt}) {
    GltfBuilder b;
    const int positions = b.addAccessor(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, test::kFloat, "VEC3");
    int indices = -1;
    if (type == test::kUnsignedByte)
      indices = b.addAccessor(std::vector<std::uint8_t>{0, 1, 2, 2, 1, 3}, type, "SCALAR");
    if (type == test::kUnsignedShort)
      indices = b.addAccessor(std::vector<std::uint16_t>{0, 1, 2, 2, 1, 3}, type, "SCALAR");
    if (type == test::kUnsignedInt)
      indices = b.addAccessor(std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3}, type, "SCALAR");
    b.addMesh({{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}});
    b.addNode({{"mesh", 0}});
    b.setScene({0});
    const Mesh mesh = test::importText(b.gltf()).scene.meshes.at(0);
    EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3})) << "componentType " << type;
  }
}

TEST(PrimitiveModes, LinesAndPointsAreSkippedWithOneWarningPerMode) {
  GltfBuilder b = test::triangleFile();
  const json line = {{"attributes", {{"POSITION", 0}}}, {"mode", test::kModeLines}, {"indices", 1}};
  const json points = {{"attributes", {{"POSITION", 0}}}, {"mode", test::kModePoints}};
  b.json["meshes"][0]["primitives"].push_back(line);
  b.json["meshes"][0]["primitives"].push_back(points);
  b.addMesh(json::array({line}));  // a second mesh with only lines: nothing to draw
  b.addNode({{"mesh", 1}});
  b.setScene({0, 1});
  const ImportResult result = test::importText(b.gltf());
  ASSERT_EQ(result.scene.meshes.size(), 1u);
  EXPECT_EQ(result.scene.meshes[0].triangleCount(), 1u);
  EXPECT_EQ(result.scene.meshes[0].parts.size(), 1u);
  ASSERT_EQ(result.scene.nodes.size(), 2u);
  EXPECT_EQ(result.scene.nodes[1].mesh, -1);
  EXPECT_EQ(result.warnings,
            (std::vector<std::string>{"skipped 1 primitive of mode POINTS", "skipped 2 primitives of mode LINES"}));
}

// ---------------------------------------------------------------------------------------------
// Attribute encodings

TEST(Attributes, NormalizedIntegerTexcoordsAndPositions) {
  GltfBuilder b;
  const int positions = b.addAccessor(std::vector<std::int16_t>{-32768, 0, 32767, 16384, 0, 0, 0, -16384, 0, 0},
                                      test::kShort, "VEC3", true);
  b.json["accessors"][positions]["count"] = 3;  // the 10th short only pads the view
  const int uvs = b.addAccessor(std::vector<std::uint8_t>{0, 255, 255, 0, 51, 102}, test::kUnsignedByte, "VEC2", true);
  const int uvs16 =
      b.addAccessor(std::vector<std::uint16_t>{65535, 0, 0, 65535, 13107, 0}, test::kUnsignedShort, "VEC2", true);
  const int signedUvs = b.addAccessor(std::vector<std::int8_t>{-128, 127, 0, -127, 64, 0}, test::kByte, "VEC2", true);
  // A textured material, so that the meshes keep their uvs.
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.append("textures", {{"source", 0}});
  b.append("images", {{"uri", std::string("data:image/png;base64,") + test::kPngRgba2x2}});
  b.addMesh({{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", uvs}}}, {"material", 0}}});
  b.addMesh({{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", uvs16}}}, {"material", 0}}});
  b.addMesh({{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", signedUvs}}}, {"material", 0}}});
  b.addNode({{"children", {1, 2, 3}}});
  b.addNode({{"mesh", 0}});
  b.addNode({{"mesh", 1}});
  b.addNode({{"mesh", 2}});
  b.setScene({0});
  const Scene scene = test::importText(b.gltf()).scene;
  ASSERT_EQ(scene.meshes.size(), 3u);
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.positions[0], glm::vec3(-1.0f, 0.0f, 1.0f));  // -32768 clamps to -1
  EXPECT_NEAR(mesh.positions[1].x, 16384.0f / 32767.0f, 1e-6f);
  EXPECT_NEAR(mesh.positions[2].y, -16384.0f / 32767.0f, 1e-6f);
  EXPECT_EQ(mesh.uvs[0], glm::vec2(0.0f, 1.0f));
  EXPECT_EQ(mesh.uvs[1], glm::vec2(1.0f, 0.0f));
  EXPECT_NEAR(mesh.uvs[2].x, 0.2f, 1e-6f);
  EXPECT_NEAR(mesh.uvs[2].y, 0.4f, 1e-6f);
  EXPECT_EQ(scene.meshes[1].uvs[0], glm::vec2(1.0f, 0.0f));
  EXPECT_NEAR(scene.meshes[1].uvs[2].x, 0.2f, 1e-6f);
  EXPECT_EQ(scene.meshes[2].uvs[0], glm::vec2(-1.0f, 1.0f));
  EXPECT_EQ(scene.meshes[2].uvs[1], glm::vec2(0.0f, -1.0f));
}

TEST(Attributes, UnnormalizedIntegerPositionsAsQuantizationAllows) {
  GltfBuilder b;
  const int positions =
      b.addAccessor(std::vector<std::uint16_t>{0, 0, 0, 300, 0, 0, 0, 7, 0, 0}, test::kUnsignedShort, "VEC3");
  b.json["accessors"][positions]["count"] = 3;
  const int normals =
      b.addAccessor(std::vector<std::int8_t>{0, 0, 127, 0, 0, 127, 0, 0, -127, 0}, test::kByte, "VEC3", true);
  b.json["accessors"][normals]["count"] = 3;
  b.addMesh({{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}}}});
  b.addNode({{"mesh", 0}});
  b.setScene({0});
  b.json["extensionsUsed"] = {"KHR_mesh_quantization"};
  b.json["extensionsRequired"] = {"KHR_mesh_quantization"};
  const Mesh mesh = test::importText(b.gltf()).scene.meshes.at(0);
  EXPECT_EQ(mesh.positions, (std::vector<glm::vec3>{{0, 0, 0}, {300, 0, 0}, {0, 7, 0}}));
  EXPECT_EQ(mesh.normals, (std::vector<glm::vec3>{{0, 0, 1}, {0, 0, 1}, {0, 0, -1}}));
}

TEST(Attributes, StridedInterleavedBufferView) {
  GltfBuilder b;
  // position xyz, normal xyz per vertex; the normals are not unit length, to see them normalised.
  const std::vector<float> interleaved{0, 0, 0, 0, 0, 2, 1, 0, 0, 0, 0, 3, 0, 1, 0, 0, 0, 4};
  const int view = b.addView(test::bytesOf(interleaved), 24);
  b.append("accessors", {{"bufferView", view}, {"componentType", test::kFloat}, {"count", 3}, {"type", "VEC3"}});
  b.append("accessors",
           {{"bufferView", view}, {"byteOffset", 12}, {"componentType", test::kFloat}, {"count", 3}, {"type", "VEC3"}});
  b.addMesh({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}}});
  b.addNode({{"mesh", 0}});
  b.setScene({0});
  const Mesh mesh = test::importText(b.gltf()).scene.meshes.at(0);
  EXPECT_EQ(mesh.positions, (std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(mesh.normals, (std::vector<glm::vec3>{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}));
}

TEST(Attributes, SparseAccessorOverABufferViewAndOverZeros) {
  GltfBuilder b = test::triangleFile();
  const int sparseIndices = b.addView(test::bytesOf(std::vector<std::uint16_t>{2, 0}));
  const int sparseValues = b.addView(test::bytesOf(std::vector<float>{5, 6, 7}));
  const json sparse = {{"count", 1},
                       {"indices", {{"bufferView", sparseIndices}, {"componentType", test::kUnsignedShort}}},
                       {"values", {{"bufferView", sparseValues}}}};
  b.json["accessors"][0]["sparse"] = sparse;
  // A second mesh whose positions have no bufferView: zeros, then the same substitution.
  const int zeros =
      b.append("accessors", {{"componentType", test::kFloat}, {"count", 3}, {"type", "VEC3"}, {"sparse", sparse}});
  b.addMesh({{{"attributes", {{"POSITION", zeros}}}, {"indices", 1}}});
  b.addNode({{"mesh", 1}});
  b.setScene({0, 1});
  const Scene scene = test::importText(b.gltf()).scene;
  ASSERT_EQ(scene.meshes.size(), 2u);
  EXPECT_EQ(scene.meshes[0].positions, (std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {5, 6, 7}}));
  EXPECT_EQ(scene.meshes[1].positions, (std::vector<glm::vec3>{{0, 0, 0}, {0, 0, 0}, {5, 6, 7}}));
}

TEST(Attributes, MissingAndZeroNormalsAreComputed) {
  GltfBuilder b = test::triangleFile();
  const int normals = b.addAccessor(std::vector<float>{0, 0, 0, 0, 0, 5, 0, 0, 5}, test::kFloat, "VEC3");
  b.json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = normals;
  const Mesh withZero = test::importText(b.gltf()).scene.meshes.at(0);
  EXPECT_EQ(withZero.normals, (std::vector<glm::vec3>(3, {0, 0, 1})));
  const Mesh without = test::importText(test::triangleFile().gltf()).scene.meshes.at(0);
  EXPECT_EQ(without.normals, (std::vector<glm::vec3>(3, {0, 0, 1})));
}

TEST(Attributes, PrimitivesMergeShareVerticesAndUvsArePaddedWhereMissing) {
  GltfBuilder b = test::triangleFile();
  const int uvs = b.addAccessor(std::vector<float>{0.5f, 0.5f, 1, 0, 0, 1}, test::kFloat, "VEC2");
  json textured = b.json["meshes"][0]["primitives"][0];
  textured["attributes"]["TEXCOORD_0"] = uvs;
  textured["material"] = 0;  // a texture reads the uvs, so the mesh keeps them
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.append("textures", {{"source", 0}});
  b.append("images", {{"uri", std::string("data:image/png;base64,") + test::kPngRgba2x2}});
  b.json["meshes"][0]["primitives"].push_back(textured);
  b.json["meshes"][0]["primitives"].push_back(b.json["meshes"][0]["primitives"][0]);
  const Mesh mesh = test::importText(b.gltf()).scene.meshes.at(0);
  // The third primitive names the first one's accessors, so it reuses its vertices.
  ASSERT_EQ(mesh.positions.size(), 6u);
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 0, 1, 2}));
  ASSERT_EQ(mesh.parts.size(), 3u);
  EXPECT_EQ(mesh.parts[1].firstIndex, 3u);
  EXPECT_EQ(mesh.parts[2].firstIndex, 6u);
  ASSERT_EQ(mesh.uvs.size(), 6u);
  EXPECT_EQ(mesh.uvs[0], glm::vec2(0.0f));
  EXPECT_EQ(mesh.uvs[3], glm::vec2(0.5f));
  EXPECT_EQ(mesh.uvs[2], glm::vec2(0.0f));
  EXPECT_EQ(mesh.bounds.max, glm::dvec3(1, 1, 0));
}

// Texture coordinates nothing reads are not kept: a mesh whose parts have no textured material
// drops them, whatever the file holds.
TEST(Attributes, UvsOfAMeshWithoutATextureAreDropped) {
  GltfBuilder b = test::triangleFile();
  const int uvs = b.addAccessor(std::vector<float>{0.5f, 0.5f, 1, 0, 0, 1}, test::kFloat, "VEC2");
  b.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uvs;
  b.json["meshes"][0]["primitives"][0]["material"] = 0;
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}});
  const Scene plain = test::importText(b.gltf()).scene;
  EXPECT_TRUE(plain.meshes.at(0).uvs.empty());
  EXPECT_EQ(meshBytes(plain.meshes[0]), 3u * 12 + 3u * 12 + 3u * 4);

  b.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.append("textures", {{"source", 0}});
  b.append("images", {{"uri", std::string("data:image/png;base64,") + test::kPngRgba2x2}});
  EXPECT_EQ(test::importText(b.gltf()).scene.meshes.at(0).uvs.size(), 3u);
}

// ---------------------------------------------------------------------------------------------
// Nodes and scenes

TEST(Nodes, TrsAndMatrixGiveTheSameTransform) {
  GltfBuilder b = test::triangleFile();
  const double s = std::sqrt(0.5);
  b.json["nodes"][0] = {
      {"mesh", 0}, {"translation", {1, 2, 3}}, {"rotation", {0, 0, 2 * s, 2 * s}}, {"scale", {2, 3, 4}}};
  const glm::dmat4 expected = glm::translate(glm::dmat4(1.0), glm::dvec3(1, 2, 3)) *
                              glm::mat4_cast(glm::angleAxis(glm::radians(90.0), glm::dvec3(0, 0, 1))) *
                              glm::scale(glm::dmat4(1.0), glm::dvec3(2, 3, 4));
  std::vector<double> columnMajor;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) columnMajor.push_back(expected[c][r]);
  b.addNode({{"mesh", 0}, {"matrix", columnMajor}});
  b.setScene({0, 1});
  const Scene scene = test::importText(b.gltf()).scene;
  ASSERT_EQ(scene.nodes.size(), 2u);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      EXPECT_NEAR(scene.nodes[0].local[c][r], expected[c][r], 1e-12) << c << "," << r;
      EXPECT_EQ(scene.nodes[1].local[c][r], expected[c][r]) << c << "," << r;
    }
  EXPECT_EQ(scene.nodes[1].local[3], glm::dvec4(1, 2, 3, 1));  // translation in the last column
}

// JSON numbers are decimal text: each must become the double nearest to it, as strtod rounds, so that a
// transform keeps the same bits whichever parser read it (scene fingerprints hash them). These are the
// cases a fast parser gets wrong: halfway and near-halfway mantissas, more than 17 digits, subnormals,
// the largest double and integers beyond 2^53.
TEST(Nodes, MatrixNumbersAreCorrectlyRounded) {
  const std::vector<std::string> texts = {"0.1",
                                          "0.30000000000000004",
                                          "9007199254740993",
                                          "2.2250738585072011e-308",
                                          "4.9406564584124654e-324",
                                          "1.7976931348623157e308",
                                          "0.99999999999999994448884876874217",
                                          "1.00000000000000011102230246251565404236316680908203125",
                                          "123456789012345678901234567890e-20",
                                          "7.038531e-26",
                                          "2.4703282292062327e-324",
                                          "8.98846567431158e307",
                                          "1.000000000000000055511151231257827021181583404541015625",
                                          "-0.0",
                                          "3.14159265358979323846264338327950288"};
  ASSERT_EQ(texts.size(), 15u);  // plus a last 1: a node matrix has 16 numbers
  std::string matrix = "[";
  for (const std::string& text : texts) matrix += text + ",";
  matrix += "1]";
  GltfBuilder b = test::triangleFile();
  b.json["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::string text = b.gltf();
  const std::string identity = "[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]";
  ASSERT_NE(text.find(identity), std::string::npos);
  text.replace(text.find(identity), identity.size(), matrix);
  const Scene scene = test::importText(text).scene;
  for (std::size_t i = 0; i < texts.size(); ++i) {
    const double expected = std::strtod(texts[i].c_str(), nullptr);
    const double got = scene.nodes.at(0).local[int(i / 4)][int(i % 4)];
    EXPECT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(expected)) << texts[i];
  }
}

TEST(Nodes, DefaultSceneElseSceneZero) {
  GltfBuilder b = test::triangleFile();
  b.json["nodes"][0]["name"] = "first";
  b.addNode({{"mesh", 0}, {"name", "second"}});
  b.json["scenes"] = json::array({{{"nodes", {0}}}, {{"nodes", {1}}}});
  b.json["scene"] = 1;
  EXPECT_EQ(test::importText(b.gltf()).scene.nodes.at(0).name, "second");
  b.json.erase("scene");
  EXPECT_EQ(test::importText(b.gltf()).scene.nodes.at(0).name, "first");
}

TEST(Nodes, NoScenesMeansEveryParentlessNodeIsARoot) {
  GltfBuilder b = test::triangleFile();
  b.json.erase("scenes");
  b.json.erase("scene");
  b.addNode({{"children", {0}}});
  b.addNode({{"mesh", 0}});
  const ImportResult result = test::importText(b.gltf());
  EXPECT_EQ(result.scene.roots.size(), 2u);
  EXPECT_EQ(result.scene.nodes.size(), 3u);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_NE(result.warnings[0].find("no scenes"), std::string::npos);
}

TEST(Nodes, DepthFirstOrderKeepsOnlyReachableNodes) {
  GltfBuilder b = test::triangleFile();
  // 0 (mesh) is a child of 3; 1 is unreachable; 3 has children 4 and 0; 4 has child 2.
  b.json["nodes"] = json::array({{{"mesh", 0}, {"name", "a"}},
                                 {{"name", "unreachable"}},
                                 {{"name", "b"}},
                                 {{"name", "root"}, {"children", {4, 0}}},
                                 {{"name", "c"}, {"children", {2}}}});
  b.setScene({3});
  const Scene scene = test::importText(b.gltf()).scene;
  std::vector<std::string> names;
  for (const Node& node : scene.nodes) names.push_back(node.name);
  EXPECT_EQ(names, (std::vector<std::string>{"root", "c", "b", "a"}));
  EXPECT_EQ(scene.nodes[0].children, (std::vector<std::uint32_t>{1, 3}));
  EXPECT_EQ(scene.nodes[1].children, (std::vector<std::uint32_t>{2}));
  EXPECT_EQ(scene.nodes[3].mesh, 0);
}

TEST(Nodes, OneMeshUsedByTwoNodesIsOneMesh) {
  GltfBuilder b = test::triangleFile();
  b.json["nodes"] = json::array({{{"children", {1, 2}}}, {{"mesh", 0}}, {{"mesh", 0}, {"translation", {5, 0, 0}}}});
  b.setScene({0});
  const Scene scene = test::importText(b.gltf()).scene;
  EXPECT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.nodes[1].mesh, 0);
  EXPECT_EQ(scene.nodes[2].mesh, 0);
}

TEST(Nodes, VeryDeepChainDoesNotOverflowTheStack) {
  GltfBuilder b = test::triangleFile();
  constexpr int kDepth = 100000;
  json nodes = json::array();
  for (int i = 0; i < kDepth; ++i) nodes.push_back(i + 1 < kDepth ? json{{"children", {i + 1}}} : json{{"mesh", 0}});
  b.json["nodes"] = nodes;
  const Scene scene = test::importText(b.gltf()).scene;
  ASSERT_EQ(scene.nodes.size(), std::size_t{kDepth});
  EXPECT_EQ(scene.nodes.back().mesh, 0);
}

TEST(Nodes, CityOfTwentyThousandNodesImportsEveryNode) {
  GltfBuilder b = test::triangleFile();
  json nodes = json::array();
  json blocks = json::array();
  constexpr int kBlocks = 200, kLeaves = 100;
  nodes.push_back({{"name", "city"}});
  for (int block = 0; block < kBlocks; ++block) {
    json children = json::array();
    const int blockIndex = static_cast<int>(nodes.size());
    blocks.push_back(blockIndex);
    nodes.push_back({{"translation", {block * 10.0, 0, 0}}});
    for (int leaf = 0; leaf < kLeaves; ++leaf) {
      children.push_back(static_cast<int>(nodes.size()));
      nodes.push_back(
          {{"mesh", 0}, {"translation", {0, leaf, 0}}, {"rotation", {0, 0, 0.6, 0.8}}, {"scale", {1, 2, 1}}});
    }
    nodes[static_cast<std::size_t>(blockIndex)]["children"] = children;
  }
  nodes[0]["children"] = blocks;
  b.json["nodes"] = nodes;
  const std::string text = b.gltf();
  const Scene scene = test::importText(text).scene;
  EXPECT_EQ(scene.nodes.size(), std::size_t{1 + kBlocks + kBlocks * kLeaves});
  EXPECT_EQ(scene.meshes.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Materials and textures

GltfBuilder texturedTriangle(const std::string& imageUri) {
  GltfBuilder b = test::triangleFile();
  const int uvs = b.addAccessor(std::vector<float>{0, 0, 1, 0, 0, 1}, test::kFloat, "VEC2");
  b.json["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uvs;
  b.json["meshes"][0]["primitives"][0]["material"] = 0;
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.append("textures", {{"source", 0}});
  b.append("images", {{"uri", imageUri}});
  return b;
}

std::vector<std::uint8_t> importedPixels(const GltfBuilder& b) {
  const Scene scene = test::importText(b.gltf()).scene;
  EXPECT_EQ(scene.textures.size(), 1u);
  return scene.textures.at(0).rgba8;
}

TEST(Materials, PngPixelsBecomeRgba8WhateverTheirFormat) {
  EXPECT_EQ(importedPixels(texturedTriangle(std::string("data:image/png;base64,") + test::kPngRgba2x2)),
            (std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128}));
  EXPECT_EQ(importedPixels(texturedTriangle(std::string("data:image/png;base64,") + test::kPngGrey2x1)),
            (std::vector<std::uint8_t>{0, 0, 0, 255, 200, 200, 200, 255}));
  EXPECT_EQ(importedPixels(texturedTriangle(std::string("data:image/png;base64,") + test::kPngRgb16)),
            (std::vector<std::uint8_t>{255, 128, 0, 255}));
}

TEST(Materials, SamplerIsMappedAndAbsentSamplerMeansRepeatTrilinear) {
  GltfBuilder b = texturedTriangle(std::string("data:image/png;base64,") + test::kPngRgba2x2);
  Texture texture = test::importText(b.gltf()).scene.textures.at(0);
  EXPECT_EQ(texture.wrapS, TextureWrap::Repeat);
  EXPECT_EQ(texture.wrapT, TextureWrap::Repeat);
  EXPECT_EQ(texture.magFilter, TextureFilter::Linear);
  EXPECT_EQ(texture.minFilter, TextureFilter::Linear);
  EXPECT_EQ(texture.mipmap, TextureMipmap::Linear);
  ASSERT_EQ(texture.mipLevels.size(), 1u) << "2 × 2 has one level below it, 1 × 1";
  EXPECT_EQ(texture.mipLevels[0].width, 1u);
  EXPECT_EQ(texture.width, 2u);
  EXPECT_EQ(texture.height, 2u);
  b.append("samplers", {{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}, {"minFilter", 9986}});
  b.json["textures"][0]["sampler"] = 0;
  texture = test::importText(b.gltf()).scene.textures.at(0);
  EXPECT_EQ(texture.wrapS, TextureWrap::ClampToEdge);
  EXPECT_EQ(texture.wrapT, TextureWrap::MirroredRepeat);
  EXPECT_EQ(texture.magFilter, TextureFilter::Nearest);
  EXPECT_EQ(texture.minFilter, TextureFilter::Nearest);
  EXPECT_EQ(texture.mipmap, TextureMipmap::Linear);
  // minFilter's two parts, each glTF value: the filter within a level and the use of levels.
  const struct {
    int value;
    TextureFilter filter;
    TextureMipmap mipmap;
  } modes[] = {
      {9728, TextureFilter::Nearest, TextureMipmap::None},    {9729, TextureFilter::Linear, TextureMipmap::None},
      {9984, TextureFilter::Nearest, TextureMipmap::Nearest}, {9985, TextureFilter::Linear, TextureMipmap::Nearest},
      {9986, TextureFilter::Nearest, TextureMipmap::Linear},  {9987, TextureFilter::Linear, TextureMipmap::Linear}};
  for (const auto& mode : modes) {
    b.json["samplers"][0]["minFilter"] = mode.value;
    texture = test::importText(b.gltf()).scene.textures.at(0);
    EXPECT_EQ(texture.minFilter, mode.filter) << mode.value;
    EXPECT_EQ(texture.mipmap, mode.mipmap) << mode.value;
    EXPECT_EQ(texture.mipLevels.size(), mode.mipmap == TextureMipmap::None ? 0u : 1u) << "levels only where used";
  }
}

TEST(Materials, OnlyUsedMaterialsAreImportedAndTheDefaultIsShared) {
  GltfBuilder b = test::triangleFile();
  b.addMaterial({{"name", "unused"}});
  b.addMaterial({{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 0.5}}}}});
  json primitive = b.json["meshes"][0]["primitives"][0];
  b.json["meshes"][0]["primitives"].push_back(primitive);  // no material: the default
  primitive["material"] = 1;
  b.json["meshes"][0]["primitives"].push_back(primitive);
  b.addMesh(json::array({b.json["meshes"][0]["primitives"][0]}));  // another mesh with no material
  b.addNode({{"mesh", 1}});
  b.setScene({0, 1});
  const Scene scene = test::importText(b.gltf()).scene;
  ASSERT_EQ(scene.materials.size(), 2u);
  EXPECT_EQ(scene.materials[0].name, "default");
  EXPECT_EQ(scene.materials[0].baseColorFactor, glm::vec4(1.0f));
  EXPECT_EQ(scene.materials[1].name, "red");
  EXPECT_EQ(scene.materials[1].baseColorFactor, glm::vec4(1, 0, 0, 0.5f));
  EXPECT_EQ(scene.meshes[0].parts[0].material, 0u);
  EXPECT_EQ(scene.meshes[0].parts[2].material, 1u);
  EXPECT_EQ(scene.meshes[1].parts[0].material, 0u);
  EXPECT_TRUE(scene.textures.empty());
}

TEST(Materials, OtherTexCoordWarnsOnce) {
  GltfBuilder b = texturedTriangle(std::string("data:image/png;base64,") + test::kPngRgba2x2);
  b.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1;
  b.addMaterial(b.json["materials"][0]);
  json primitive = b.json["meshes"][0]["primitives"][0];
  primitive["material"] = 1;
  b.json["meshes"][0]["primitives"].push_back(primitive);
  const ImportResult result = test::importText(b.gltf());
  EXPECT_EQ(result.scene.textures.size(), 1u);  // one texture, used by both materials
  EXPECT_EQ(result.warnings, (std::vector<std::string>{"2 materials read their base colour texture through a texCoord "
                                                       "other than 0; TEXCOORD_0 is used instead"}));
}

// ---------------------------------------------------------------------------------------------
// Files: external resources and GLB

TEST(Files, GltfWithExternalBinAndPng) {
  test::ScratchDir dir;
  std::filesystem::create_directories(dir / "assets");
  const GltfBuilder b = texturedTriangle("assets/tex%20ture.png");  // URIs are percent-encoded
  test::writeFile(dir / "scene.gltf", b.gltf("assets/scene.bin"));
  test::writeFile(dir / "assets" / "scene.bin", b.bin);
  test::writeFile(dir / "assets" / "tex ture.png", test::fromBase64(test::kPngRgba2x2));
  const Scene scene = importGltf(dir / "scene.gltf").scene;
  EXPECT_EQ(scene.meshes.at(0).triangleCount(), 1u);
  ASSERT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.textures[0].rgba8,
            (std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128}));
  EXPECT_EQ(scene.textures[0].name, "assets/tex%20ture.png");
}

TEST(Files, HandBuiltGlbFromMemoryAndFromDisk) {
  const std::string glb = test::triangleFile().glb();
  const Scene fromMemory = importGltfFromMemory(test::asBytes(glb), "mem.glb", ".").scene;
  EXPECT_EQ(fromMemory.meshes.at(0).triangleCount(), 1u);
  test::ScratchDir dir;
  test::writeFile(dir / "named-like-json.gltf", glb);  // binary is told by its magic, not its name
  const Scene fromDisk = importGltf(dir / "named-like-json.gltf").scene;
  EXPECT_EQ(fromDisk.meshes.at(0).positions, fromMemory.meshes.at(0).positions);
}

// The spec wants chunks padded to 4 bytes; some writers do not pad the JSON, which is still readable.
TEST(Files, UnpaddedGlbJsonChunkOnlyWarns) {
  const GltfBuilder b = test::triangleFile();
  nlohmann::json doc = b.json;
  doc["buffers"] = json::array({{{"byteLength", b.bin.size()}}});
  std::string text = doc.dump();
  if (text.size() % 4 == 0) text += ' ';
  std::string bin = b.bin;
  bin.resize((bin.size() + 3) / 4 * 4, '\0');
  const auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::string body = u32(static_cast<std::uint32_t>(text.size())) + u32(0x4E4F534A) + text +
                           u32(static_cast<std::uint32_t>(bin.size())) + u32(0x004E4942) + bin;
  const std::string glb = "glTF" + u32(2) + u32(static_cast<std::uint32_t>(12 + body.size())) + body;
  const ImportResult result = test::importText(glb, "unpadded.glb");
  EXPECT_EQ(result.scene.meshes.at(0).triangleCount(), 1u);
  EXPECT_EQ(result.warnings, std::vector<std::string>{"GLB JSON chunk is not padded to 4 bytes"});
}

TEST(Files, GlbWithImageInABufferView) {
  GltfBuilder b = texturedTriangle("");
  b.json["images"][0] = {{"bufferView", b.addView(test::fromBase64(test::kPngGrey2x1))}, {"mimeType", "image/png"}};
  const Scene scene = test::importText(b.glb(), "textured.glb").scene;
  ASSERT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.textures[0].rgba8, (std::vector<std::uint8_t>{0, 0, 0, 255, 200, 200, 200, 255}));
}

}  // namespace
}  // namespace pbs
