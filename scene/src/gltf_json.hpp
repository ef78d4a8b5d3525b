// Private to the glTF importer: a glTF's JSON text to a tinygltf::Model, parsed with simdjson.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace pbs::gltf {

// What the JSON says; buffers and images keep their uri but no bytes yet (gltf_document.cpp loads them).
struct GltfJson {
  tinygltf::Model model;
  std::vector<std::size_t> bufferLengths;  // each buffer's byteLength, which tinygltf::Buffer has no field for
};

// Reads the properties the importer uses (and checks their JSON types), naming the element at fault
// in an InputError: "accessor 3: count must be an integer ≥ 1". Everything else (extras, extensions
// other than extensionsRequired, animations, skins, cameras) is skipped unread. Numbers are
// correctly rounded to the nearest double; NaN, Infinity and numbers beyond a double are JSON errors.
// `readableAfter`: how many bytes follow the text in memory (a GLB's BIN chunk); with enough of them the
// parser reads ahead into them instead of copying the text to a padded buffer.
GltfJson readGltfJson(std::span<const std::uint8_t> text, std::size_t readableAfter, std::string_view file);

}  // namespace pbs::gltf
