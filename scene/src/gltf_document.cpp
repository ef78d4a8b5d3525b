// glTF/GLB bytes to a Document: our checks of the GLB layout, the JSON read by gltf_json.cpp, then
// the buffers its uris name.
#include "gltf_document.hpp"

#include "gltf_json.hpp"
#include "gltf_messages.hpp"
#include "pbs/scene/input_error.hpp"

#include <cctype>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace pbs::gltf {
namespace {

constexpr std::uint32_t kGlbHeaderBytes = 20;   // magic, version, length, then the JSON chunk's length and type
constexpr std::uint32_t kChunkHeaderBytes = 8;  // length, type
constexpr std::uint32_t kChunkTypeJson = 0x4E4F534A;
constexpr std::uint32_t kChunkTypeBin = 0x004E4942;

std::uint32_t readU32(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return std::uint32_t{bytes[offset]} | std::uint32_t{bytes[offset + 1]} << 8 | std::uint32_t{bytes[offset + 2]} << 16 |
         std::uint32_t{bytes[offset + 3]} << 24;
}

bool hasGlbMagic(std::span<const std::uint8_t> bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

// The GLB layout: header, JSON chunk, optional BIN chunk. Returns the BIN chunk's bytes (empty when
// there is none).
std::span<const std::uint8_t> checkGlbLayout(std::span<const std::uint8_t> bytes, std::string_view file) {
  const char* header = "GLB header";
  if (bytes.size() < kGlbHeaderBytes) {
    throw InputError(file, header, "file is " + std::to_string(bytes.size()) + " bytes, too short for a GLB header");
  }
  const std::uint32_t version = readU32(bytes, 4);
  const std::uint32_t length = readU32(bytes, 8);
  const std::uint32_t jsonLength = readU32(bytes, 12);
  if (version != 2) throw InputError(file, header, "version " + std::to_string(version) + " is not supported (only 2)");
  if (length > bytes.size()) {
    throw InputError(
        file, header,
        "says " + std::to_string(length) + " bytes but the file has " + std::to_string(bytes.size()) + " (truncated?)");
  }
  if (readU32(bytes, 16) != kChunkTypeJson) throw InputError(file, header, "the first chunk is not JSON");
  if (length < kGlbHeaderBytes || jsonLength == 0 || jsonLength > length - kGlbHeaderBytes) {
    throw InputError(file, "GLB JSON chunk",
                     std::to_string(jsonLength) + " bytes do not fit in the file's " + std::to_string(length));
  }
  const std::uint32_t jsonEnd = kGlbHeaderBytes + jsonLength;
  if (jsonEnd == length) return {};  // no BIN chunk
  const char* bin = "GLB BIN chunk";
  if (length - jsonEnd < kChunkHeaderBytes) throw InputError(file, bin, "its header runs past the end of the data");
  const std::uint32_t binLength = readU32(bytes, jsonEnd);
  if (readU32(bytes, jsonEnd + 4) != kChunkTypeBin) throw InputError(file, bin, "the second chunk is not BIN");
  if (binLength > length - jsonEnd - kChunkHeaderBytes) {
    throw InputError(file, bin,
                     std::to_string(binLength) + " bytes run past the end of the data (" +
                         std::to_string(length - jsonEnd - kChunkHeaderBytes) + " left)");
  }
  return bytes.subspan(jsonEnd + kChunkHeaderBytes, binLength);
}

// The JSON text (a .gltf, or a GLB's JSON chunk) must open an object, else random bytes would get a
// JSON parser's message.
void checkJsonStart(std::span<const std::uint8_t> text, bool glb, std::string_view file) {
  std::size_t i = 0;
  if (text.size() >= 3 && text[0] == 0xEF && text[1] == 0xBB && text[2] == 0xBF) i = 3;  // UTF-8 byte order mark
  while (i < text.size() && std::isspace(text[i])) ++i;
  if (i < text.size() && text[i] == '{') return;
  if (glb) throw InputError(file, "GLB JSON chunk", "does not start with '{'");
  throw InputError(file, "", "not glTF: neither GLB (no \"glTF\" magic) nor JSON (does not start with '{')");
}

// Each buffer's bytes: a GLB's first buffer without a uri is its BIN chunk (which may carry up to 3
// bytes of padding more than the byteLength).
void loadBuffers(Document& document, const std::vector<std::size_t>& bufferLengths,
                 std::span<const std::uint8_t> binChunk, bool glb, std::string_view file,
                 const std::filesystem::path& baseDir) {
  for (std::size_t b = 0; b < document.buffers.size(); ++b) {
    const std::string& uri = document.buffers[b].uri;
    const std::string element = elementName("buffer", static_cast<std::int64_t>(b));
    const std::size_t byteLength = bufferLengths[b];
    if (uri.empty()) {
      if (!glb || b != 0) throw InputError(file, element, "has no uri (only a GLB's first buffer may omit it)");
      if (binChunk.size() < byteLength) {
        throw InputError(file, element,
                         "byteLength " + std::to_string(byteLength) + " is more than the GLB BIN chunk's " +
                             std::to_string(binChunk.size()) + " bytes");
      }
      document.bufferBytes.push_back(binChunk.first(byteLength));
      continue;
    }
    std::span<const std::uint8_t> bytes;
    try {
      bytes = document.loadedBuffers.emplace_back(readUri(uri, baseDir)).bytes();
    } catch (const std::runtime_error& error) {
      throw InputError(file, element, error.what());
    }
    if (bytes.size() < byteLength) {
      const std::string source = uri.starts_with("data:") ? "its data: URI" : "'" + uri + "'";
      throw InputError(file, element,
                       source + " holds " + std::to_string(bytes.size()) + " bytes, fewer than its byteLength " +
                           std::to_string(byteLength));
    }
    document.bufferBytes.push_back(bytes.first(byteLength));
  }
}

// Extensions a file may require that we implement, or whose absence changes only what we ignore anyway.
void checkRequiredExtensions(const tinygltf::Model& model, std::string_view file, std::vector<std::string>& warnings) {
  for (const std::string& extension : model.extensionsRequired) {
    if (extension == "KHR_mesh_quantization") continue;  // integer attributes: gltf_accessor.cpp reads them
    if (extension == "KHR_texture_transform" || extension.starts_with("KHR_materials_")) {
      warnings.push_back("ignoring required extension " + extension + ": only base colour and TEXCOORD_0 are imported");
      continue;
    }
    throw InputError(file, "extensionsRequired", "extension " + extension + " is not supported");
  }
}

}  // namespace

Document parseDocument(std::span<const std::uint8_t> bytes, const std::string& file,
                       const std::filesystem::path& baseDir, std::vector<std::string>& warnings) {
  if (bytes.empty()) throw InputError(file, "", "file is empty");
  if (bytes.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError(file, "", "file is larger than 4 GiB, more than glTF can address");
  }
  const bool glb = hasGlbMagic(bytes);
  const std::span<const std::uint8_t> binChunk = glb ? checkGlbLayout(bytes, file) : std::span<const std::uint8_t>{};
  const std::span<const std::uint8_t> jsonText = glb ? bytes.subspan(kGlbHeaderBytes, readU32(bytes, 12)) : bytes;
  checkJsonStart(jsonText, glb, file);
  if (glb && jsonText.size() % 4 != 0) warnings.push_back("GLB JSON chunk is not padded to 4 bytes");
  const std::size_t jsonEnd = glb ? kGlbHeaderBytes + jsonText.size() : bytes.size();
  GltfJson json = readGltfJson(jsonText, bytes.size() - jsonEnd, file);
  Document document;
  static_cast<tinygltf::Model&>(document) = std::move(json.model);
  document.baseDir = baseDir;
  loadBuffers(document, json.bufferLengths, binChunk, glb, file, baseDir);
  checkRequiredExtensions(document, file, warnings);
  return document;
}

}  // namespace pbs::gltf
