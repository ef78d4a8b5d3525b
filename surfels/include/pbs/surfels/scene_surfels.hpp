// A .surfels file matched to its scene: decoded arrays ready to draw, and which node uses which.
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/surfel_file.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace pbs {

// The surface area one surfel stands for, as a fraction of r² for a prefix of spacing r (packing / k =
// r²): the cell of a point in a hexagonal packing of spacing r has area (√3 / 2) r².
inline constexpr double kSurfelAreaPerSpacing2 = 0.8660254037844386;

// An array at least this share of whose surfels have a twin facing the other way (SurfelArray::
// twoSidedShare) is an open sheet (a terrain, a sign, a leaf): its surfels seen from one side sample the
// same surface as those seen from the other, so all are drawn, facing the eye, instead of culling those
// facing away. Culled, each side had half the prefix, too sparse to close it: a 10 M-triangle terrain seen
// from 5 bounding radii had holes over 5 % of its pixels.
inline constexpr float kOpenSheetShare = 0.5f;

// One array in the structure-of-arrays form drawPoints reads.
struct SplatArray {
  Bounds box;  // node-frame box; positions are relative to its centre
  double coverage = 0.0;
  // The file's packing values (SurfelArray), at k = min(1000, N) surfels and at all N (0: not known),
  // each capped so that the array never stands for more than the subtree's surface area (splatArrayOf).
  double packing = 0.0;
  double packingEnd = 0.0;
  bool openSheet = false;  // two-sided share ≥ kOpenSheetShare: drawn facing either way
  // The array's length. The surfels below hold its first loaded() of them: all of them when the file
  // was read whole, the prefixes frames asked for when it is read on demand (SurfelCache).
  std::size_t length = 0;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::u8vec4> colors;

  std::size_t size() const { return length; }
  std::size_t loaded() const { return positions.size(); }
  // Mean spacing of the first `count` surfels, from the packing values (packing = d_k² · k): the
  // distance between neighbours that a prefix of that length leaves, in the node frame. Between the two
  // measured lengths the packing is interpolated as a power of k: where a subtree's parts lie far apart
  // (a city), its first surfels spread over the gaps and later ones fill the parts, and the first value
  // overstates the spacing of long prefixes (the 500 M-triangle city's root: its surfels would stand for
  // 6.5 times its area, against 0.6 for a typical array of the default scene).
  double spacing(std::size_t count) const;
};

SplatArray splatArrayOf(const SurfelArray& array);
// An array of `info.count` surfels with none loaded yet.
SplatArray splatArrayOf(const SurfelArrayInfo& info);
// Appends decoded surfels to the loaded prefix (they must be the ones that follow it).
void appendSurfels(SplatArray& array, std::span<const Surfel> surfels);
// Bytes one loaded surfel takes in a SplatArray.
inline constexpr std::size_t kSplatBytesPerSurfel = 2 * sizeof(glm::vec3) + sizeof(glm::u8vec4);

inline constexpr std::uint32_t kNoSurfels = 0xffffffffu;

struct SceneSurfels {
  std::vector<SplatArray> arrays;
  std::vector<std::uint32_t> arrayOfNode;  // per scene node: index into arrays, or kNoSurfels
};

// Matches the file's node records to the scene's nodes by their stable paths (nodePath). Throws
// InputError naming `source` and the node when a path does not exist in the scene.
SceneSurfels sceneSurfelsOf(const SurfelFile& file, const Scene& scene, const Hierarchy& hierarchy,
                            const std::string& source);

// The same match alone: per scene node the array its record names, or kNoSurfels.
std::vector<std::uint32_t> arrayOfNodes(std::span<const SurfelNodeRecord> records, const Scene& scene,
                                        const Hierarchy& hierarchy, const std::string& source);

// Reads the whole file (every checksum checked), requires it to belong to `scene` (its fingerprint),
// and matches it as above. Errors are InputErrors naming the file.
SceneSurfels loadSceneSurfels(const std::filesystem::path& file, const Scene& scene, const Hierarchy& hierarchy);

}  // namespace pbs
