// Test helper shared by the glTF import suites: builds small glTF files by hand (JSON through
// nlohmann::json, one binary buffer) and writes them as .gltf with a data: URI or an external .bin,
// or as .glb; plus tiny PNGs with known pixels.
#pragma once

#include "pbs/scene/gltf_import.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace pbs::test {

// glTF numbers used throughout the tests.
enum GltfConstant : int {
  kByte = 5120,
  kUnsignedByte = 5121,
  kShort = 5122,
  kUnsignedShort = 5123,
  kUnsignedInt = 5125,
  kFloat = 5126,
  kModePoints = 0,
  kModeLines = 1,
  kModeTriangles = 4,
  kModeStrip = 5,
  kModeFan = 6,
};

inline std::string base64(std::string_view bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t block = 0;
    for (std::size_t k = 0; k < 3; ++k) block = block << 8 | (k < n ? static_cast<std::uint8_t>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(block >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

inline std::string fromBase64(std::string_view text) {
  std::string out;
  std::uint32_t block = 0;
  int bits = 0;
  for (const char c : text) {
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* found = c ? std::strchr(alphabet, c) : nullptr;
    if (!found) continue;  // padding
    block = block << 6 | static_cast<std::uint32_t>(found - alphabet);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((block >> bits) & 0xFF);
    }
  }
  return out;
}

template <typename T>
std::string bytesOf(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// 2×2 RGBA8: red, green / blue, white at alpha 128.
inline const char* const kPngRgba2x2 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAE0lEQVR4nGP4z8DwHwyBNAg0AABJSQl4KKDbdwAAAABJRU5ErkJggg==";
// 2×1 grey8: 0, 200.
inline const char* const kPngGrey2x1 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAAAAADRSSBWAAAAC0lEQVR4nGNgOAEAAMsAyWnIw2wAAAAASUVORK5CYII=";
// 1×1 RGB16: 65535, 32768, 0.
inline const char* const kPngRgb16 =
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABEAIAAADA54+dAAAAD0lEQVR4nGP4/7+BgYEBAAz8An+jd5TMAAAAAElFTkSuQmCC";

inline std::vector<std::uint8_t> asBytes(std::string_view text) { return {text.begin(), text.end()}; }

// A glTF document under construction: `json` plus the bytes of buffer 0.
struct GltfBuilder {
  nlohmann::json json = {{"asset", {{"version", "2.0"}}}};
  std::string bin;

  // Appends `bytes` (4-byte aligned) as a new bufferView; returns its index.
  int addView(const std::string& bytes, int byteStride = 0) {
    bin.resize((bin.size() + 3) / 4 * 4, '\0');
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}};
    if (byteStride) view["byteStride"] = byteStride;
    bin += bytes;
    return append("bufferViews", view);
  }

  // A tightly packed accessor over a new bufferView; `values` holds count × components numbers.
  template <typename T>
  int addAccessor(const std::vector<T>& values, int componentType, const std::string& type, bool normalized = false) {
    const int view = addView(bytesOf(values));
    nlohmann::json accessor = {{"bufferView", view},
                               {"componentType", componentType},
                               {"count", values.size() / components(type)},
                               {"type", type}};
    if (normalized) accessor["normalized"] = true;
    return append("accessors", accessor);
  }

  int addMesh(const nlohmann::json& primitives) { return append("meshes", {{"primitives", primitives}}); }
  int addNode(const nlohmann::json& node) { return append("nodes", node); }
  int addMaterial(const nlohmann::json& material) { return append("materials", material); }

  // Scene 0 with `roots`, the default scene.
  void setScene(const std::vector<int>& roots) {
    json["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
    json["scene"] = 0;
  }

  int append(const char* array, const nlohmann::json& element) {
    json[array].push_back(element);
    return static_cast<int>(json[array].size()) - 1;
  }

  // JSON text; buffer 0 (when there are bytes) is a data: URI, or `binUri` when given.
  std::string gltf(const std::string& binUri = "") const {
    nlohmann::json doc = json;
    if (!bin.empty()) {
      doc["buffers"] = nlohmann::json::array(
          {{{"byteLength", bin.size()},
            {"uri", binUri.empty() ? "data:application/octet-stream;base64," + base64(bin) : binUri}}});
    }
    return doc.dump();
  }

  std::string glb() const {
    nlohmann::json doc = json;
    std::string binChunk = bin;
    binChunk.resize((binChunk.size() + 3) / 4 * 4, '\0');
    if (!bin.empty()) doc["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
    std::string text = doc.dump();
    text.resize((text.size() + 3) / 4 * 4, ' ');
    const auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    std::string out = "glTF" + u32(2) + u32(0) + u32(static_cast<std::uint32_t>(text.size())) + u32(0x4E4F534A) + text;
    if (!bin.empty()) out += u32(static_cast<std::uint32_t>(binChunk.size())) + u32(0x004E4942) + binChunk;
    const auto length = static_cast<std::uint32_t>(out.size());
    std::memcpy(out.data() + 8, &length, 4);
    return out;
  }

  static std::size_t components(const std::string& type) {
    return type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : 4;
  }
};

// One triangle (0,0,0) (1,0,0) (0,1,0) with UNSIGNED_SHORT indices: accessor 0 positions, accessor 1
// indices, mesh 0, node 0, scene 0.
inline GltfBuilder triangleFile() {
  GltfBuilder b;
  const int positions = b.addAccessor(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}, kFloat, "VEC3");
  const int indices = b.addAccessor(std::vector<std::uint16_t>{0, 1, 2}, kUnsignedShort, "SCALAR");
  b.addMesh({{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}});
  b.addNode({{"mesh", 0}});
  b.setScene({0});
  return b;
}

inline ImportResult importText(const std::string& text, const std::string& name = "test.gltf",
                               const std::filesystem::path& baseDir = ".") {
  return importGltfFromMemory(asBytes(text), name, baseDir);
}

}  // namespace pbs::test
