// Private to the glTF importer: the wording shared by its error messages, so every part names
// elements the same way ("accessor 3", "mesh 2 primitive 1").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace pbs::gltf {

inline std::string elementName(std::string_view kind, std::int64_t index) {
  return std::string(kind) + ' ' + std::to_string(index);
}

inline std::string primitiveName(int mesh, std::size_t primitive) {
  return "mesh " + std::to_string(mesh) + " primitive " + std::to_string(primitive);
}

// glTF references are ints where -1 (or absence) means "none"; anything else must be in range.
inline bool validIndex(std::int64_t index, std::size_t count) {
  return index >= 0 && static_cast<std::uint64_t>(index) < count;
}

// "accessor 9 does not exist (the file has 4)"
inline std::string missingElement(std::string_view kind, std::int64_t index, std::size_t count) {
  return elementName(kind, index) + " does not exist (the file has " + std::to_string(count) + ")";
}

}  // namespace pbs::gltf
