// A glTF's JSON to a tinygltf::Model with simdjson's DOM: one parse, then one pass over the
// properties the importer reads, each checked for its JSON type where it is read, so that an error
// names its element and property. (tinygltf's loader, on nlohmann's JSON, made the whole import of a
// 21 MB city 2.5–3× as slow, and its messages seldom said which element failed.)
#include "gltf_json.hpp"

#include "gltf_messages.hpp"
#include "pbs/scene/input_error.hpp"

#include <simdjson.h>

#include <charconv>
#include <climits>
#include <optional>

namespace pbs::gltf {
namespace {

namespace dom = simdjson::dom;

constexpr std::size_t kMaxJsonDepth = 256;                      // glTF itself needs about 8
constexpr std::int64_t kMaxIndex = INT_MAX;                     // tinygltf keeps references as int
constexpr std::int64_t kMaxSize = (std::int64_t{1} << 53) - 1;  // largest integer every JSON reader keeps exactly

std::string describe(dom::element value) {
  switch (value.type()) {
    case dom::element_type::INT64: return std::to_string(std::int64_t(value));
    case dom::element_type::UINT64: return std::to_string(std::uint64_t(value));
    case dom::element_type::DOUBLE: {
      char text[32];
      const auto end = std::to_chars(text, text + sizeof text, double(value)).ptr;
      return std::string(text, end);
    }
    case dom::element_type::STRING: return "a string";
    case dom::element_type::ARRAY: return "an array";
    case dom::element_type::OBJECT: return "an object";
    case dom::element_type::BOOL: return bool(value) ? "true" : "false";
    default: return "null";
  }
}

// The properties of one JSON object, read by key with their types checked; errors name `element`.
class Fields {
 public:
  Fields(dom::element value, std::string element, std::string_view file) : element_(std::move(element)), file_(file) {
    if (value.get(object_) != simdjson::SUCCESS) fail("is " + describe(value) + ", not a JSON object");
  }

  [[noreturn]] void fail(const std::string& message) const { throw InputError(file_, element_, message); }

  std::optional<dom::element> find(const char* key) const {
    dom::element value;
    if (object_[key].get(value) != simdjson::SUCCESS) return std::nullopt;
    return value;
  }

  std::int64_t integer(const char* key, std::int64_t absent, std::int64_t minimum, std::int64_t maximum) const {
    const std::optional<dom::element> value = find(key);
    return value ? integerValue(*value, key, minimum, maximum) : absent;
  }
  std::int64_t requiredInteger(const char* key, std::int64_t minimum, std::int64_t maximum) const {
    const std::optional<dom::element> value = find(key);
    if (!value) fail(std::string("has no ") + key);
    return integerValue(*value, key, minimum, maximum);
  }
  // An index of another element: -1 when absent.
  int reference(const char* key) const { return static_cast<int>(integer(key, -1, 0, kMaxIndex)); }

  std::string string(const char* key) const {
    const std::optional<dom::element> value = find(key);
    if (!value) return {};
    std::string_view text;
    if (value->get(text) != simdjson::SUCCESS) fail(std::string(key) + " is " + describe(*value) + ", not a string");
    return std::string(text);
  }

  bool boolean(const char* key) const {
    const std::optional<dom::element> value = find(key);
    if (!value) return false;
    bool flag = false;
    if (value->get(flag) != simdjson::SUCCESS) {
      fail(std::string(key) + " is " + describe(*value) + ", not true or false");
    }
    return flag;
  }

  // An array of numbers, empty when absent; its length is the reader's to check.
  std::vector<double> numbers(const char* key) const {
    std::vector<double> result;
    forEachItem(key, [&](dom::element item) {
      double number = 0.0;
      if (item.get(number) != simdjson::SUCCESS) fail(std::string(key) + " holds " + describe(item) + ", not a number");
      result.push_back(number);
    });
    return result;
  }

  std::vector<int> references(const char* key) const {
    std::vector<int> result;
    forEachItem(key,
                [&](dom::element item) { result.push_back(static_cast<int>(integerValue(item, key, 0, kMaxIndex))); });
    return result;
  }

  // Calls visit(item) for each element of an array property; for none when it is absent.
  template <typename F>
  void forEachItem(const char* key, F&& visit) const {
    const std::optional<dom::element> value = find(key);
    if (!value) return;
    dom::array items;
    if (value->get(items) != simdjson::SUCCESS) fail(std::string(key) + " is " + describe(*value) + ", not an array");
    for (const dom::element item : items) visit(item);
  }

  template <typename F>
  void forEachMember(F&& visit) const {
    for (const dom::key_value_pair member : object_) visit(member.key, member.value);
  }

  // A nested object, named "<element> <key>" in errors; nullopt when absent.
  std::optional<Fields> object(const char* key) const {
    const std::optional<dom::element> value = find(key);
    if (!value) return std::nullopt;
    if (!value->is_object()) fail(std::string(key) + " is " + describe(*value) + ", not a JSON object");
    return Fields(*value, element_ + ' ' + key, file_);
  }

 private:
  std::int64_t integerValue(dom::element value, const char* key, std::int64_t minimum, std::int64_t maximum) const {
    std::int64_t number = 0;
    if (value.get(number) != simdjson::SUCCESS || number < minimum || number > maximum) {
      fail(std::string(key) + " is " + describe(value) + ", not an integer from " + std::to_string(minimum) + " to " +
           std::to_string(maximum));
    }
    return number;
  }

  dom::object object_;
  std::string element_;
  std::string_view file_;
};

// Calls read(fields, index) for each element of the top-level array `key`, naming them "<kind> <index>".
template <typename Read>
void forEachElement(const Fields& document, const char* key, const char* kind, std::string_view file, Read&& read) {
  int index = 0;
  document.forEachItem(key, [&](dom::element item) {
    read(Fields(item, elementName(kind, index), file), index);
    ++index;
  });
}

int accessorType(const Fields& accessor) {
  const std::string type = accessor.string("type");
  static constexpr std::pair<std::string_view, int> kTypes[] = {
      {"SCALAR", TINYGLTF_TYPE_SCALAR}, {"VEC2", TINYGLTF_TYPE_VEC2}, {"VEC3", TINYGLTF_TYPE_VEC3},
      {"VEC4", TINYGLTF_TYPE_VEC4},     {"MAT2", TINYGLTF_TYPE_MAT2}, {"MAT3", TINYGLTF_TYPE_MAT3},
      {"MAT4", TINYGLTF_TYPE_MAT4}};
  for (const auto& [name, value] : kTypes)
    if (type == name) return value;
  if (type.empty()) accessor.fail("has no type");
  accessor.fail("type '" + type + "' is not a glTF accessor type");
}

tinygltf::Accessor readAccessor(const Fields& fields) {
  tinygltf::Accessor accessor;
  accessor.name = fields.string("name");
  accessor.bufferView = fields.reference("bufferView");
  accessor.byteOffset = static_cast<std::size_t>(fields.integer("byteOffset", 0, 0, kMaxSize));
  accessor.componentType = static_cast<int>(fields.requiredInteger("componentType", 0, kMaxIndex));
  accessor.normalized = fields.boolean("normalized");
  accessor.count = static_cast<std::size_t>(fields.requiredInteger("count", 1, kMaxSize));
  accessor.type = accessorType(fields);
  if (const std::optional<Fields> sparse = fields.object("sparse")) {
    accessor.sparse.isSparse = true;
    accessor.sparse.count = static_cast<int>(sparse->requiredInteger("count", 1, kMaxIndex));
    const std::optional<Fields> indices = sparse->object("indices");
    const std::optional<Fields> values = sparse->object("values");
    if (!indices || !values) sparse->fail(indices ? "has no values" : "has no indices");
    accessor.sparse.indices.bufferView = static_cast<int>(indices->requiredInteger("bufferView", 0, kMaxIndex));
    accessor.sparse.indices.byteOffset = static_cast<int>(indices->integer("byteOffset", 0, 0, kMaxIndex));
    accessor.sparse.indices.componentType = static_cast<int>(indices->requiredInteger("componentType", 0, kMaxIndex));
    accessor.sparse.values.bufferView = static_cast<int>(values->requiredInteger("bufferView", 0, kMaxIndex));
    accessor.sparse.values.byteOffset = static_cast<int>(values->integer("byteOffset", 0, 0, kMaxIndex));
  }
  return accessor;
}

tinygltf::BufferView readBufferView(const Fields& fields) {
  tinygltf::BufferView view;
  view.name = fields.string("name");
  view.buffer = static_cast<int>(fields.requiredInteger("buffer", 0, kMaxIndex));
  view.byteOffset = static_cast<std::size_t>(fields.integer("byteOffset", 0, 0, kMaxSize));
  view.byteLength = static_cast<std::size_t>(fields.requiredInteger("byteLength", 1, kMaxSize));
  view.byteStride = static_cast<std::size_t>(fields.integer("byteStride", 0, 4, 252));
  return view;
}

tinygltf::Primitive readPrimitive(const Fields& fields) {
  tinygltf::Primitive primitive;
  const std::optional<Fields> attributes = fields.object("attributes");
  if (!attributes) fields.fail("has no attributes");
  // Every attribute is kept by name; the mesh reader picks the ones it draws.
  attributes->forEachMember([&](std::string_view name, dom::element value) {
    std::int64_t accessor = 0;
    if (value.get(accessor) != simdjson::SUCCESS || accessor < 0 || accessor > kMaxIndex) {
      attributes->fail(std::string(name) + " is " + describe(value) + ", not an accessor index");
    }
    primitive.attributes.emplace(std::string(name), static_cast<int>(accessor));
  });
  primitive.indices = fields.reference("indices");
  primitive.material = fields.reference("material");
  primitive.mode = static_cast<int>(fields.integer("mode", TINYGLTF_MODE_TRIANGLES, 0, kMaxIndex));
  return primitive;
}

tinygltf::Mesh readMesh(const Fields& fields, int index, std::string_view file) {
  tinygltf::Mesh mesh;
  mesh.name = fields.string("name");
  fields.forEachItem("primitives", [&](dom::element item) {
    mesh.primitives.push_back(readPrimitive(Fields(item, primitiveName(index, mesh.primitives.size()), file)));
  });
  return mesh;
}

tinygltf::Node readNode(const Fields& fields) {
  tinygltf::Node node;
  node.name = fields.string("name");
  node.mesh = fields.reference("mesh");
  node.children = fields.references("children");
  node.matrix = fields.numbers("matrix");
  node.translation = fields.numbers("translation");
  node.rotation = fields.numbers("rotation");
  node.scale = fields.numbers("scale");
  return node;
}

tinygltf::Material readMaterial(const Fields& fields) {
  tinygltf::Material material;
  material.name = fields.string("name");
  if (const std::optional<Fields> pbr = fields.object("pbrMetallicRoughness")) {
    if (pbr->find("baseColorFactor")) material.pbrMetallicRoughness.baseColorFactor = pbr->numbers("baseColorFactor");
    if (const std::optional<Fields> texture = pbr->object("baseColorTexture")) {
      tinygltf::TextureInfo& info = material.pbrMetallicRoughness.baseColorTexture;
      info.index = static_cast<int>(texture->requiredInteger("index", 0, kMaxIndex));
      info.texCoord = static_cast<int>(texture->integer("texCoord", 0, 0, kMaxIndex));
    }
  }
  return material;
}

tinygltf::Image readImage(const Fields& fields) {
  tinygltf::Image image;
  image.name = fields.string("name");
  image.uri = fields.string("uri");
  image.mimeType = fields.string("mimeType");
  image.bufferView = fields.reference("bufferView");
  return image;
}

tinygltf::Texture readTexture(const Fields& fields) {
  tinygltf::Texture texture;
  texture.name = fields.string("name");
  texture.source = fields.reference("source");
  texture.sampler = fields.reference("sampler");
  return texture;
}

tinygltf::Sampler readSampler(const Fields& fields) {
  tinygltf::Sampler sampler;
  sampler.name = fields.string("name");
  sampler.wrapS = static_cast<int>(fields.integer("wrapS", TINYGLTF_TEXTURE_WRAP_REPEAT, INT_MIN, INT_MAX));
  sampler.wrapT = static_cast<int>(fields.integer("wrapT", TINYGLTF_TEXTURE_WRAP_REPEAT, INT_MIN, INT_MAX));
  sampler.magFilter = static_cast<int>(fields.integer("magFilter", -1, INT_MIN, INT_MAX));
  sampler.minFilter = static_cast<int>(fields.integer("minFilter", -1, INT_MIN, INT_MAX));
  return sampler;
}

void checkAsset(const Fields& document) {
  const std::optional<Fields> asset = document.object("asset");
  if (!asset) document.fail("has no asset (every glTF names its version there)");
  const std::string version = asset->string("version");
  if (version.empty()) asset->fail("has no version");
  if (!version.starts_with("2.")) asset->fail("version " + version + " is not supported (only 2.x)");
}

dom::element parseJson(dom::parser& parser, std::span<const std::uint8_t> text, std::size_t readableAfter,
                       std::string_view file) {
  dom::element root;
  const bool copy = readableAfter < simdjson::SIMDJSON_PADDING;
  const simdjson::error_code error = parser.allocate(text.size(), kMaxJsonDepth) != simdjson::SUCCESS
                                         ? simdjson::MEMALLOC
                                         : parser.parse(text.data(), text.size(), copy).get(root);
  if (error == simdjson::DEPTH_ERROR) {
    throw InputError(file, "JSON", "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  }
  if (error != simdjson::SUCCESS) {
    throw InputError(file, "JSON", std::string("not valid: ") + simdjson::error_message(error));
  }
  return root;
}

}  // namespace

GltfJson readGltfJson(std::span<const std::uint8_t> text, std::size_t readableAfter, std::string_view file) {
  dom::parser parser;
  const Fields document(parseJson(parser, text, readableAfter, file), "", file);
  checkAsset(document);

  GltfJson result;
  tinygltf::Model& model = result.model;
  forEachElement(document, "buffers", "buffer", file, [&](const Fields& fields, int) {
    tinygltf::Buffer buffer;
    buffer.name = fields.string("name");
    buffer.uri = fields.string("uri");
    model.buffers.push_back(std::move(buffer));
    result.bufferLengths.push_back(static_cast<std::size_t>(fields.requiredInteger("byteLength", 1, kMaxSize)));
  });
  forEachElement(document, "bufferViews", "bufferView", file,
                 [&](const Fields& fields, int) { model.bufferViews.push_back(readBufferView(fields)); });
  forEachElement(document, "accessors", "accessor", file,
                 [&](const Fields& fields, int) { model.accessors.push_back(readAccessor(fields)); });
  forEachElement(document, "meshes", "mesh", file,
                 [&](const Fields& fields, int index) { model.meshes.push_back(readMesh(fields, index, file)); });
  forEachElement(document, "nodes", "node", file,
                 [&](const Fields& fields, int) { model.nodes.push_back(readNode(fields)); });
  forEachElement(document, "scenes", "scene", file, [&](const Fields& fields, int) {
    tinygltf::Scene scene;
    scene.name = fields.string("name");
    scene.nodes = fields.references("nodes");
    model.scenes.push_back(std::move(scene));
  });
  model.defaultScene = document.reference("scene");
  forEachElement(document, "materials", "material", file,
                 [&](const Fields& fields, int) { model.materials.push_back(readMaterial(fields)); });
  forEachElement(document, "images", "image", file,
                 [&](const Fields& fields, int) { model.images.push_back(readImage(fields)); });
  forEachElement(document, "textures", "texture", file,
                 [&](const Fields& fields, int) { model.textures.push_back(readTexture(fields)); });
  forEachElement(document, "samplers", "sampler", file,
                 [&](const Fields& fields, int) { model.samplers.push_back(readSampler(fields)); });
  document.forEachItem("extensionsRequired", [&](dom::element item) {
    std::string_view name;
    if (item.get(name) != simdjson::SUCCESS) {
      throw InputError(file, "extensionsRequired", "holds " + describe(item) + ", not an extension name");
    }
    model.extensionsRequired.emplace_back(name);
  });
  return result;
}

}  // namespace pbs::gltf
