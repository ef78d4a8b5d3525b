// A 64-bit fingerprint of everything in a scene that shapes its surfels, so a .surfels file can tell
// the scene it was made from apart from any other.
#pragma once

#include "pbs/raster/hash64.hpp"
#include "pbs/scene/scene.hpp"

#include <cstddef>

#include <cstdint>

namespace pbs {

// Hashes the node graph (roots, children, mesh references, the exact bits of every transform), every
// mesh's vertex data, indices and parts, the materials and the textures' pixels. Names do not count.
// Equal scenes give equal values on every machine; any change to what is hashed changes it (up to
// 64-bit collisions).
std::uint64_t sceneFingerprint(const Scene& scene);

// sceneFingerprint with the meshes fed one at a time, for a scene whose meshes are read and dropped one
// after another: the scene (whose node graph, materials and textures it reads) must outlive it; add()
// every mesh in index order, then finish() (std::logic_error when a mesh is missing).
class SceneFingerprinter {
 public:
  explicit SceneFingerprinter(const Scene& scene);
  void add(const Mesh& mesh);
  std::uint64_t finish();

 private:
  const Scene& scene_;
  Hash64 hash_;
  std::size_t added_ = 0;
};

// The two halves a scene opened without its mesh arrays (lazy_meshes.hpp) is checked by: the structure
// (the node graph and transforms, each mesh's parts, the materials and textures: all but the arrays) at
// open, and each mesh's arrays and parts when they are first read. Equal scenes give equal values of both;
// a change to anything sceneFingerprint hashes changes the structure's or some mesh's.
std::uint64_t structureFingerprint(const Scene& scene);
std::uint64_t meshFingerprint(const Mesh& mesh);

}  // namespace pbs
