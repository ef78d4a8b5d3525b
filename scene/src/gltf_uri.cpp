// glTF uris: base64 data: URIs and files relative to the glTF (mapped, as the glTF itself is). The
// decoders are written here rather than taken from tinygltf, whose are private to its loader, and are
// short enough not to need another library.
#include "gltf_uri.hpp"

#include <stdexcept>
#include <type_traits>

namespace pbs::gltf {
namespace {

// 0–63 for a base64 digit, -1 otherwise.
int base64Digit(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Decodes base64 text, padded or not; stops at the first '='.
std::vector<std::uint8_t> decodeBase64(std::string_view text) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(text.size() / 4 * 3 + 2);
  std::uint32_t bits = 0;
  int bitCount = 0;
  for (const char c : text) {
    if (c == '=') break;
    const int digit = base64Digit(c);
    if (digit < 0) throw std::runtime_error("its base64 data holds a character that is not base64");
    bits = (bits << 6) | static_cast<std::uint32_t>(digit);
    bitCount += 6;
    if (bitCount >= 8) {
      bitCount -= 8;
      bytes.push_back(static_cast<std::uint8_t>(bits >> bitCount));
    }
  }
  return bytes;
}

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string percentDecoded(const std::string& uri) {
  std::string path;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    const int high = uri[i] == '%' && i + 2 < uri.size() ? hexDigit(uri[i + 1]) : -1;
    const int low = high >= 0 ? hexDigit(uri[i + 2]) : -1;
    if (low < 0) {
      path += uri[i];
    } else {
      path += static_cast<char>(high * 16 + low);
      i += 2;
    }
  }
  return path;
}

MappedFile mapRelativeFile(const std::string& uri, const std::filesystem::path& baseDir) {
  const std::filesystem::path relative(percentDecoded(uri));
  if (relative.is_absolute() || relative.has_root_name() || uri.find("://") != std::string::npos) {
    throw std::runtime_error("cannot read '" + uri + "': only files relative to the glTF are read");
  }
  const std::filesystem::path path = baseDir / relative;
  std::error_code ignored;
  if (!std::filesystem::exists(path, ignored)) throw std::runtime_error("cannot read '" + uri + "': no such file");
  try {
    return MappedFile(path);
  } catch (const std::runtime_error& error) {  // MappedFile's InputError names the whole path
    throw std::runtime_error("cannot read '" + uri + "': " + error.what());
  }
}

}  // namespace

std::span<const std::uint8_t> UriBytes::bytes() const {
  return std::visit(
      [](const auto& held) -> std::span<const std::uint8_t> {
        if constexpr (std::is_same_v<std::decay_t<decltype(held)>, MappedFile>) {
          return held.bytes();
        } else {
          return held;
        }
      },
      storage);
}

UriBytes readUri(const std::string& uri, const std::filesystem::path& baseDir) {
  if (!uri.starts_with("data:")) return {mapRelativeFile(uri, baseDir)};
  const std::size_t comma = uri.find(',');
  if (comma == std::string::npos || !std::string_view(uri).substr(0, comma).ends_with(";base64")) {
    throw std::runtime_error("its data: URI is not base64 (\"data:<type>;base64,...\")");
  }
  return {decodeBase64(std::string_view(uri).substr(comma + 1))};
}

}  // namespace pbs::gltf
