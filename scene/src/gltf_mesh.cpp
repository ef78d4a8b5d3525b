// glTF meshes to pbs Meshes: reads each triangle primitive's attributes and indices through the
// checked accessor readers, converts strips and fans to triangle lists and merges the primitives.
#include "gltf_mesh.hpp"

#include "gltf_accessor.hpp"
#include "gltf_messages.hpp"
#include "pbs/scene/input_error.hpp"

#include <limits>
#include <numeric>

namespace pbs::gltf {
namespace {

constexpr std::size_t kMaxIndex = std::numeric_limits<std::uint32_t>::max();

const tinygltf::Primitive& primitiveAt(const Document& model, int mesh, std::size_t primitive) {
  return model.meshes[static_cast<std::size_t>(mesh)].primitives[primitive];
}

const int* findAttribute(const tinygltf::Primitive& primitive, const char* name) {
  const auto it = primitive.attributes.find(name);
  return it == primitive.attributes.end() ? nullptr : &it->second;
}

void checkSameCount(const AccessorView& view, const char* semantic, std::size_t vertexCount) {
  if (view.count != vertexCount) {
    throw InputError(view.file, elementName("accessor", view.accessor),
                     std::string(semantic) + " has " + std::to_string(view.count) + " elements but POSITION has " +
                         std::to_string(vertexCount));
  }
}

// The primitive's vertex indices: its index accessor, each checked against the vertex count, or
// 0..n-1 for a non-indexed primitive, so that both go through one triangle conversion.
void readPrimitiveIndices(const Document& model, const tinygltf::Primitive& primitive, std::size_t vertexCount,
                          std::string_view file, const std::string& element, std::vector<std::uint32_t>& indices,
                          ZeroFilledBudget& zeros) {
  if (primitive.indices == -1) {
    indices.resize(vertexCount);
    std::iota(indices.begin(), indices.end(), 0u);
    return;
  }
  const AccessorView view = viewAccessor(model, primitive.indices, kIndexRules, file, element, zeros);
  indices.resize(view.count);
  readIndices(view, indices);
  for (const std::uint32_t index : indices) {
    if (index >= vertexCount) {
      throw InputError(
          file, elementName("accessor", primitive.indices),
          "index " + std::to_string(index) + " out of range (" + std::to_string(vertexCount) + " vertices)");
    }
  }
}

// Appends the triangles of `indices` (offset by `base`) in the glTF spec's order: strip triangle i is
// (i, i+1, i+2) for even i and (i, i+2, i+1) for odd i, keeping one winding; fans turn around index 0.
void appendTriangles(int mode, std::span<const std::uint32_t> indices, std::uint32_t base,
                     std::vector<std::uint32_t>& out, std::string_view file, const std::string& element) {
  const std::size_t n = indices.size();
  if (mode == TINYGLTF_MODE_TRIANGLES && n % 3 != 0) {
    throw InputError(file, element, "TRIANGLES needs a multiple of 3 indices, not " + std::to_string(n));
  }
  const std::size_t triangles = mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : (n >= 3 ? n - 2 : 0);
  const std::size_t start = out.size();
  if (3 * triangles > kMaxIndex - start)
    throw InputError(file, element, "mesh has more indices than 32-bit offsets can address");
  out.resize(start + 3 * triangles);  // resize, not an exact reserve: growth stays geometric over many primitives
  std::uint32_t* dst = out.data() + start;
  const auto emit = [&](std::size_t a, std::size_t b, std::size_t c) {
    *dst++ = base + indices[a];
    *dst++ = base + indices[b];
    *dst++ = base + indices[c];
  };
  for (std::size_t t = 0; t < triangles; ++t) {
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      emit(3 * t, 3 * t + 1, 3 * t + 2);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      const std::size_t odd = t & 1;
      emit(t, t + 1 + odd, t + 2 - odd);
    } else {
      emit(0, t + 1, t + 2);
    }
  }
}

// Normalises the file's normals; a zero one stays zero, the mark for "compute this one". Returns
// whether any is zero.
bool normaliseNormals(std::span<glm::vec3> normals) {
  bool anyZero = false;
  for (glm::vec3& n : normals) {
    const glm::dvec3 d(n);
    const double length = glm::length(d);  // in double: tiny float normals would underflow when squared
    anyZero |= !(length > 0.0);
    n = length > 0.0 ? glm::vec3(d / length) : glm::vec3(0.0f);
  }
  return anyZero;
}

// Appends a primitive's triangles (over vertices starting at `first`) and its part.
void appendIndexedPart(const Document& model, const tinygltf::Primitive& primitive, std::size_t vertexCount,
                       std::size_t first, std::string_view file, const std::string& element,
                       const MaterialOf& materialOf, Mesh& result, std::vector<std::uint32_t>& scratch,
                       ZeroFilledBudget& zeros) {
  readPrimitiveIndices(model, primitive, vertexCount, file, element, scratch, zeros);
  const std::size_t firstIndex = result.indices.size();
  appendTriangles(primitive.mode, scratch, static_cast<std::uint32_t>(first), result.indices, file, element);
  if (result.indices.size() > firstIndex) {
    result.parts.push_back(MeshPart{static_cast<std::uint32_t>(firstIndex),
                                    static_cast<std::uint32_t>(result.indices.size() - firstIndex),
                                    materialOf(primitive.material, element)});
  }
}

// The accessors a primitive's vertices come from: primitives that share them (one vertex buffer,
// several index ranges, as exporters write multi-material meshes) share the merged vertices too.
struct VertexSource {
  int position = -1, normal = -1, texcoord = -1;
  std::size_t first = 0;  // where its vertices start in the merged mesh
  std::size_t count = 0;
  bool sameAccessors(const VertexSource& o) const {
    return position == o.position && normal == o.normal && texcoord == o.texcoord;
  }
};

// Appends one triangle primitive's vertices (unless an earlier primitive of the mesh read the same
// accessors), triangles and part. Returns whether some of its normals are still to be computed.
bool appendPrimitive(const Document& model, int mesh, std::size_t p, std::string_view file,
                     const MaterialOf& materialOf, Mesh& result, std::vector<std::uint32_t>& scratch,
                     std::vector<VertexSource>& sources, ZeroFilledBudget& zeros) {
  const tinygltf::Primitive& primitive = primitiveAt(model, mesh, p);
  const std::string element = primitiveName(mesh, p);
  const int* position = findAttribute(primitive, "POSITION");
  if (!position) throw InputError(file, element, "has no POSITION attribute");
  const int* normal = findAttribute(primitive, "NORMAL");
  const int* texcoord = findAttribute(primitive, "TEXCOORD_0");
  VertexSource source{*position, normal ? *normal : -1, texcoord ? *texcoord : -1};
  for (const VertexSource& seen : sources) {
    if (seen.sameAccessors(source)) {
      appendIndexedPart(model, primitive, seen.count, seen.first, file, element, materialOf, result, scratch, zeros);
      return false;  // its normals were dealt with when the vertices were read
    }
  }
  const AccessorView positions = viewAccessor(model, *position, kPositionRules, file, element, zeros);
  const std::size_t first = result.positions.size();
  const std::size_t vertexCount = positions.count;
  sources.push_back(VertexSource{source.position, source.normal, source.texcoord, first, vertexCount});
  if (vertexCount > kMaxIndex - first)
    throw InputError(file, element, "mesh has more vertices than 32-bit indices can address");
  result.positions.resize(first + vertexCount);
  readVectors<3>(positions, std::span(result.positions).subspan(first));

  bool computeNormals = true;
  result.normals.resize(first + vertexCount);  // zero normals: computed after the merge
  if (normal) {
    const AccessorView normals = viewAccessor(model, *normal, kNormalRules, file, element, zeros);
    checkSameCount(normals, "NORMAL", vertexCount);
    const auto span = std::span(result.normals).subspan(first);
    readVectors<3>(normals, span);
    computeNormals = normaliseNormals(span);
  }
  if (texcoord) {
    const AccessorView uvs = viewAccessor(model, *texcoord, kTexcoordRules, file, element, zeros);
    checkSameCount(uvs, "TEXCOORD_0", vertexCount);
    result.uvs.resize(first + vertexCount);  // also gives earlier primitives without uvs their (0,0)
    readVectors<2>(uvs, std::span(result.uvs).subspan(first));
  }

  appendIndexedPart(model, primitive, vertexCount, first, file, element, materialOf, result, scratch, zeros);
  return computeNormals;
}

}  // namespace

void SkippedPrimitives::appendWarnings(std::vector<std::string>& warnings) const {
  static constexpr const char* kModeNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
  for (std::size_t mode = 0; mode < byMode.size(); ++mode) {
    if (byMode[mode] == 0) continue;
    warnings.push_back("skipped " + std::to_string(byMode[mode]) + (byMode[mode] == 1 ? " primitive" : " primitives") +
                       " of mode " + kModeNames[mode]);
  }
}

// Calls each(p, mode) for the mesh's triangle primitives, counting the point and line ones in `skipped`
// and refusing a mode glTF does not have.
template <class Each>
void forTrianglePrimitives(const Document& model, int mesh, std::string_view file, SkippedPrimitives& skipped,
                           Each each) {
  const tinygltf::Mesh& source = model.meshes[static_cast<std::size_t>(mesh)];
  for (std::size_t p = 0; p < source.primitives.size(); ++p) {
    const int mode = source.primitives[p].mode;
    if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {
      ++skipped.byMode[static_cast<std::size_t>(mode)];
    } else if (mode >= TINYGLTF_MODE_TRIANGLES && mode <= TINYGLTF_MODE_TRIANGLE_FAN) {
      each(p);
    } else {
      throw InputError(file, primitiveName(mesh, p), "mode " + std::to_string(mode) + " is not a glTF primitive mode");
    }
  }
}

Mesh importMesh(const Document& model, int mesh, std::string_view file, const MaterialOf& materialOf,
                SkippedPrimitives& skipped, ZeroFilledBudget& zeros) {
  Mesh result;
  result.name = model.meshes[static_cast<std::size_t>(mesh)].name;
  std::vector<std::uint32_t> scratch;  // one primitive's indices, reused
  std::vector<VertexSource> sources;
  bool computeNormals = false;
  forTrianglePrimitives(model, mesh, file, skipped, [&](std::size_t p) {
    computeNormals |= appendPrimitive(model, mesh, p, file, materialOf, result, scratch, sources, zeros);
  });
  if (result.indices.empty()) return Mesh{};

  if (computeNormals) {
    // Vertices are shared only by primitives that name the same accessors, so one pass over the
    // merged mesh gives each vertex the normal of the triangles that use it.
    const std::vector<glm::vec3> computed = computeVertexNormals(result.positions, result.indices);
    for (std::size_t v = 0; v < result.normals.size(); ++v) {
      if (result.normals[v] == glm::vec3(0.0f)) result.normals[v] = computed[v];
    }
  }
  if (!result.uvs.empty()) result.uvs.resize(result.positions.size());  // later primitives without uvs
  updateMeshBounds(result);
  return result;
}

Mesh describeMesh(const Document& model, int mesh, std::string_view file, const MaterialOf& materialOf,
                  SkippedPrimitives& skipped) {
  Mesh result;
  result.name = model.meshes[static_cast<std::size_t>(mesh)].name;
  std::uint64_t indexCount = 0;
  std::vector<VertexSource> sources;  // as importMesh reads them: primitives of the same accessors share vertices
  forTrianglePrimitives(model, mesh, file, skipped, [&](std::size_t p) {
    const tinygltf::Primitive& primitive = primitiveAt(model, mesh, p);
    const std::string element = primitiveName(mesh, p);
    const int* position = findAttribute(primitive, "POSITION");
    if (!position) throw InputError(file, element, "has no POSITION attribute");
    if (!validIndex(*position, model.accessors.size()))
      throw InputError(file, element, missingElement("accessor", *position, model.accessors.size()));
    const int* normal = findAttribute(primitive, "NORMAL");
    const int* texcoord = findAttribute(primitive, "TEXCOORD_0");
    const VertexSource source{*position, normal ? *normal : -1, texcoord ? *texcoord : -1};
    if (std::none_of(sources.begin(), sources.end(),
                     [&](const VertexSource& seen) { return seen.sameAccessors(source); })) {
      sources.push_back(source);
      result.describedVertices += model.accessors[static_cast<std::size_t>(*position)].count;
    }
    // The count appendTriangles converts: the index accessor's, else one index per vertex.
    const int counted = primitive.indices != -1 ? primitive.indices : *position;
    if (!validIndex(counted, model.accessors.size()))
      throw InputError(file, element, missingElement("accessor", counted, model.accessors.size()));
    const std::size_t n = model.accessors[static_cast<std::size_t>(counted)].count;
    if (primitive.mode == TINYGLTF_MODE_TRIANGLES && n % 3 != 0)
      throw InputError(file, element, "TRIANGLES needs a multiple of 3 indices, not " + std::to_string(n));
    const std::size_t triangles = primitive.mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : (n >= 3 ? n - 2 : 0);
    if (3 * triangles > kMaxIndex - indexCount)
      throw InputError(file, element, "mesh has more indices than 32-bit offsets can address");
    if (triangles == 0) return;
    result.parts.push_back(MeshPart{static_cast<std::uint32_t>(indexCount), static_cast<std::uint32_t>(3 * triangles),
                                    materialOf(primitive.material, element)});
    indexCount += 3 * triangles;
  });
  return result;
}

std::vector<std::span<const std::uint8_t>> meshViewBytes(const Document& model, int mesh) {
  std::vector<std::span<const std::uint8_t>> views;
  const auto add = [&](int accessor) {
    if (accessor < 0) return;
    const int view = model.accessors[static_cast<std::size_t>(accessor)].bufferView;
    if (view >= 0) views.push_back(bufferViewBytes(model, view, "", ""));
  };
  for (const tinygltf::Primitive& primitive : model.meshes[static_cast<std::size_t>(mesh)].primitives) {
    if (primitive.mode < TINYGLTF_MODE_TRIANGLES) continue;  // skipped: never read, nor checked
    add(primitive.indices);
    for (const char* name : {"POSITION", "NORMAL", "TEXCOORD_0"})
      if (const int* accessor = findAttribute(primitive, name)) add(*accessor);
  }
  return views;
}

}  // namespace pbs::gltf
