// Private to the glTF importer: bounds-checked views of accessors and the typed readers that
// decode them (strided, normalized integers, sparse substitutions) into plain arrays.
#pragma once

#include <glm/glm.hpp>
#include "gltf_document.hpp"

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace pbs::gltf {

// Bit for a glTF componentType (5120 BYTE … 5126 FLOAT) in AccessorRules::componentTypes.
constexpr unsigned componentBit(int componentType) { return 1u << (componentType - TINYGLTF_COMPONENT_TYPE_BYTE); }

// What one use of an accessor accepts.
struct AccessorRules {
  const char* semantic;     // "POSITION", "indices": for messages
  int components;           // 1 (SCALAR), 2 (VEC2) or 3 (VEC3)
  unsigned componentTypes;  // componentBit()s allowed
};

inline constexpr AccessorRules kIndexRules{"indices", 1,
                                           componentBit(TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) |
                                               componentBit(TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) |
                                               componentBit(TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)};

// Float, or any 8/16-bit integer (normalized, or not as KHR_mesh_quantization allows).
inline constexpr unsigned kQuantizableTypes =
    componentBit(TINYGLTF_COMPONENT_TYPE_FLOAT) | componentBit(TINYGLTF_COMPONENT_TYPE_BYTE) |
    componentBit(TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) | componentBit(TINYGLTF_COMPONENT_TYPE_SHORT) |
    componentBit(TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);

inline constexpr AccessorRules kPositionRules{"POSITION", 3, kQuantizableTypes};
inline constexpr AccessorRules kNormalRules{"NORMAL", 3,
                                            componentBit(TINYGLTF_COMPONENT_TYPE_FLOAT) |
                                                componentBit(TINYGLTF_COMPONENT_TYPE_BYTE) |
                                                componentBit(TINYGLTF_COMPONENT_TYPE_SHORT)};
inline constexpr AccessorRules kTexcoordRules{"TEXCOORD_0", 2, kQuantizableTypes};

// An accessor whose every byte has been checked to lie inside its buffer; reading it cannot go
// out of bounds. Points into the model, which must outlive it.
struct AccessorView {
  std::string_view file;  // for messages
  int accessor = -1;
  std::size_t count = 0;
  const std::uint8_t* data = nullptr;  // first element; null when the accessor has no bufferView (zeros)
  std::size_t stride = 0;
  int componentType = 0;
  int components = 0;
  bool normalized = false;

  // Sparse substitutions applied over the dense values; sparseCount 0 when none.
  std::size_t sparseCount = 0;
  const std::uint8_t* sparseIndices = nullptr;
  int sparseIndexType = 0;
  const std::uint8_t* sparseValues = nullptr;  // tightly packed elements
};

// The bytes of bufferView `bufferView`, checked to lie inside its buffer; `referrer` names who asked
// (for a missing bufferView). Throws InputError naming the bufferView otherwise.
std::span<const std::uint8_t> bufferViewBytes(const Document& model, int bufferView, std::string_view file,
                                              std::string_view referrer);

// An accessor without a bufferView is all zeros: its elements cost memory without costing file bytes,
// and one such accessor can be read by any number of primitives and meshes. One budget per import caps
// them all, every read counted, so that a file of a few hundred bytes cannot ask for gigabytes.
inline constexpr std::size_t kMaxZeroFilledElements = std::size_t{1} << 20;
struct ZeroFilledBudget {
  std::size_t left = kMaxZeroFilledElements;
};

// Checks accessor `accessor` against `rules` and the buffers, throwing InputError naming the accessor,
// bufferView or buffer at fault. `referrer` names who asked (for a missing accessor). An accessor
// without a bufferView spends its element count from `zeros`, throwing InputError when too few are left.
AccessorView viewAccessor(const Document& model, int accessor, const AccessorRules& rules, std::string_view file,
                          std::string_view referrer, ZeroFilledBudget& zeros);

// Decodes every element into `out` (out.size() == view.count), as float, integers normalized per the
// glTF spec when the accessor says so. Throws InputError on a non-finite value or a bad sparse index.
template <int N>
void readVectors(const AccessorView& view, std::span<glm::vec<N, float>> out);

// Decodes indices as stored; range checks against a vertex count are the caller's.
void readIndices(const AccessorView& view, std::span<std::uint32_t> out);

}  // namespace pbs::gltf
