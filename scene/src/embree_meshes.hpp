// The bottom level of the Embree casters: one BVH per mesh, built the first time an instance needs it
// and kept, shared by every instance of the mesh.
#pragma once

#include "embree_handles.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace pbs {

struct EmbreeMeshes {
  // The device's allocation count, shared by every owner of the device; declared before it, so that it
  // is released after the device's last release has been counted.
  std::shared_ptr<EmbreeAllocations> allocations;
  EmbreeDevice device;                    // released after the scenes built on it
  std::vector<EmbreeSceneHandle> scenes;  // by mesh index; null until built
};

// A new device with no BVH built yet, room for every mesh of `scene`.
EmbreeMeshes makeEmbreeMeshes(const Scene& scene);

// A second owner of the same device and built BVHs (no copy: Embree counts references). What either
// builds afterwards stays its own.
EmbreeMeshes shareEmbreeMeshes(const EmbreeMeshes& meshes);

// Of `nodes`, in their order, those whose instance rays can hit: a mesh with triangles under a
// transform Embree can invert.
std::vector<std::uint32_t> rayInstanceNodes(const Scene& scene, const Hierarchy& hierarchy,
                                            std::span<const std::uint32_t> nodes);

struct MeshBuilds {
  std::uint32_t meshes = 0;
  std::uint64_t triangles = 0;
};

// Builds the BVH of every mesh that `nodes` (from rayInstanceNodes) draw and that is not built yet.
MeshBuilds buildMeshScenes(EmbreeMeshes& meshes, const Scene& scene, std::span<const std::uint32_t> nodes);

}  // namespace pbs
