// Tests of glTF import on bad input: each kind of malformed file gives an InputError that names the
// file and the element at fault; seeded random mutations never crash; `pbs info` reports one line.
#include "gltf_test_files.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_import.hpp>
#include <pbs/scene/input_error.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <random>

namespace pbs {
namespace {

using nlohmann::json;
using test::GltfBuilder;

// Expects `load` to throw an InputError, on one line, starting with `file` and containing each of `parts`.
void expectInputError(const std::function<void()>& load, const std::string& file,
                      std::initializer_list<std::string> parts) {
  try {
    load();
    ADD_FAILURE() << "no error; expected one naming " << *parts.begin();
  } catch (const InputError& error) {
    const std::string what = error.what();
    EXPECT_TRUE(what.starts_with(file + ": ")) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    for (const std::string& part : parts)
      EXPECT_NE(what.find(part), std::string::npos) << "no \"" << part << "\" in: " << what;
  }
}

// The file as .gltf (buffer as a data: URI) and as .glb: both must fail the same way.
void expectRejected(const GltfBuilder& b, std::initializer_list<std::string> parts) {
  expectInputError([&] { test::importText(b.gltf(), "bad.gltf"); }, "bad.gltf", parts);
  expectInputError([&] { test::importText(b.glb(), "bad.glb"); }, "bad.glb", parts);
}

// Positions and indices of the triangle file as raw bytes, to put NaN and Inf where JSON cannot.
GltfBuilder triangleWithPositions(const std::vector<float>& positions) {
  GltfBuilder b = test::triangleFile();
  std::memcpy(b.bin.data(), positions.data(), positions.size() * sizeof(float));
  return b;
}

// ---------------------------------------------------------------------------------------------
// Files that are not glTF at all

TEST(BadFiles, EmptyMissingOrADirectory) {
  test::ScratchDir dir;
  test::writeFile(dir / "empty.glb", "");
  const std::string empty = (dir / "empty.glb").string();
  expectInputError([&] { importGltf(empty); }, empty, {"empty"});
  const std::string missing = (dir / "missing.gltf").string();
  expectInputError([&] { importGltf(missing); }, missing, {"cannot open", "No such file"});
  expectInputError([&] { importGltf(dir.path()); }, dir.path().string(), {"directory"});
  // The file is mapped, not read: a device (which could stream forever) is refused up front.
  expectInputError([&] { importGltf("/dev/zero"); }, "/dev/zero", {"not a regular file"});
}

TEST(BadFiles, TruncatedGlb) {
  const std::string glb = test::triangleFile().glb();
  for (const std::size_t length : {std::size_t{4}, std::size_t{19}}) {
    expectInputError([&] { test::importText(glb.substr(0, length), "cut.glb"); }, "cut.glb",
                     {"GLB header", "too short"});
  }
  for (const std::size_t length : {std::size_t{20}, glb.size() / 2, glb.size() - 4}) {
    expectInputError([&] { test::importText(glb.substr(0, length), "cut.glb"); }, "cut.glb",
                     {"GLB header", "truncated"});
  }
}

TEST(BadFiles, GlbOfAnotherVersion) {
  std::string glb = test::triangleFile().glb();
  glb[4] = 1;
  expectInputError([&] { test::importText(glb, "v1.glb"); }, "v1.glb", {"GLB header", "version 1"});
}

// A BIN chunk's bound must count its 8-byte header (tinygltf 2.7's did not, and copied past the data).
TEST(BadFiles, GlbBinChunkLongerThanTheFile) {
  GltfBuilder b = test::triangleFile();
  const std::uint32_t jsonLength = static_cast<std::uint32_t>(b.glb().size()) - 20 - 8 - 44;  // 42 bytes of bin, padded
  std::string glb = b.glb();
  std::uint32_t binLength;
  std::memcpy(&binLength, glb.data() + 20 + jsonLength, 4);
  ASSERT_EQ(binLength, 44u);
  binLength += 8;
  std::memcpy(glb.data() + 20 + jsonLength, &binLength, 4);
  expectInputError([&] { test::importText(glb, "long.glb"); }, "long.glb",
                   {"GLB BIN chunk", "52 bytes run past the end"});
}

TEST(BadFiles, GarbageBytes) {
  std::string garbage;
  std::mt19937 random(7);
  for (int i = 0; i < 1000; ++i) garbage += static_cast<char>(random() % 256);
  garbage[0] = 'X';
  expectInputError([&] { test::importText(garbage, "noise.gltf"); }, "noise.gltf", {"not glTF"});
}

TEST(BadFiles, GlbWithGarbageForJson) {
  std::string glb = test::triangleFile().glb();
  glb[20] = '#';
  expectInputError([&] { test::importText(glb, "g.glb"); }, "g.glb", {"GLB JSON chunk", "does not start with '{'"});
}

// JSON nested without limit would exhaust any recursive reader's stack; the parser stops at 256 levels.
TEST(BadFiles, DeeplyNestedJson) {
  GltfBuilder b = test::triangleFile();
  b.json["extras"] = "PLACEHOLDER";
  std::string text = b.gltf();
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  text.replace(text.find("\"PLACEHOLDER\""), 13, deep);
  expectInputError([&] { test::importText(text, "deep.gltf"); }, "deep.gltf", {"JSON", "nested deeper than"});
  // Brackets inside strings do not count.
  b.json["extras"] = std::string(100000, '[') + "\"\\";
  EXPECT_EQ(test::importText(b.gltf()).scene.meshes.size(), 1u);
}

TEST(BadFiles, InvalidJson) {
  expectInputError([&] { test::importText(R"({"asset": {"version": "2.0"}, "nodes": [)", "cut.gltf"); }, "cut.gltf",
                   {"JSON"});
  expectInputError([&] { test::importText(R"({"nodes": []})", "noasset.gltf"); }, "noasset.gltf", {"asset"});
}

// ---------------------------------------------------------------------------------------------
// Accessors, buffer views and buffers

TEST(BadData, IndexOutOfRange) {
  GltfBuilder b = test::triangleFile();
  const std::uint16_t seven = 7;
  std::memcpy(b.bin.data() + 36 + 2, &seven, 2);  // the second index
  expectRejected(b, {"accessor 1", "index 7 out of range (3 vertices)"});
}

TEST(BadData, IndicesAccessorDoesNotExist) {
  GltfBuilder b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["indices"] = 9;
  expectRejected(b, {"mesh 0 primitive 0"});
}

TEST(BadData, AccessorRunsPastItsBufferView) {
  GltfBuilder b = test::triangleFile();
  b.json["accessors"][0]["count"] = 4;
  expectRejected(b, {"accessor 0", "bufferView 0"});
  b = test::triangleFile();
  b.json["accessors"][0]["byteOffset"] = 4;
  expectRejected(b, {"accessor 0", "run past the end of bufferView 0"});
}

TEST(BadData, BufferViewRunsPastItsBuffer) {
  GltfBuilder b = test::triangleFile();
  b.json["bufferViews"][1]["byteLength"] = 100;
  expectRejected(b, {"bufferView 1", "buffer 0"});
}

TEST(BadData, StrideSmallerThanTheElement) {
  GltfBuilder b = test::triangleFile();
  b.json["bufferViews"][0]["byteStride"] = 4;
  expectRejected(b, {"accessor 0", "byteStride 4"});
}

TEST(BadData, WrongTypeOrComponentTypeForTheSemantic) {
  GltfBuilder b = test::triangleFile();
  b.json["accessors"][0]["type"] = "VEC2";
  expectRejected(b, {"accessor 0", "POSITION must be VEC3"});
  b = test::triangleFile();
  b.json["accessors"][0]["componentType"] = test::kUnsignedInt;
  expectRejected(b, {"accessor 0", "POSITION cannot use componentType UNSIGNED_INT"});
  b = test::triangleFile();
  b.json["accessors"][1]["componentType"] = test::kFloat;
  expectRejected(b, {"accessor 1", "indices cannot use componentType FLOAT"});
}

TEST(BadData, NanAndInfPositions) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  expectRejected(triangleWithPositions({0, 0, 0, nan, 0, 0}), {"accessor 0", "element 1 is not finite"});
  expectRejected(triangleWithPositions({0, 0, 0, 1, 0, 0, 0, -inf, 0}), {"accessor 0", "element 2 is not finite"});
}

TEST(BadData, SparseIndexOutOfRange) {
  GltfBuilder b = test::triangleFile();
  const int indices = b.addView(test::bytesOf(std::vector<std::uint8_t>{3, 0, 0, 0}));
  const int values = b.addView(test::bytesOf(std::vector<float>{1, 2, 3}));
  b.json["accessors"][0]["sparse"] = {{"count", 1},
                                      {"indices", {{"bufferView", indices}, {"componentType", test::kUnsignedByte}}},
                                      {"values", {{"bufferView", values}}}};
  expectRejected(b, {"accessor 0", "sparse index 3 out of range (3 elements)"});
  b.json["accessors"][0]["sparse"]["values"]["byteOffset"] = 8;
  expectRejected(b, {"accessor 0", "sparse values run past the end of bufferView"});
}

TEST(BadData, AttributeCountsDisagree) {
  GltfBuilder b = test::triangleFile();
  const int normals = b.addAccessor(std::vector<float>{0, 0, 1, 0, 0, 1}, test::kFloat, "VEC3");
  b.json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = normals;
  expectRejected(b, {"accessor 2", "NORMAL has 2 elements but POSITION has 3"});
}

// A property of the wrong JSON type is named with its element.
TEST(BadData, ParserErrorsNameTheElement) {
  GltfBuilder b = test::triangleFile();
  b.json["bufferViews"][1]["byteLength"] = "six";
  expectRejected(b, {"bufferView 1", "byteLength"});
  b = test::triangleFile();
  b.json["accessors"][1]["count"] = -3;
  expectRejected(b, {"accessor 1", "count"});
  b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["attributes"] = 5;
  expectRejected(b, {"mesh 0", "attributes"});
  b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["material"] = 0;
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1}}}}});
  expectRejected(b, {"material 0", "baseColorFactor"});
  b.json["materials"][0]["pbrMetallicRoughness"] = {{"baseColorTexture", {{"texCoord", 0}}}};
  expectRejected(b, {"material 0", "index"});
  b = test::triangleFile();
  b.json["nodes"].push_back(7);
  expectRejected(b, {"node 1", "JSON object"});
}

TEST(BadData, EveryPropertyIsCheckedWhereItIsRead) {
  const auto rejected = [](const std::function<void(GltfBuilder&)>& spoil, std::initializer_list<std::string> parts) {
    GltfBuilder b = test::triangleFile();
    spoil(b);
    expectRejected(b, parts);
  };
  rejected([](GltfBuilder& b) { b.json["accessors"][0]["type"] = "VEC5"; }, {"accessor 0", "type 'VEC5'"});
  rejected([](GltfBuilder& b) { b.json["accessors"][0].erase("componentType"); }, {"accessor 0", "no componentType"});
  rejected([](GltfBuilder& b) { b.json["accessors"][0]["normalized"] = 1; }, {"accessor 0", "normalized is 1"});
  rejected([](GltfBuilder& b) { b.json["accessors"][0]["bufferView"] = 0.5; }, {"accessor 0", "bufferView is 0.5"});
  rejected([](GltfBuilder& b) { b.json["bufferViews"][0]["byteStride"] = 2; }, {"bufferView 0", "byteStride is 2"});
  rejected([](GltfBuilder& b) { b.json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = "one"; },
           {"mesh 0 primitive 0 attributes", "NORMAL is a string"});
  rejected([](GltfBuilder& b) { b.json["meshes"][0]["primitives"] = 1; }, {"mesh 0", "primitives is 1, not an array"});
  rejected([](GltfBuilder& b) { b.json["nodes"][0]["children"] = {-1}; }, {"node 0", "children is -1"});
  rejected([](GltfBuilder& b) { b.json["nodes"][0]["matrix"] = {"1"}; }, {"node 0", "matrix holds a string"});
  rejected([](GltfBuilder& b) { b.json["asset"]["version"] = "1.0"; }, {"asset", "version 1.0 is not supported"});
  rejected([](GltfBuilder& b) { b.json["asset"].erase("version"); }, {"asset", "has no version"});
  rejected([](GltfBuilder& b) { b.json["extensionsRequired"] = {7}; }, {"extensionsRequired", "holds 7"});
}

TEST(BadData, BufferUris) {
  GltfBuilder b = test::triangleFile();
  nlohmann::json doc = nlohmann::json::parse(b.gltf());
  const auto rejectedBuffer = [&](const nlohmann::json& buffer, std::initializer_list<std::string> parts) {
    nlohmann::json spoilt = doc;
    spoilt["buffers"][0] = buffer;
    expectInputError([&] { test::importText(spoilt.dump(), "uri.gltf"); }, "uri.gltf", parts);
  };
  const std::size_t length = b.bin.size();
  rejectedBuffer({{"byteLength", length}}, {"buffer 0", "has no uri"});
  rejectedBuffer({{"byteLength", length}, {"uri", "data:application/octet-stream,plain"}}, {"buffer 0", "not base64"});
  rejectedBuffer({{"byteLength", length}, {"uri", "data:application/octet-stream;base64,AA*A"}},
                 {"buffer 0", "not base64"});
  rejectedBuffer({{"byteLength", length}, {"uri", "data:application/octet-stream;base64,AAAA"}},
                 {"buffer 0", "its data: URI holds 3 bytes, fewer than its byteLength"});
  rejectedBuffer({{"byteLength", length}, {"uri", "/etc/hostname"}}, {"buffer 0", "only files relative"});
  rejectedBuffer({{"byteLength", length}, {"uri", "https://example.com/a.bin"}}, {"buffer 0", "only files relative"});
  rejectedBuffer({{"byteLength", 0}, {"uri", "a.bin"}}, {"buffer 0", "byteLength is 0"});
  // A GLB whose JSON names a first buffer without a uri but has no BIN chunk.
  GltfBuilder noBin = test::triangleFile();
  noBin.json["buffers"] = json::array({{{"byteLength", 4}}});
  noBin.bin.clear();
  expectInputError([&] { test::importText(noBin.glb(), "nobin.glb"); }, "nobin.glb",
                   {"buffer 0", "more than the GLB BIN chunk's 0 bytes"});
}

// ---------------------------------------------------------------------------------------------
// Primitives and references

TEST(BadReferences, MissingAccessorBufferViewBufferMeshNodeMaterial) {
  GltfBuilder b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 12;
  expectRejected(b, {"mesh 0 primitive 0", "accessor 12 does not exist (the file has 2)"});
  b = test::triangleFile();
  b.json["accessors"][0]["bufferView"] = 8;
  expectRejected(b, {"accessor 0", "bufferView 8 does not exist"});
  b = test::triangleFile();
  b.json["bufferViews"][0]["buffer"] = 3;
  expectRejected(b, {"bufferView 0", "buffer 3 does not exist"});
  b = test::triangleFile();
  b.json["nodes"][0]["mesh"] = 5;
  expectRejected(b, {"node 0", "mesh 5 does not exist"});
  b = test::triangleFile();
  b.json["nodes"][0]["children"] = {9};
  expectRejected(b, {"node 0", "child node 9 does not exist"});
  b = test::triangleFile();
  b.json["scenes"][0]["nodes"] = {0, 4};
  expectRejected(b, {"scene 0", "node 4 does not exist"});
  b = test::triangleFile();
  b.json["scene"] = 3;
  expectRejected(b, {"scene", "default scene 3 does not exist"});
  b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["material"] = 2;
  expectRejected(b, {"mesh 0 primitive 0", "material 2 does not exist"});
}

TEST(BadReferences, MissingTextureImageOrSampler) {
  GltfBuilder b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["material"] = 0;
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 3}}}}}});
  expectRejected(b, {"material 0", "texture 3 does not exist"});
  b.append("textures", {{"source", 4}});
  b.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 0;
  expectRejected(b, {"texture 0", "image 4 does not exist"});
  b.append("images", {{"uri", std::string("data:image/png;base64,") + test::kPngRgba2x2}});
  b.json["textures"][0] = {{"source", 0}, {"sampler", 2}};
  expectRejected(b, {"texture 0", "sampler 2 does not exist"});
  b.append("samplers", {{"wrapS", 1234}});
  b.json["textures"][0]["sampler"] = 0;
  expectRejected(b, {"sampler 0", "wrapS 1234"});
}

TEST(BadReferences, UndecodableImage) {
  GltfBuilder b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["material"] = 0;
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.append("textures", {{"source", 0}});
  b.append("images", {{"uri", "data:image/png;base64," + test::base64("certainly not a PNG")}});
  expectRejected(b, {"image 0", "cannot decode"});
  b.json["images"][0] = {{"bufferView", 0}, {"mimeType", "image/png"}};  // the positions' bytes
  expectRejected(b, {"image 0", "cannot decode"});
  b.json["images"][0] = {{"bufferView", 7}, {"mimeType", "image/png"}};
  expectRejected(b, {"image 0", "bufferView", "7"});
}

TEST(BadReferences, PrimitiveWithoutPositionOrWithAnUnknownMode) {
  GltfBuilder b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["attributes"] = {{"NORMAL", 0}};
  expectRejected(b, {"mesh 0 primitive 0", "no POSITION"});
  b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["mode"] = 9;
  expectRejected(b, {"mesh 0 primitive 0", "mode 9"});
  b = test::triangleFile();
  b.json["accessors"][1]["count"] = 2;
  expectRejected(b, {"mesh 0 primitive 0", "multiple of 3"});
}

TEST(BadReferences, UnsupportedRequiredExtension) {
  GltfBuilder b = test::triangleFile();
  b.json["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  expectRejected(b, {"extensionsRequired", "KHR_draco_mesh_compression is not supported"});
}

// ---------------------------------------------------------------------------------------------
// Nodes

TEST(BadNodes, NonFiniteOrMalformedTransforms) {
  GltfBuilder b = test::triangleFile();
  // JSON has no NaN or Inf: the parser rejects a NaN literal and a number too large for a
  // double, so a non-finite node value can only ever arrive as a JSON error.
  b.json["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::string text = b.gltf();
  const std::string first = "[1,0,0,0";
  for (const char* value : {"NaN", "1e999", "-1e400"}) {
    std::string bad = text;
    bad.replace(bad.find(first), first.size(), std::string("[") + value + ",0,0,0");
    expectInputError([&] { test::importText(bad, "nan.gltf"); }, "nan.gltf", {"JSON"});
  }
  b.json["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  expectRejected(b, {"node 0", "matrix has 12 numbers, not 16"});
  b.json["nodes"][0].erase("matrix");
  b.json["nodes"][0]["rotation"] = {0, 0, 0, 0};
  expectRejected(b, {"node 0", "rotation quaternion is zero"});
  b.json["nodes"][0]["rotation"] = {0, 0, 0, 1};
  b.json["nodes"][0]["scale"] = {1, 1};
  expectRejected(b, {"node 0", "scale has 2 numbers"});
}

TEST(BadNodes, HugeQuaternionIsNormalisedNotOverflowed) {
  GltfBuilder b = test::triangleFile();
  b.json["nodes"][0]["rotation"] = {0, 0, 1e300, 1e300};  // squared, these would overflow
  const glm::dmat4 local = test::importText(b.gltf()).scene.nodes.at(0).local;
  EXPECT_NEAR(local[0][1], 1.0, 1e-12);  // 90 degrees about z: x goes to y
}

TEST(BadData, BaseColorFactorBeyondFloat) {
  GltfBuilder b = test::triangleFile();
  b.json["meshes"][0]["primitives"][0]["material"] = 0;
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1e300, 1, 1}}}}});  // finite double, infinite float
  expectRejected(b, {"material 0", "baseColorFactor is not finite"});
}

TEST(BadNodes, Cycles) {
  GltfBuilder b = test::triangleFile();
  b.json["nodes"] = json::array({{{"children", {1}}}, {{"children", {2}}}, {{"mesh", 0}, {"children", {1}}}});
  expectRejected(b, {"node 1", "cycle"});
  b.json["nodes"] = json::array({{{"mesh", 0}, {"children", {0}}}});
  expectRejected(b, {"node 0", "cycle"});
}

TEST(BadNodes, TwoParents) {
  GltfBuilder b = test::triangleFile();
  b.json["nodes"] = json::array({{{"children", {1, 2}}}, {{"children", {2}}}, {{"mesh", 0}}});
  expectRejected(b, {"node 2", "two parents", "node 0", "node 1"});
  b.setScene({0, 2});
  b.json["nodes"] = json::array({{{"children", {1}}}, {{"mesh", 0}}, {{"children", {1}}}});
  expectRejected(b, {"node 1", "two parents"});
  b.setScene({0, 0});
  expectRejected(b, {"node 0", "listed twice"});
}

// ---------------------------------------------------------------------------------------------
// External files

TEST(BadExternalFiles, MissingBinOrImage) {
  test::ScratchDir dir;
  GltfBuilder b = test::triangleFile();
  test::writeFile(dir / "scene.gltf", b.gltf("missing.bin"));
  const std::string scene = (dir / "scene.gltf").string();
  expectInputError([&] { importGltf(scene); }, scene, {"buffer 0", "missing.bin"});
  // A .bin of the wrong size is as bad as none.
  test::writeFile(dir / "short.bin", b.bin.substr(0, 10));
  test::writeFile(dir / "scene.gltf", b.gltf("short.bin"));
  expectInputError([&] { importGltf(scene); }, scene, {"buffer 0", "short.bin"});

  b.json["meshes"][0]["primitives"][0]["material"] = 0;
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.append("textures", {{"source", 0}});
  b.append("images", {{"uri", "missing.png"}});
  test::writeFile(dir / "scene.gltf", b.gltf());
  expectInputError([&] { importGltf(scene); }, scene, {"image 0", "cannot read 'missing.png'"});
}

// ---------------------------------------------------------------------------------------------
// Seeded random mutations: every one imports or throws InputError; nothing crashes.

// A small file touching most of the importer: strip and triangles, normals, uvs, sparse, a texture.
GltfBuilder richFile() {
  GltfBuilder b = test::triangleFile();
  const int normals = b.addAccessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}, test::kFloat, "VEC3");
  const int uvs =
      b.addAccessor(std::vector<std::uint16_t>{0, 0, 65535, 0, 0, 65535}, test::kUnsignedShort, "VEC2", true);
  const int sparseIndices = b.addView(test::bytesOf(std::vector<std::uint8_t>{1, 0, 0, 0}));
  const int sparseValues = b.addView(test::bytesOf(std::vector<float>{2, 0, 0}));
  b.json["accessors"][0]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", sparseIndices}, {"componentType", test::kUnsignedByte}}},
      {"values", {{"bufferView", sparseValues}}}};
  b.json["meshes"][0]["primitives"][0]["attributes"] = {{"POSITION", 0}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}};
  b.json["meshes"][0]["primitives"][0]["material"] = 0;
  b.json["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"mode", test::kModeStrip}});
  b.addMaterial(
      {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0.5, 0.5, 1}}, {"baseColorTexture", {{"index", 0}}}}}});
  b.append("samplers", {{"wrapS", 33071}, {"magFilter", 9728}});
  b.append("textures", {{"source", 0}, {"sampler", 0}});
  b.append("images", {{"bufferView", b.addView(test::fromBase64(test::kPngRgba2x2))}, {"mimeType", "image/png"}});
  b.json["nodes"][0]["translation"] = {1, 2, 3};
  b.addNode({{"children", {0}}, {"rotation", {0, 0, 0, 1}}});
  b.addNode({{"mesh", 0}, {"scale", {2, 2, 2}}});
  b.setScene({1, 2});
  return b;
}

void mutateAndImport(const std::string& valid, const std::string& name, std::uint64_t seed, int rounds) {
  std::mt19937_64 random(seed);
  const auto pick = [&](std::size_t n) -> std::size_t { return random() % n; };
  int imported = 0;
  for (int round = 0; round < rounds; ++round) {
    std::string bytes = valid;
    switch (round % 4) {
      case 0:  // a few random bytes
        for (std::size_t k = 1 + pick(4); k > 0; --k) bytes[pick(bytes.size())] = static_cast<char>(random());
        break;
      case 1:  // truncation
        bytes.resize(pick(bytes.size()));
        break;
      case 2:    // one digit changed: indices, counts, offsets and lengths go wrong while the JSON stays valid
      case 3: {  // or a digit inserted, making a number much larger
        std::vector<std::size_t> digits;
        for (std::size_t i = 0; i < bytes.size(); ++i)
          if (bytes[i] >= '0' && bytes[i] <= '9') digits.push_back(i);
        const std::size_t at = digits[pick(digits.size())];
        const char digit = static_cast<char>('0' + pick(10));
        if (round % 4 == 2) {
          bytes[at] = digit;
        } else {
          bytes.insert(at, 1, digit);
        }
        break;
      }
    }
    try {
      test::importText(bytes, name);
      ++imported;
    } catch (const InputError&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << " round " << round << ": not an InputError: " << e.what();
    }
  }
  // Some mutations (a digit in a name, a byte of padding) leave the file valid.
  EXPECT_GT(imported, 0);
}

TEST(Fuzz, MutatedGlbImportsOrThrowsInputError) { mutateAndImport(richFile().glb(), "fuzz.glb", 1, 400); }

TEST(Fuzz, MutatedGltfImportsOrThrowsInputError) { mutateAndImport(richFile().gltf(), "fuzz.gltf", 2, 400); }

TEST(Fuzz, TheUnmutatedFilesImport) {
  EXPECT_EQ(test::importText(richFile().glb(), "rich.glb").scene.meshes.at(0).triangleCount(), 2u);
  EXPECT_EQ(test::importText(richFile().gltf(), "rich.gltf").scene.textures.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// The command line: `pbs info` on a bad file says "error: <message>" on one line and exits 1.

void expectCliError(const std::filesystem::path& file, const std::string& expected) {
  const test::CommandResult result = test::runPbs("info '" + file.string() + "'");
  EXPECT_EQ(result.status, 1) << result.err;
  EXPECT_TRUE(result.err.starts_with("error: " + file.string() + ": ")) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_NE(result.err.find(expected), std::string::npos) << result.err;
}

TEST(Cli, InfoReportsBadFilesOnOneLine) {
  test::ScratchDir dir;
  test::writeFile(dir / "empty.glb", "");
  expectCliError(dir / "empty.glb", "empty");
  test::writeFile(dir / "cut.glb", test::triangleFile().glb().substr(0, 40));
  expectCliError(dir / "cut.glb", "GLB header");
  test::writeFile(dir / "noise.gltf", std::string(64, '\x7f'));
  expectCliError(dir / "noise.gltf", "not glTF");
  test::writeFile(dir / "broken.gltf", R"({"asset": {"version": "2.0"}, "nodes": [)");
  expectCliError(dir / "broken.gltf", "JSON");
  GltfBuilder cycle = test::triangleFile();
  cycle.json["nodes"][0]["children"] = {0};
  test::writeFile(dir / "cycle.gltf", cycle.gltf());
  expectCliError(dir / "cycle.gltf", "node 0");
  test::writeFile(dir / "nobin.gltf", test::triangleFile().gltf("nobin.bin"));
  expectCliError(dir / "nobin.gltf", "buffer 0");
}

}  // namespace
}  // namespace pbs
