// Writes the fuzzers' seed corpora: small valid files that between them use every feature the
// readers handle, so that mutations start from inputs that get deep. Run once, output committed:
//   build-fuzz/bin/pbs_fuzz_seeds tests/fuzz/corpus
// gltf/: hand-built glTF (data: URIs and GLB, through tests/gltf_test_files.hpp) and a writeGlb export;
// surfels/: writeSurfelFile output.
#include "gltf_test_files.hpp"
#include "pbs/scene/gltf_export.hpp"
#include "pbs/surfels/surfel_file.hpp"

#include <cstdio>
#include <fstream>
#include <iostream>

namespace {

using namespace pbs;
using namespace pbs::test;
using nlohmann::json;

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
  std::cout << path.string() << ": " << text.size() << " bytes\n";
}

// A unit quad with normals, uvs, UNSIGNED_BYTE indices and a textured material whose PNG sits in a
// bufferView.
GltfBuilder texturedQuad() {
  GltfBuilder b;
  const int positions = b.addAccessor(std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, kFloat, "VEC3");
  const int normals = b.addAccessor(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, kFloat, "VEC3");
  const int uvs =
      b.addAccessor(std::vector<std::uint16_t>{0, 0, 65535, 0, 65535, 65535, 0, 65535}, kUnsignedShort, "VEC2", true);
  const int indices = b.addAccessor(std::vector<std::uint8_t>{0, 1, 2, 0, 2, 3}, kUnsignedByte, "SCALAR");
  const int image = b.addView(fromBase64(kPngRgba2x2));
  b.append("images", {{"bufferView", image}, {"mimeType", "image/png"}});
  b.append("samplers", {{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}, {"minFilter", 9987}});
  b.append("textures", {{"source", 0}, {"sampler", 0}});
  b.addMaterial(
      {{"name", "checker"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 0.5, 0.25, 1.0}}, {"baseColorTexture", {{"index", 0}}}}}});
  b.addMesh({{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}}},
              {"indices", indices},
              {"material", 0}}});
  b.addNode({{"mesh", 0}, {"name", "quad"}});
  b.setScene({0});
  return b;
}

// The same quad's texture as a data: URI image (grey PNG), the uvs as floats.
GltfBuilder uriTexture() {
  GltfBuilder b;
  const int positions = b.addAccessor(std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0}, kFloat, "VEC3");
  const int uvs = b.addAccessor(std::vector<float>{0, 0, 1, 0, 1, 1}, kFloat, "VEC2");
  b.append("images", {{"uri", std::string("data:image/png;base64,") + kPngGrey2x1}});
  b.append("textures", {{"source", 0}});
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 0}}}}}});
  b.addMesh({{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", uvs}}}, {"material", 0}}});
  b.addNode({{"mesh", 0}});
  b.setScene({0});
  return b;
}

// A hierarchy: matrix and TRS transforms, children, one mesh instanced twice, strips and fans,
// a sparse accessor, quantized (BYTE) positions, a skipped POINTS primitive, and a second scene.
GltfBuilder hierarchy() {
  GltfBuilder b;
  const int strip = b.addAccessor(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0}, kFloat, "VEC3");
  const int quantized =
      b.addAccessor(std::vector<std::int8_t>{0, 0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127}, kByte, "VEC3", true);
  const int fanIndices = b.addAccessor(std::vector<std::uint32_t>{0, 1, 2, 3}, kUnsignedInt, "SCALAR");
  // Sparse: three zero positions of which two are replaced.
  const int sparseIndices = b.addView(bytesOf(std::vector<std::uint16_t>{1, 2}));
  const int sparseValues = b.addView(bytesOf(std::vector<float>{1, 0, 0, 0, 1, 0}));
  const int sparse =
      b.append("accessors", {{"componentType", kFloat},
                             {"count", 3},
                             {"type", "VEC3"},
                             {"sparse",
                              {{"count", 2},
                               {"indices", {{"bufferView", sparseIndices}, {"componentType", kUnsignedShort}}},
                               {"values", {{"bufferView", sparseValues}}}}}});
  b.addMesh({{{"attributes", {{"POSITION", strip}}}, {"mode", kModeStrip}},
             {{"attributes", {{"POSITION", quantized}}}, {"indices", fanIndices}, {"mode", kModeFan}},
             {{"attributes", {{"POSITION", strip}}}, {"mode", kModePoints}}});
  b.addMesh({{{"attributes", {{"POSITION", sparse}}}}});
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 1.0}}}}});
  b.addNode({{"name", "root"}, {"children", std::vector<int>{1, 2, 3}}, {"translation", {1.0, 2.0, 3.0}}});
  b.addNode({{"mesh", 0}, {"rotation", {0.0, 0.7071068, 0.0, 0.7071068}}, {"scale", {2.0, 2.0, 2.0}}});
  b.addNode(
      {{"mesh", 0}, {"matrix", {1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 5.0, 0.0, 0.0, 1.0}}});
  b.addNode({{"children", std::vector<int>{4}}});
  b.addNode({{"mesh", 1}});
  b.json["extensionsUsed"] = {"KHR_mesh_quantization"};
  b.json["extensionsRequired"] = {"KHR_mesh_quantization"};
  b.json["scenes"] = json::array({{{"nodes", std::vector<int>{0}}}, {{"nodes", std::vector<int>{3}}}});
  b.json["scene"] = 0;
  return b;
}

// No scenes: the parentless nodes are the roots.
GltfBuilder noScenes() {
  GltfBuilder b = triangleFile();
  b.json.erase("scenes");
  b.json.erase("scene");
  b.addNode({{"children", std::vector<int>{0}}});
  b.addNode({{"mesh", 0}, {"translation", {0.0, 0.0, -1.0}}});
  return b;
}

// A small scene through the exporter: two meshes, one instanced, a textured material.
Scene exportedScene() {
  Scene scene;
  Mesh triangle;
  triangle.name = "triangle";
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  triangle.uvs = {{0, 0}, {1, 0}, {0, 1}};
  triangle.indices = {0, 1, 2};
  triangle.parts = {MeshPart{0, 3, 0}};
  updateMeshBounds(triangle);
  Mesh tetra;
  tetra.name = "tetra";
  tetra.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetra.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  tetra.normals = computeVertexNormals(tetra.positions, tetra.indices);
  tetra.parts = {MeshPart{0, 6, 0}, MeshPart{6, 6, 1}};
  updateMeshBounds(tetra);
  scene.meshes = {triangle, tetra};
  Texture texture;
  texture.name = "checker";
  texture.width = 2;
  texture.height = 2;
  texture.rgba8 = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128};
  texture.wrapS = TextureWrap::ClampToEdge;
  texture.magFilter = TextureFilter::Nearest;
  scene.textures = {texture};
  scene.materials = {Material{"textured", glm::vec4(1.0f), 0},
                     Material{"plain", glm::vec4(0.5f, 0.5f, 0.5f, 1.0f), -1}};
  Node root{"root", glm::dmat4(1.0), {1, 2}, -1};
  Node a{"a", glm::dmat4(1.0), {}, 0};
  Node b{"b", glm::dmat4(1.0), {}, 1};
  b.local[3] = glm::dvec4(2.0, 0.0, 0.0, 1.0);
  Node c{"c", glm::dmat4(2.0), {}, 1};
  c.local[3][3] = 1.0;
  scene.nodes = {root, a, b, c};
  scene.roots = {0, 3};
  return scene;
}

std::vector<Surfel> surfels(std::size_t count) {
  std::vector<Surfel> result(count);
  for (std::size_t i = 0; i < count; ++i) {
    const float t = static_cast<float>(i) / static_cast<float>(count);
    result[i].position = {t - 0.5f, 0.5f - t * t, 0.25f * t};
    result[i].normal = glm::normalize(glm::vec3(t, 1.0f, 0.5f - t));
    result[i].color = glm::u8vec4(static_cast<std::uint8_t>(i * 7), static_cast<std::uint8_t>(i * 13), 200, 255);
  }
  return result;
}

SurfelArray array(std::size_t count, double extent) {
  SurfelArray a;
  a.box = Bounds{glm::dvec3(-extent, -extent, -extent), glm::dvec3(extent, extent, extent)};
  a.coverage = 0.9;
  a.packing = 1.5;
  a.area = 4.0 * extent * extent;
  a.surfels = surfels(count);
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: pbs_fuzz_seeds CORPUS_DIR (writes CORPUS_DIR/gltf and CORPUS_DIR/surfels)\n";
    return 2;
  }
  const std::filesystem::path root = argv[1];
  const std::filesystem::path gltfDir = root / "gltf", surfelDir = root / "surfels";
  std::filesystem::create_directories(gltfDir);
  std::filesystem::create_directories(surfelDir);

  writeText(gltfDir / "triangle.gltf", triangleFile().gltf());
  writeText(gltfDir / "triangle.glb", triangleFile().glb());
  writeText(gltfDir / "textured_quad.glb", texturedQuad().glb());
  writeText(gltfDir / "uri_texture.gltf", uriTexture().gltf());
  writeText(gltfDir / "hierarchy.gltf", hierarchy().gltf());
  writeText(gltfDir / "hierarchy.glb", hierarchy().glb());
  writeText(gltfDir / "no_scenes.gltf", noScenes().gltf());
  writeGlb(exportedScene(), gltfDir / "exported.glb");
  std::cout << (gltfDir / "exported.glb").string() << ": " << std::filesystem::file_size(gltfDir / "exported.glb")
            << " bytes\n";

  SurfelFile empty;
  writeSurfelFile(surfelDir / "empty.surfels", empty);
  SurfelFile small;
  small.sceneFingerprint = 0x0123456789ABCDEFull;
  small.options.ordering = SurfelOrdering::Dart;
  small.options.colors = SurfelColors::Pixel;
  small.arrays = {array(3, 1.0), array(0, 2.0), array(17, 0.0)};
  small.nodes = {{"/0", 0}, {"/0/1", 0}, {"/1", 1}, {"/2/0", 2}};
  small.sceneTable = {.structure = 11,
                      .meshes = {12, 13},
                      .instanceBounds = {Bounds{}, Bounds{glm::dvec3(-1.0, 0.0, 2.0), glm::dvec3(1.0, 0.5, 2.0)}}};
  writeSurfelFile(surfelDir / "small.surfels", small);
  SurfelFile chunks;
  chunks.arrays = {array(kSurfelsPerChunk + 9, 10.0)};
  chunks.nodes = {{"/0", 0}};
  writeSurfelFile(surfelDir / "two_chunks.surfels", chunks);
  for (const char* name : {"empty.surfels", "small.surfels", "two_chunks.surfels"}) {
    std::cout << (surfelDir / name).string() << ": " << std::filesystem::file_size(surfelDir / name) << " bytes\n";
  }
  return 0;
}
