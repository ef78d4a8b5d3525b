// Bounds-checked glTF accessor views and their typed readers: every byte range is checked before
// a view is handed out, so the decoding loops below can read without further tests.
#include "gltf_accessor.hpp"

#include "gltf_messages.hpp"
#include "pbs/scene/input_error.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

namespace pbs::gltf {
namespace {

std::string componentTypeName(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    default: return std::to_string(componentType) + " (not a glTF componentType)";
  }
}

std::size_t componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    default: return 4;  // INT, UNSIGNED_INT, FLOAT: the only others a rule lets through
  }
}

// Components per element for the types a mesh attribute or index can have; 0 for matrices.
int typeComponents(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    default: return 0;
  }
}

const char* typeName(int components) {
  switch (components) {
    case 1: return "SCALAR";
    case 2: return "VEC2";
    case 3: return "VEC3";
    case 4: return "VEC4";
    default: return "a matrix";
  }
}

// Range first: componentBit of an arbitrary int from the file would be an out-of-range shift.
bool admits(unsigned componentTypes, int componentType) {
  return componentType >= TINYGLTF_COMPONENT_TYPE_BYTE && componentType <= TINYGLTF_COMPONENT_TYPE_FLOAT &&
         (componentTypes & componentBit(componentType)) != 0;
}

bool rangeFits(std::size_t offset, std::size_t length, std::size_t size) {
  return offset <= size && length <= size - offset;
}

// Calls f(T{}) with T the C++ type of a glTF componentType the rules admitted.
template <typename F>
void withComponentType(int componentType, F&& f) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: f(std::int8_t{}); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: f(std::uint8_t{}); break;
    case TINYGLTF_COMPONENT_TYPE_SHORT: f(std::int16_t{}); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: f(std::uint16_t{}); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: f(std::uint32_t{}); break;
    default: f(float{}); break;
  }
}

template <typename T>
T load(const std::uint8_t* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// The glTF spec's conversions: c / 255 for unsigned, max(c / 127, -1) for signed types.
template <typename T>
float componentValue(const std::uint8_t* p, bool normalized) {
  const T value = load<T>(p);
  if constexpr (std::is_same_v<T, float>) {
    return value;
  } else {
    if (!normalized) return static_cast<float>(value);
    const float scaled = static_cast<float>(value) / static_cast<float>(std::numeric_limits<T>::max());
    return std::is_signed_v<T> ? std::max(scaled, -1.0f) : scaled;
  }
}

template <typename T, int N>
void decodeVectors(const std::uint8_t* src, std::size_t stride, bool normalized, std::span<glm::vec<N, float>> out) {
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::uint8_t* element = src + i * stride;
    for (int c = 0; c < N; ++c) out[i][c] = componentValue<T>(element + c * sizeof(T), normalized);
  }
}

std::uint32_t sparseIndex(const AccessorView& view, std::size_t j) {
  switch (view.sparseIndexType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return load<std::uint8_t>(view.sparseIndices + j);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return load<std::uint16_t>(view.sparseIndices + 2 * j);
    default: return load<std::uint32_t>(view.sparseIndices + 4 * j);
  }
}

// Calls apply(target, valueBytes) for each sparse substitution, after checking its target index.
template <typename F>
void forEachSparse(const AccessorView& view, F&& apply) {
  const std::size_t elementSize = componentSize(view.componentType) * static_cast<std::size_t>(view.components);
  for (std::size_t j = 0; j < view.sparseCount; ++j) {
    const std::uint32_t target = sparseIndex(view, j);
    if (target >= view.count) {
      throw InputError(
          view.file, elementName("accessor", view.accessor),
          "sparse index " + std::to_string(target) + " out of range (" + std::to_string(view.count) + " elements)");
    }
    apply(target, view.sparseValues + j * elementSize);
  }
}

void checkSparse(const Document& model, const tinygltf::Accessor& a, AccessorView& view, std::size_t elementSize,
                 const std::string& element) {
  const auto& sparse = a.sparse;
  if (sparse.count < 0 || static_cast<std::size_t>(sparse.count) > view.count) {
    throw InputError(
        view.file, element,
        "sparse count " + std::to_string(sparse.count) + " out of range (" + std::to_string(view.count) + " elements)");
  }
  const int indexType = sparse.indices.componentType;
  if (!admits(kIndexRules.componentTypes, indexType)) {
    throw InputError(view.file, element, "sparse indices cannot use componentType " + componentTypeName(indexType));
  }
  const auto sparseCount = static_cast<std::size_t>(sparse.count);
  const auto sparseBytes = [&](int bufferView, int byteOffset, std::size_t size, const char* what) {
    const auto bytes = bufferViewBytes(model, bufferView, view.file, element);
    if (byteOffset < 0 || !rangeFits(static_cast<std::size_t>(byteOffset), sparseCount * size, bytes.size())) {
      throw InputError(view.file, element,
                       std::string("sparse ") + what + " run past the end of bufferView " + std::to_string(bufferView));
    }
    return bytes.data() + byteOffset;
  };
  view.sparseCount = sparseCount;
  view.sparseIndexType = indexType;
  view.sparseIndices =
      sparseBytes(sparse.indices.bufferView, sparse.indices.byteOffset, componentSize(indexType), "indices");
  view.sparseValues = sparseBytes(sparse.values.bufferView, sparse.values.byteOffset, elementSize, "values");
}

}  // namespace

std::span<const std::uint8_t> bufferViewBytes(const Document& model, int bufferView, std::string_view file,
                                              std::string_view referrer) {
  if (!validIndex(bufferView, model.bufferViews.size())) {
    throw InputError(file, referrer, missingElement("bufferView", bufferView, model.bufferViews.size()));
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(bufferView)];
  const std::string element = elementName("bufferView", bufferView);
  if (!validIndex(view.buffer, model.buffers.size())) {
    throw InputError(file, element, missingElement("buffer", view.buffer, model.buffers.size()));
  }
  const std::span<const std::uint8_t> data = model.bufferBytes[static_cast<std::size_t>(view.buffer)];
  if (!rangeFits(view.byteOffset, view.byteLength, data.size())) {
    throw InputError(file, element,
                     "byteOffset " + std::to_string(view.byteOffset) + " + byteLength " +
                         std::to_string(view.byteLength) + " runs past the end of buffer " +
                         std::to_string(view.buffer) + " (" + std::to_string(data.size()) + " bytes)");
  }
  return {data.data() + view.byteOffset, view.byteLength};
}

AccessorView viewAccessor(const Document& model, int accessor, const AccessorRules& rules, std::string_view file,
                          std::string_view referrer, ZeroFilledBudget& zeros) {
  if (!validIndex(accessor, model.accessors.size())) {
    throw InputError(file, referrer, missingElement("accessor", accessor, model.accessors.size()));
  }
  const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(accessor)];
  const std::string element = elementName("accessor", accessor);
  const int components = typeComponents(a.type);
  if (components != rules.components) {
    throw InputError(
        file, element,
        std::string(rules.semantic) + " must be " + typeName(rules.components) + ", not " + typeName(components));
  }
  if (!admits(rules.componentTypes, a.componentType)) {
    throw InputError(file, element,
                     std::string(rules.semantic) + " cannot use componentType " + componentTypeName(a.componentType));
  }

  AccessorView view;
  view.file = file;
  view.accessor = accessor;
  view.count = a.count;
  view.componentType = a.componentType;
  view.components = components;
  view.normalized = a.normalized;
  const std::size_t elementSize = componentSize(a.componentType) * static_cast<std::size_t>(components);

  if (a.bufferView == -1) {
    if (view.count > zeros.left) {
      throw InputError(file, element,
                       "has no bufferView but " + std::to_string(view.count) + " elements: zero-filled elements are " +
                           "limited to " + std::to_string(kMaxZeroFilledElements) + " per file, every use counted (" +
                           std::to_string(zeros.left) + " left)");
    }
    zeros.left -= view.count;
  } else {
    const auto bytes = bufferViewBytes(model, a.bufferView, file, element);
    const std::size_t byteStride = model.bufferViews[static_cast<std::size_t>(a.bufferView)].byteStride;
    view.stride = byteStride != 0 ? byteStride : elementSize;
    if (view.stride < elementSize) {
      throw InputError(file, element,
                       "byteStride " + std::to_string(view.stride) + " of bufferView " + std::to_string(a.bufferView) +
                           " is smaller than the element size " + std::to_string(elementSize));
    }
    // The last element ends at byteOffset + stride * (count - 1) + elementSize.
    std::size_t span = 0;
    if (view.count > 0 &&
        (__builtin_mul_overflow(view.stride, view.count - 1, &span) ||
         __builtin_add_overflow(span, elementSize, &span) || !rangeFits(a.byteOffset, span, bytes.size()))) {
      throw InputError(file, element,
                       std::to_string(view.count) + " elements from byteOffset " + std::to_string(a.byteOffset) +
                           " run past the end of bufferView " + std::to_string(a.bufferView) + " (" +
                           std::to_string(bytes.size()) + " bytes)");
    }
    if (view.count > 0) view.data = bytes.data() + a.byteOffset;
  }
  if (a.sparse.isSparse) checkSparse(model, a, view, elementSize, element);
  return view;
}

template <int N>
void readVectors(const AccessorView& view, std::span<glm::vec<N, float>> out) {
  const std::size_t elementSize = componentSize(view.componentType) * N;
  withComponentType(view.componentType, [&](auto tag) {
    using T = decltype(tag);
    if (view.data) {
      decodeVectors<T, N>(view.data, view.stride, view.normalized, out);
    } else {
      std::fill(out.begin(), out.end(), glm::vec<N, float>(0.0f));
    }
    forEachSparse(view, [&](std::uint32_t target, const std::uint8_t* value) {
      decodeVectors<T, N>(value, elementSize, view.normalized, out.subspan(target, 1));
    });
  });
  if (view.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) return;  // integers are always finite
  const auto bad = std::find_if(out.begin(), out.end(), [](const glm::vec<N, float>& v) {
    for (int c = 0; c < N; ++c)
      if (!std::isfinite(v[c])) return true;
    return false;
  });
  if (bad != out.end()) {
    throw InputError(view.file, elementName("accessor", view.accessor),
                     "element " + std::to_string(bad - out.begin()) + " is not finite");
  }
}

template void readVectors<2>(const AccessorView&, std::span<glm::vec2>);
template void readVectors<3>(const AccessorView&, std::span<glm::vec3>);

void readIndices(const AccessorView& view, std::span<std::uint32_t> out) {
  withComponentType(view.componentType, [&](auto tag) {
    using T = decltype(tag);
    if constexpr (std::is_unsigned_v<T>) {  // the index rules admit nothing else
      if (view.data) {
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = load<T>(view.data + i * view.stride);
      } else {
        std::fill(out.begin(), out.end(), 0u);
      }
      forEachSparse(view, [&](std::uint32_t target, const std::uint8_t* value) { out[target] = load<T>(value); });
    }
  });
}

}  // namespace pbs::gltf
