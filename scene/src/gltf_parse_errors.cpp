// What tinygltf's error text is about: one line of it, and the element at fault, which its messages
// seldom name.
#include "gltf_parse_errors.hpp"

#include "gltf_messages.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>

namespace pbs::gltf {
namespace {

constexpr std::size_t kMaxMessageLength = 300;  // tinygltf quotes whole data: URIs in some messages

// "image[3]" in tinygltf's text becomes "image 3"; empty when there is none.
std::string bracketedElement(const std::string& message) {
  for (std::size_t open = message.find('['); open != std::string::npos; open = message.find('[', open + 1)) {
    std::size_t start = open;
    while (start > 0 && std::isalpha(static_cast<unsigned char>(message[start - 1]))) --start;
    std::size_t end = open + 1;
    while (end < message.size() && std::isdigit(static_cast<unsigned char>(message[end]))) ++end;
    if (start < open && end > open + 1 && end < message.size() && message[end] == ']') {
      return message.substr(start, open - start) + ' ' + message.substr(open + 1, end - open - 1);
    }
  }
  return {};
}

// The material problems tinygltf notes and carries on past: a baseColorFactor that is not 4 numbers,
// a texture reference without an integer index.
std::string malformedMaterial(const nlohmann::json& document) {
  const auto materials = document.find("materials");
  if (materials == document.end() || !materials->is_array()) return {};
  const auto badTextureInfo = [](const nlohmann::json& owner, const char* name) {
    const auto info = owner.find(name);
    return info != owner.end() &&
           !(info->is_object() && info->contains("index") && (*info)["index"].is_number_integer());
  };
  for (std::size_t m = 0; m < materials->size(); ++m) {
    const nlohmann::json& material = (*materials)[m];
    if (!material.is_object()) continue;
    bool bad = badTextureInfo(material, "normalTexture") || badTextureInfo(material, "occlusionTexture") ||
               badTextureInfo(material, "emissiveTexture");
    const auto pbr = material.find("pbrMetallicRoughness");
    if (pbr != material.end() && pbr->is_object()) {
      const auto factor = pbr->find("baseColorFactor");
      bad = bad || (factor != pbr->end() && factor->is_array() && factor->size() != 4) ||
            badTextureInfo(*pbr, "baseColorTexture") || badTextureInfo(*pbr, "metallicRoughnessTexture");
    }
    if (bad) return elementName("material", static_cast<std::int64_t>(m));
  }
  return {};
}

// tinygltf's messages rarely say which element failed. Clues, in order: an "image[3]" in the text;
// its one check made after all meshes are parsed; its few messages about the file as a whole; and
// the partially filled model against the file's own JSON (parsed again, on this error path only).
// tinygltf parses the top-level arrays in the order below, appending each element once parsed, and
// stops at the first it cannot parse: the first array shorter than the file's holds the failure at
// its end. When instead it dropped a primitive and carried on, the mesh that lost one is at fault.
}  // namespace

std::string failingElement(const std::string& message, std::span<const std::uint8_t> jsonText,
                           const tinygltf::Model& partial, bool stoppedEarly) {
  if (std::string bracketed = bracketedElement(message); !bracketed.empty()) return bracketed;
  if (message.find("primitive indices accessor out of bounds") != std::string::npos) {
    for (std::size_t m = 0; m < partial.meshes.size(); ++m) {
      const auto& primitives = partial.meshes[m].primitives;
      for (std::size_t p = 0; p < primitives.size(); ++p) {
        if (primitives[p].indices >= std::ssize(partial.accessors)) return primitiveName(static_cast<int>(m), p);
      }
    }
  }
  const nlohmann::json document = nlohmann::json::parse(jsonText.begin(), jsonText.end(), nullptr, false);
  if (!document.is_object()) return "JSON";  // not parseable (or not an object): the message is the parser's
  std::string lower = message;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower.find("asset") != std::string::npos) return "asset";
  if (lower.find("chunk") != std::string::npos) return "GLB BIN chunk";  // the rest of tinygltf's GLB checks
  const auto fileCount = [&](const char* array) -> std::size_t {
    const auto it = document.find(array);
    return it != document.end() && it->is_array() ? it->size() : 0;
  };
  if (stoppedEarly) {
    struct Parsed {
      const char* array;
      const char* element;
      std::size_t count;
    };
    const Parsed inParseOrder[] = {{"buffers", "buffer", partial.buffers.size()},
                                   {"bufferViews", "bufferView", partial.bufferViews.size()},
                                   {"accessors", "accessor", partial.accessors.size()},
                                   {"meshes", "mesh", partial.meshes.size()},
                                   {"nodes", "node", partial.nodes.size()},
                                   {"scenes", "scene", partial.scenes.size()},
                                   {"materials", "material", partial.materials.size()},
                                   {"images", "image", partial.images.size()},
                                   {"textures", "texture", partial.textures.size()},
                                   {"animations", "animation", partial.animations.size()},
                                   {"skins", "skin", partial.skins.size()},
                                   {"samplers", "sampler", partial.samplers.size()},
                                   {"cameras", "camera", partial.cameras.size()}};
    for (const Parsed& parsed : inParseOrder) {
      if (parsed.count < fileCount(parsed.array))
        return elementName(parsed.element, static_cast<std::int64_t>(parsed.count));
    }
    return {};
  }
  if (!partial.meshes.empty() && fileCount("meshes") == partial.meshes.size()) {
    const nlohmann::json& meshes = document.at("meshes");
    for (std::size_t m = 0; m < partial.meshes.size(); ++m) {
      const auto it = meshes[m].find("primitives");
      if (it != meshes[m].end() && it->is_array() && it->size() > partial.meshes[m].primitives.size()) {
        return elementName("mesh", static_cast<std::int64_t>(m));
      }
    }
  }
  return malformedMaterial(document);
}

std::string oneLine(std::string_view text) {
  std::string line;
  for (const char c : text) {
    if (c == '\n' || c == '\r') {
      if (!line.empty() && !line.ends_with("; ")) line += "; ";
    } else {
      line += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    }
  }
  while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
  if (line.size() > kMaxMessageLength) line = line.substr(0, kMaxMessageLength) + "...";
  return line;
}

std::vector<std::string> splitLines(std::string_view text) {
  std::vector<std::string> result;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    if (std::string line = oneLine(text.substr(start, end - start)); !line.empty()) result.push_back(std::move(line));
    start = end + 1;
  }
  return result;
}

}  // namespace pbs::gltf
