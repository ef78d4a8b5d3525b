// simplifyMesh and simplifyScene: meshopt_simplify per part, then one vertex compaction per mesh.
#include "pbs/scene/simplified_meshes.hpp"

#include <meshoptimizer.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pbs {
namespace {

// What meshoptimizer reads without checking: finite positions, indices in range, and parts that
// cover the index buffer in whole triangles (validateScene's rules, checked again for unvalidated input).
bool simplifiable(const Mesh& mesh) {
  if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) return false;
  const auto finite = [](const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); };
  if (!std::all_of(mesh.positions.begin(), mesh.positions.end(), finite)) return false;
  const std::size_t vertices = mesh.positions.size();
  const auto inRange = [&](std::uint32_t i) { return i < vertices; };
  if (!std::all_of(mesh.indices.begin(), mesh.indices.end(), inRange)) return false;
  if (mesh.normals.size() != vertices || (!mesh.uvs.empty() && mesh.uvs.size() != vertices)) return false;
  std::size_t covered = 0;
  for (const MeshPart& part : mesh.parts) {
    if (part.firstIndex != covered || part.indexCount % 3 != 0) return false;
    covered += part.indexCount;
  }
  return covered == mesh.indices.size();
}

// The attribute stream in the order of meshopt_optimizeVertexFetchRemap's table.
template <typename T>
std::vector<T> remapped(const std::vector<T>& values, const std::vector<unsigned>& remap, std::size_t kept) {
  std::vector<T> out(kept);
  if (kept > 0) meshopt_remapVertexBuffer(out.data(), values.data(), values.size(), sizeof(T), remap.data());
  return out;
}

}  // namespace

SimplifiedMesh simplifyMesh(const Mesh& mesh, const SimplifyOptions& options) {
  if (!(options.ratio > 0.0 && options.ratio <= 1.0))
    throw std::invalid_argument("simplifyMesh: the ratio must lie in (0, 1]");
  if (options.ratio == 1.0 || !simplifiable(mesh)) return {mesh, 0.0f};

  SimplifiedMesh result;
  Mesh& out = result.mesh;
  out.name = mesh.name;
  std::vector<std::uint32_t> indices(mesh.indices.size());  // room for any part: meshopt's worst case is no collapse
  std::vector<std::uint32_t> kept;
  // Parts are simplified apart, so the vertices where they meet would move apart and open cracks.
  // meshoptimizer 0.18 cannot lock just those (per-vertex locks came later): a mesh of several parts
  // keeps every border vertex where it is.
  const unsigned lock = mesh.parts.size() > 1 ? meshopt_SimplifyLockBorder : 0;
  for (const MeshPart& part : mesh.parts) {
    const auto target = std::size_t(std::llround(options.ratio * double(part.indexCount / 3))) * 3;
    float error = 0.0f;
    const std::size_t count =
        meshopt_simplify(indices.data(), mesh.indices.data() + part.firstIndex, part.indexCount, &mesh.positions[0].x,
                         mesh.positions.size(), sizeof(glm::vec3), target, float(options.targetError), lock, &error);
    result.error = std::max(result.error, error);
    if (count == 0) continue;  // the whole part collapsed: no empty part is kept
    out.parts.push_back({std::uint32_t(kept.size()), std::uint32_t(count), part.material});
    kept.insert(kept.end(), indices.begin(), indices.begin() + std::ptrdiff_t(count));
  }

  // Vertices in order of first use, unused ones dropped, every attribute stream moved alike.
  std::vector<unsigned> remap(mesh.positions.size());
  const std::size_t vertices =
      meshopt_optimizeVertexFetchRemap(remap.data(), kept.data(), kept.size(), mesh.positions.size());
  out.positions = remapped(mesh.positions, remap, vertices);
  out.normals = remapped(mesh.normals, remap, vertices);
  if (!mesh.uvs.empty()) out.uvs = remapped(mesh.uvs, remap, vertices);
  out.indices.resize(kept.size());
  if (!kept.empty()) meshopt_remapIndexBuffer(out.indices.data(), kept.data(), kept.size(), remap.data());
  updateMeshBounds(out);
  return result;
}

SimplifiedScene simplifyScene(const Scene& scene, const SimplifyOptions& options) {
  SimplifiedScene result;
  result.scene.nodes = scene.nodes;
  result.scene.roots = scene.roots;
  result.scene.materials = scene.materials;
  result.scene.textures = scene.textures;
  std::vector<SimplifiedMesh> meshes(scene.meshes.size());
  // One task per mesh: each writes its own slot, so the result is the same for any thread count.
  tbb::parallel_for(std::size_t(0), scene.meshes.size(),
                    [&](std::size_t m) { meshes[m] = simplifyMesh(scene.meshes[m], options); });
  result.scene.meshes.reserve(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    result.trianglesBefore += scene.meshes[m].triangleCount();
    result.trianglesAfter += meshes[m].mesh.triangleCount();
    result.largestError = std::max(result.largestError, meshes[m].error);
    result.scene.meshes.push_back(std::move(meshes[m].mesh));
  }
  return result;
}

}  // namespace pbs
