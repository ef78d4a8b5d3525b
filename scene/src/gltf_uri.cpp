// glTF uris: base64 data: URIs and files relative to the glTF. Written here rather than taken from
// tinygltf, whose decoders are private to its loader, and short enough not to need another library.
#include "gltf_uri.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

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

std::vector<std::uint8_t> readRelativeFile(const std::string& uri, const std::filesystem::path& baseDir) {
  const std::filesystem::path relative(percentDecoded(uri));
  if (relative.is_absolute() || relative.has_root_name() || uri.find("://") != std::string::npos) {
    throw std::runtime_error("cannot read '" + uri + "': only files relative to the glTF are read");
  }
  const std::filesystem::path path = baseDir / relative;
  std::error_code ignored;
  if (!std::filesystem::is_regular_file(path, ignored)) {
    throw std::runtime_error("cannot read '" + uri + "': " +
                             (std::filesystem::exists(path, ignored) ? "not a regular file" : "no such file"));
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamsize size = in ? static_cast<std::streamsize>(in.tellg()) : -1;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(std::max<std::streamsize>(size, 0)));
  if (size < 0 || !in.seekg(0) || !in.read(reinterpret_cast<char*>(bytes.data()), size)) {
    throw std::runtime_error("cannot read '" + uri + "': " + (errno ? std::strerror(errno) : "read failed"));
  }
  return bytes;
}

}  // namespace

std::vector<std::uint8_t> readUri(const std::string& uri, const std::filesystem::path& baseDir) {
  if (!uri.starts_with("data:")) return readRelativeFile(uri, baseDir);
  const std::size_t comma = uri.find(',');
  if (comma == std::string::npos || !std::string_view(uri).substr(0, comma).ends_with(";base64")) {
    throw std::runtime_error("its data: URI is not base64 (\"data:<type>;base64,...\")");
  }
  return decodeBase64(std::string_view(uri).substr(comma + 1));
}

}  // namespace pbs::gltf
