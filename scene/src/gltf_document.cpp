// glTF/GLB bytes to a tinygltf::Model: our checks of the GLB layout and the JSON text, then
// tinygltf's loader with our file and image callbacks.
#include "gltf_document.hpp"

#include "gltf_parse_errors.hpp"
#include "pbs/scene/input_error.hpp"

#include <cctype>
#include <cstring>
#include <limits>

namespace pbs::gltf {
namespace {

constexpr std::uint32_t kGlbHeaderBytes = 20;   // magic, version, length, then the JSON chunk's length and type
constexpr std::uint32_t kChunkHeaderBytes = 8;  // length, type
constexpr std::uint32_t kChunkTypeJson = 0x4E4F534A;
constexpr std::uint32_t kChunkTypeBin = 0x004E4942;
constexpr std::size_t kMaxJsonDepth = 256;      // glTF itself needs about 8; see checkJsonText

std::uint32_t readU32(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return std::uint32_t{bytes[offset]} | std::uint32_t{bytes[offset + 1]} << 8 | std::uint32_t{bytes[offset + 2]} << 16 |
         std::uint32_t{bytes[offset + 3]} << 24;
}

bool hasGlbMagic(std::span<const std::uint8_t> bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

// The GLB layout: header, JSON chunk, optional BIN chunk. tinygltf checks it too, but says only
// "Invalid glTF binary." for a truncated download, and it lets a BIN chunk claim up to 8 bytes more
// than the data holds (its bound forgets the chunk header) and then copies them: never pass it one.
void checkGlbLayout(std::span<const std::uint8_t> bytes, std::string_view file) {
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
  if (jsonEnd == length) return;  // no BIN chunk
  const char* bin = "GLB BIN chunk";
  if (length - jsonEnd < kChunkHeaderBytes) throw InputError(file, bin, "its header runs past the end of the data");
  const std::uint32_t binLength = readU32(bytes, jsonEnd);
  if (readU32(bytes, jsonEnd + 4) != kChunkTypeBin) throw InputError(file, bin, "the second chunk is not BIN");
  if (binLength > length - jsonEnd - kChunkHeaderBytes) {
    throw InputError(file, bin,
                     std::to_string(binLength) + " bytes run past the end of the data (" +
                         std::to_string(length - jsonEnd - kChunkHeaderBytes) + " left)");
  }
}

// The JSON text (a .gltf, or a GLB's JSON chunk) must open an object, else random bytes would get a
// JSON parser's message; and must not nest deeper than kMaxJsonDepth: tinygltf converts `extras` and
// `extensions` recursively, so a deeply nested file would overflow the stack.
void checkJsonText(std::span<const std::uint8_t> text, bool glb, std::string_view file) {
  std::size_t i = 0;
  if (text.size() >= 3 && text[0] == 0xEF && text[1] == 0xBB && text[2] == 0xBF) i = 3;  // UTF-8 byte order mark
  while (i < text.size() && std::isspace(text[i])) ++i;
  if (i == text.size() || text[i] != '{') {
    if (glb) throw InputError(file, "GLB JSON chunk", "does not start with '{'");
    throw InputError(file, "", "not glTF: neither GLB (no \"glTF\" magic) nor JSON (does not start with '{')");
  }
  std::size_t depth = 0;
  bool inString = false;
  for (; i < text.size(); ++i) {
    const std::uint8_t c = text[i];
    if (inString) {
      if (c == '\\')
        ++i;  // skips the escaped character, which may be a quote
      else if (c == '"')
        inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '{' || c == '[') {
      if (++depth > kMaxJsonDepth) {
        throw InputError(file, "JSON", "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
      }
    } else if ((c == '}' || c == ']') && depth > 0) {
      --depth;
    }
  }
}

// tinygltf also looks for a relative URI in the working directory, which could quietly load an
// unrelated file, and its fopen() test accepts directories: only regular files under the base.
bool regularFileUnderBase(const std::string& path, void* baseDir) {
  const std::string& base = *static_cast<const std::string*>(baseDir);
  std::error_code ignored;
  return path.compare(0, base.size(), base) == 0 && std::filesystem::is_regular_file(path, ignored);
}

// Keeps a URI image's encoded bytes for gltf_image.cpp. A bufferView image's bytes are left alone:
// tinygltf hands them over without checking the view against its buffer.
bool keepEncodedImage(tinygltf::Image* image, int, std::string*, std::string*, int, int, const unsigned char* bytes,
                      int size, void*) {
  if (image->bufferView == -1) {
    image->image.assign(bytes, bytes + size);
    image->as_is = true;
  }
  return true;
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

tinygltf::Model parseDocument(std::span<const std::uint8_t> bytes, const std::string& file,
                              const std::filesystem::path& baseDir, std::vector<std::string>& warnings) {
  if (bytes.empty()) throw InputError(file, "", "file is empty");
  if (bytes.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw InputError(file, "", "file is larger than 4 GiB, more than glTF can address");
  }
  const bool glb = hasGlbMagic(bytes);
  if (glb) checkGlbLayout(bytes, file);
  const std::span<const std::uint8_t> jsonText = glb ? bytes.subspan(kGlbHeaderBytes, readU32(bytes, 12)) : bytes;
  checkJsonText(jsonText, glb, file);

  std::string base = baseDir.string();
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(
      {&regularFileUnderBase, &tinygltf::ExpandFilePath, &tinygltf::ReadWholeFile, &tinygltf::WriteWholeFile, &base});
  loader.SetImageLoader(&keepEncodedImage, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const auto size = static_cast<unsigned int>(bytes.size());
  const bool loaded = glb ? loader.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(), size, base)
                          : loader.LoadASCIIFromString(&model, &error, &warning,
                                                       reinterpret_cast<const char*>(bytes.data()), size, base);
  // tinygltf reports success after dropping a primitive it could not parse, with the reason in the error
  // text: any error text fails the import. Its one complaint about readable data, an unpadded GLB JSON
  // chunk, is only a warning.
  std::vector<std::string> errors = splitLines(error);
  std::erase_if(errors, [&](const std::string& line) {
    if (!line.starts_with("JSON Chunk end does not aligned")) return false;
    warnings.push_back("GLB JSON chunk is not padded to 4 bytes");
    return true;
  });
  if (!loaded || !errors.empty()) {
    std::string message = oneLine(error.empty() ? warning : error);
    if (message.empty()) message = "tinygltf could not load the file";
    throw InputError(file, failingElement(message, jsonText, model, !loaded), message);
  }
  for (std::string& line : splitLines(warning)) warnings.push_back(std::move(line));
  checkRequiredExtensions(model, file, warnings);
  return model;
}

}  // namespace pbs::gltf
