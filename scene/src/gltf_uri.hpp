// Private to the glTF importer: the bytes a buffer's or image's uri names.
#pragma once

#include "mapped_file.hpp"

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace pbs::gltf {

// The bytes a uri names: a base64 data: URI ("data:<type>;base64,<data>") decoded, or a regular file
// under the glTF's folder mapped (MappedFile). Moving it keeps bytes() where they are.
struct UriBytes {
  std::variant<std::vector<std::uint8_t>, MappedFile> storage;
  std::span<const std::uint8_t> bytes() const;
};

// Reads `uri` relative to `baseDir`, percent-escapes decoded (RFC 3986). Throws std::runtime_error
// with the reason ("cannot read 'x.bin': no such file") on failure.
UriBytes readUri(const std::string& uri, const std::filesystem::path& baseDir);

}  // namespace pbs::gltf
