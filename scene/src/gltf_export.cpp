// Writes a scene as glTF: every mesh stored once (nodes instance it), one primitive per part over shared
// vertex accessors, textures as PNG in the binary data; all of it in one .glb, or a .gltf with its data
// in .bin files written mesh by mesh.
#include "pbs/scene/gltf_export.hpp"

#include "pbs/scene/hierarchy.hpp"

#include <nlohmann/json.hpp>

#include <tiny_gltf.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace pbs {
namespace {

constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;

// A name beside `file` that no other writer in this or another process picks.
std::filesystem::path temporaryBeside(const std::filesystem::path& file) {
  static std::atomic<std::uint64_t> counter{0};
  return file.parent_path() /
         (file.filename().string() + "." + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".tmp");
}

// Where the views' bytes go: the one buffer of a .glb, held in memory (model.buffers[0].data), or .bin
// files beside a .gltf, written as they come (temporaries until commit()), a new one before one would
// pass a given size. Every view starts on a 4-byte boundary so every component type is aligned.
class BinaryData {
 public:
  // In memory, for a .glb.
  explicit BinaryData(tinygltf::Model& model) : model_(model) { model_.buffers.resize(1); }
  // Into files named `<gltf's stem>.<k>.bin` beside `gltf`, each at most `maxBinBytes` unless one view is larger.
  BinaryData(tinygltf::Model& model, const std::filesystem::path& gltf, std::uint64_t maxBinBytes)
      : model_(model), gltf_(gltf), maxBinBytes_(maxBinBytes) {}
  ~BinaryData() {
    std::error_code ignored;
    for (const Bin& bin : bins_) std::filesystem::remove(bin.temporary, ignored);
  }

  int addView(const void* data, std::size_t bytes, int target) {
    const auto* first = static_cast<const unsigned char*>(data);
    tinygltf::BufferView view;
    view.byteLength = bytes;
    view.target = target;
    if (!gltf_) {
      std::vector<unsigned char>& buffer = model_.buffers[0].data;
      buffer.resize((buffer.size() + 3) & ~std::size_t(3), 0);
      view.buffer = 0;
      view.byteOffset = buffer.size();
      buffer.insert(buffer.end(), first, first + bytes);
    } else {
      if (bins_.empty() || (bins_.back().bytes > 0 && bins_.back().bytes + bytes + 3 > maxBinBytes_)) startBin();
      Bin& bin = bins_.back();
      const std::uint64_t padding = (4 - bin.bytes % 4) % 4;
      const char zeros[4] = {};
      bin.out.write(zeros, std::streamsize(padding));
      bin.out.write(reinterpret_cast<const char*>(first), std::streamsize(bytes));
      if (!bin.out) throw std::runtime_error(bin.temporary.string() + ": write failed: " + std::strerror(errno));
      view.buffer = int(bins_.size() - 1);
      view.byteOffset = bin.bytes + padding;
      bin.bytes += padding + bytes;
    }
    model_.bufferViews.push_back(std::move(view));
    return int(model_.bufferViews.size() - 1);
  }

  // The .bin files as the .gltf names them (uri, byteLength), closed; empty for a .glb.
  nlohmann::json buffers() {
    nlohmann::json list = nlohmann::json::array();
    for (Bin& bin : bins_) {
      bin.out.close();  // reports a failed final flush, e.g. a full disk
      if (!bin.out) throw std::runtime_error(bin.temporary.string() + ": write failed: " + std::strerror(errno));
      list.push_back({{"uri", bin.file.filename().string()}, {"byteLength", bin.bytes}});
    }
    return list;
  }
  // Renames the .bin files into place; returns their names.
  std::vector<std::filesystem::path> commit() {
    std::vector<std::filesystem::path> files;
    for (Bin& bin : bins_) {
      std::filesystem::rename(bin.temporary, bin.file);
      files.push_back(bin.file);
    }
    bins_.clear();
    return files;
  }

 private:
  struct Bin {
    std::filesystem::path file, temporary;
    std::ofstream out;
    std::uint64_t bytes = 0;
  };
  void startBin() {
    Bin bin;
    bin.file = gltf_->parent_path() / (gltf_->stem().string() + "." + std::to_string(bins_.size()) + ".bin");
    bin.temporary = temporaryBeside(bin.file);
    bin.out.open(bin.temporary, std::ios::binary | std::ios::trunc);
    if (!bin.out) throw std::runtime_error(bin.file.string() + ": cannot create: " + std::strerror(errno));
    bins_.push_back(std::move(bin));
  }

  tinygltf::Model& model_;
  std::optional<std::filesystem::path> gltf_;
  std::uint64_t maxBinBytes_ = 0;
  std::vector<Bin> bins_;
};

int addAccessor(tinygltf::Model& model, int view, std::size_t byteOffset, int componentType, int type,
                std::size_t count) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.byteOffset = byteOffset;
  accessor.componentType = componentType;
  accessor.type = type;
  accessor.count = count;
  model.accessors.push_back(std::move(accessor));
  return int(model.accessors.size() - 1);
}

template <typename Vec>
int addVertexAccessor(tinygltf::Model& model, BinaryData& data, const std::vector<Vec>& values, int type) {
  const int view = data.addView(values.data(), values.size() * sizeof(Vec), kArrayBuffer);
  return addAccessor(model, view, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, type, values.size());
}

// Indices as 16-bit when every one fits (65535 itself is reserved by the specification), else
// 32-bit, all in one view; each part gets its own accessor into it.
std::vector<int> addIndexAccessors(tinygltf::Model& model, BinaryData& data, const Mesh& mesh) {
  std::uint32_t largest = 0;
  for (std::uint32_t index : mesh.indices) largest = std::max(largest, index);
  const bool narrow = largest < 65535;
  int view = -1;
  if (narrow) {
    const std::vector<std::uint16_t> shortIndices(mesh.indices.begin(), mesh.indices.end());
    view = data.addView(shortIndices.data(), shortIndices.size() * 2, kElementArrayBuffer);
  } else {
    view = data.addView(mesh.indices.data(), mesh.indices.size() * 4, kElementArrayBuffer);
  }
  std::vector<int> accessors;
  for (const MeshPart& part : mesh.parts) {
    accessors.push_back(part.indexCount == 0 ? -1
                                             : addAccessor(model, view, std::size_t(part.firstIndex) * (narrow ? 2 : 4),
                                                           narrow ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                                                  : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                                           TINYGLTF_TYPE_SCALAR, part.indexCount));
  }
  return accessors;
}

void addMesh(tinygltf::Model& model, BinaryData& data, const Mesh& mesh, std::size_t index) {
  if (mesh.positions.empty())
    throw std::runtime_error("mesh " + std::to_string(index) + " has no vertices, which glTF cannot store");
  tinygltf::Primitive shared;
  const int positions = addVertexAccessor(model, data, mesh.positions, TINYGLTF_TYPE_VEC3);
  Bounds box;  // the specification requires POSITION's min and max
  for (const glm::vec3& p : mesh.positions) box.extend(glm::dvec3(p));
  model.accessors[std::size_t(positions)].minValues = {box.min.x, box.min.y, box.min.z};
  model.accessors[std::size_t(positions)].maxValues = {box.max.x, box.max.y, box.max.z};
  shared.attributes["POSITION"] = positions;
  if (!mesh.normals.empty())
    shared.attributes["NORMAL"] = addVertexAccessor(model, data, mesh.normals, TINYGLTF_TYPE_VEC3);
  if (!mesh.uvs.empty()) shared.attributes["TEXCOORD_0"] = addVertexAccessor(model, data, mesh.uvs, TINYGLTF_TYPE_VEC2);

  tinygltf::Mesh out;
  out.name = mesh.name;
  const std::vector<int> indexAccessors =
      mesh.indices.empty() ? std::vector<int>() : addIndexAccessors(model, data, mesh);
  for (std::size_t p = 0; p < indexAccessors.size(); ++p) {
    if (indexAccessors[p] < 0) continue;  // an empty part has nothing to draw and no valid accessor
    tinygltf::Primitive primitive = shared;
    primitive.indices = indexAccessors[p];
    primitive.material = int(mesh.parts[p].material);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    out.primitives.push_back(std::move(primitive));
  }
  if (out.primitives.empty()) {
    // glTF needs a primitive per mesh: keep the vertices as points, which draw no triangles.
    shared.mode = TINYGLTF_MODE_POINTS;
    out.primitives.push_back(std::move(shared));
  }
  model.meshes.push_back(std::move(out));
}

std::vector<unsigned char> encodePng(const Texture& texture, std::size_t index) {
  // tinygltf's writer encodes with stb_image_write into a data URI; decoding the URI gives the
  // PNG bytes for the binary chunk.
  tinygltf::Image image;
  image.width = int(texture.width);
  image.height = int(texture.height);
  image.component = 4;
  image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.image = texture.rgba8;
  const std::string folder, name = "texture.png";
  std::string uri, mime;
  std::vector<unsigned char> png;
  if (!tinygltf::WriteImageData(&folder, &name, &image, true, &uri, nullptr) ||
      !tinygltf::DecodeDataURI(&png, mime, uri, 0, false) || mime != "image/png")
    throw std::runtime_error("texture " + std::to_string(index) + " could not be encoded as PNG");
  return png;
}

int wrapMode(TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::ClampToEdge: return TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    case TextureWrap::MirroredRepeat: return TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
    case TextureWrap::Repeat: break;
  }
  return TINYGLTF_TEXTURE_WRAP_REPEAT;
}

int filterMode(TextureFilter filter, TextureMipmap mipmap = TextureMipmap::None) {
  const bool nearest = filter == TextureFilter::Nearest;
  switch (mipmap) {
    case TextureMipmap::None: break;
    case TextureMipmap::Nearest:
      return nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST : TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST;
    case TextureMipmap::Linear:
      return nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR : TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  }
  return nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST : TINYGLTF_TEXTURE_FILTER_LINEAR;
}

void addTexture(tinygltf::Model& model, BinaryData& data, const Texture& texture, std::size_t index) {
  const std::vector<unsigned char> png = encodePng(texture, index);
  tinygltf::Image image;
  image.name = texture.name;
  image.mimeType = "image/png";
  image.bufferView = data.addView(png.data(), png.size(), 0);
  model.images.push_back(std::move(image));

  tinygltf::Sampler sampler;
  sampler.magFilter = filterMode(texture.magFilter);
  sampler.minFilter = filterMode(texture.minFilter, texture.mipmap);
  sampler.wrapS = wrapMode(texture.wrapS);
  sampler.wrapT = wrapMode(texture.wrapT);
  model.samplers.push_back(std::move(sampler));

  tinygltf::Texture out;
  out.name = texture.name;
  out.source = int(model.images.size() - 1);
  out.sampler = int(model.samplers.size() - 1);
  model.textures.push_back(std::move(out));
}

void addMaterial(tinygltf::Model& model, const Material& material) {
  tinygltf::Material out;
  out.name = material.name;
  const glm::vec4& c = material.baseColorFactor;
  out.pbrMetallicRoughness.baseColorFactor = {c.r, c.g, c.b, c.a};
  out.pbrMetallicRoughness.baseColorTexture.index = material.baseColorTexture;
  // pbs shades with the base colour alone; a rough dielectric is what other viewers match that with.
  out.pbrMetallicRoughness.metallicFactor = 0.0;
  out.pbrMetallicRoughness.roughnessFactor = 1.0;
  model.materials.push_back(std::move(out));
}

void addNode(tinygltf::Model& model, const Node& node) {
  tinygltf::Node out;
  out.name = node.name;
  out.mesh = node.mesh;
  out.children.assign(node.children.begin(), node.children.end());
  if (node.local != glm::dmat4(1.0)) {
    out.matrix.resize(16);
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 4; ++row) out.matrix[std::size_t(column * 4 + row)] = node.local[column][row];
  }
  model.nodes.push_back(std::move(out));
}

// The model of `scene`, its views' bytes in `data`, each mesh read by `meshAt` as it is written.
void buildModel(const Scene& scene, const MeshReader& meshAt, BinaryData& data, tinygltf::Model& model) {
  model.asset.version = "2.0";
  model.asset.generator = "pbs";
  for (std::size_t t = 0; t < scene.textures.size(); ++t) addTexture(model, data, scene.textures[t], t);
  for (const Material& material : scene.materials) addMaterial(model, material);
  for (std::uint32_t m = 0; m < scene.meshes.size(); ++m) addMesh(model, data, *meshAt(m), m);
  for (const Node& node : scene.nodes) addNode(model, node);
  tinygltf::Scene root;
  root.nodes.assign(scene.roots.begin(), scene.roots.end());
  model.scenes.push_back(std::move(root));
  model.defaultScene = 0;
}

// Runs `write(temporary)` and renames the temporary over `file`; on any error removes it and throws
// std::runtime_error naming `file`.
template <class Write>
void writeWhole(const std::filesystem::path& file, Write write) {
  const std::filesystem::path temporary = temporaryBeside(file);
  try {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(std::string("cannot create a file there: ") + std::strerror(errno));
    write(out);
    out.close();  // reports a failed final flush, e.g. a full disk
    if (!out) throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
    // rename replaces an existing file in one step: readers see the old file or the new one.
    std::filesystem::rename(temporary, file);
  } catch (const std::exception& error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(file.string() + ": cannot write glTF: " + error.what());
  }
}

}  // namespace

void writeGlb(const Scene& scene, const std::filesystem::path& file) {
  validateScene(scene, file.string());
  writeWhole(file, [&](std::ofstream& out) {
    tinygltf::Model model;
    BinaryData data(model);
    buildModel(scene, loadedMeshes(scene), data, model);
    // A GLB chunk length is 32-bit; a buffer of no bytes is not allowed.
    if (model.buffers[0].data.size() > std::numeric_limits<std::uint32_t>::max() - 1024)
      throw std::runtime_error("the binary data exceeds the 4 GiB a .glb can hold");
    if (model.buffers[0].data.empty()) model.buffers.clear();
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, out, false, true)) throw std::runtime_error("write failed");
  });
}

std::vector<std::filesystem::path> writeGltf(const Scene& scene, const MeshReader& meshAt,
                                             const std::filesystem::path& file, std::uint64_t maxBinBytes) {
  validateScene(scene, file.string());
  tinygltf::Model model;
  BinaryData data(model, file, maxBinBytes);
  try {
    buildModel(scene, meshAt, data, model);
  } catch (const std::exception& error) {
    throw std::runtime_error(file.string() + ": cannot write glTF: " + error.what());
  }
  std::vector<std::filesystem::path> files = {file};
  writeWhole(file, [&](std::ofstream& out) {
    // tinygltf writes a buffer's bytes where its JSON goes (a data: uri); the buffers here are files
    // already written, so the JSON is written without them and they are named after.
    std::stringstream withoutBuffers;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, withoutBuffers, false, false)) throw std::runtime_error("write failed");
    nlohmann::json json = nlohmann::json::parse(withoutBuffers.str());
    if (nlohmann::json buffers = data.buffers(); !buffers.empty()) json["buffers"] = std::move(buffers);
    out << json.dump();
    const std::vector<std::filesystem::path> bins = data.commit();  // first: a .gltf never names a missing one
    files.insert(files.end(), bins.begin(), bins.end());
  });
  return files;
}

}  // namespace pbs
