// Private to the glTF importer: turns tinygltf's error text into what an InputError needs.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pbs::gltf {

// tinygltf's and stb's messages span lines, and may quote a whole data: URI; InputError's are one
// short line.
std::string oneLine(std::string_view text);

// The non-empty lines of `text`, each through oneLine.
std::vector<std::string> splitLines(std::string_view text);

// The element ("accessor 3", "mesh 0 primitive 1", "JSON") that tinygltf's `message` is about, from
// the message, the file's JSON text and the model tinygltf left; empty when it cannot be told.
// `stoppedEarly`: the load failed, rather than succeeding with error text.
std::string failingElement(const std::string& message, std::span<const std::uint8_t> jsonText,
                           const tinygltf::Model& partial, bool stoppedEarly);

}  // namespace pbs::gltf
