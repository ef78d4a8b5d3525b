// Private to the glTF importer: the bytes a buffer's or image's uri names.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pbs::gltf {

// A base64 data: URI ("data:<type>;base64,<data>") decoded, or a relative reference read from a
// regular file under `baseDir`, percent-escapes decoded (RFC 3986). Throws std::runtime_error with
// the reason ("cannot read 'x.bin': No such file or directory") on failure.
std::vector<std::uint8_t> readUri(const std::string& uri, const std::filesystem::path& baseDir);

}  // namespace pbs::gltf
