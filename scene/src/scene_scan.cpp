// scanScene: the questions every mesh answers, listed per mesh, then the meshes read in a pipeline.
#include "pbs/scene/scene_scan.hpp"

#include "instance_bounds.hpp"
#include "pbs/scene/mesh_closure.hpp"
#include "pbs/scene/scene_fingerprint.hpp"
#include "pbs/scene/surface_area.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace pbs {
namespace {

// A box to compute: of instance `instance` of the list `list` (kWorld: the world instance of node
// `instance`).
struct BoxQuestion {
  static constexpr std::uint32_t kWorld = 0xffffffffu;
  std::uint32_t list;
  std::uint32_t instance;
};

}  // namespace

SceneScan scanScene(const Scene& scene, const Hierarchy& structure, const SceneScanRequest& request,
                    const MeshReader& read) {
  const std::size_t meshCount = scene.meshes.size();
  SceneScan scan;
  scan.meshFingerprints.resize(meshCount);
  if (request.meshClosures) scan.meshClosures.resize(meshCount);

  // The questions, listed per mesh.
  std::vector<std::vector<BoxQuestion>> boxesOf(meshCount);
  if (request.worldBounds) {
    scan.instanceBounds.assign(scene.nodes.size(), Bounds{});
    for (std::uint32_t n : structure.preorder)
      if (const std::int32_t mesh = scene.nodes[n].mesh; mesh >= 0)
        boxesOf[std::size_t(mesh)].push_back({BoxQuestion::kWorld, n});
  }
  std::vector<std::vector<SubtreeInstance>> subtrees(request.subtreeStarts.size());
  tbb::parallel_for(std::size_t(0), subtrees.size(),
                    [&](std::size_t s) { subtrees[s] = subtreeInstances(scene, request.subtreeStarts[s]); });
  scan.subtreeBounds.resize(subtrees.size());
  for (std::uint32_t s = 0; s < subtrees.size(); ++s) {
    scan.subtreeBounds[s].resize(subtrees[s].size());
    for (std::uint32_t i = 0; i < subtrees[s].size(); ++i)
      boxesOf[std::size_t(scene.nodes[subtrees[s][i].node].mesh)].push_back({s, i});
  }
  std::vector<MeshAreaQuery> areaQueries;
  std::vector<std::vector<std::uint32_t>> areasOf(meshCount);
  if (request.ownFrameAreas) {
    areaQueries = ownFrameAreaQueries(scene, structure);
    for (std::uint32_t q = 0; q < areaQueries.size(); ++q) areasOf[areaQueries[q].mesh].push_back(q);
  }
  std::vector<double> areas(areaQueries.size());

  // Read in order, answered side by side, fingerprinted in order (the scene's fingerprint is one stream).
  const auto answer = [&](std::uint32_t m, const Mesh& mesh) {
    scan.meshFingerprints[m] = meshFingerprint(mesh);
    if (request.meshClosures) scan.meshClosures[m] = meshClosure(mesh);
    if (!boxesOf[m].empty()) {
      const detail::ClusteredPoints clustered = detail::clusterPoints(mesh.positions);
      tbb::parallel_for(std::size_t(0), boxesOf[m].size(), [&](std::size_t q) {
        const BoxQuestion& box = boxesOf[m][q];
        if (box.list == BoxQuestion::kWorld) {
          scan.instanceBounds[box.instance] = detail::transformedPointBounds(clustered, structure.world[box.instance]);
        } else {
          scan.subtreeBounds[box.list][box.instance] =
              detail::transformedPointBounds(clustered, subtrees[box.list][box.instance].frameFromInstance);
        }
      });
    }
    if (!areasOf[m].empty()) {
      const TriangleAreaVectors vectors(mesh);
      tbb::parallel_for(std::size_t(0), areasOf[m].size(), [&](std::size_t i) {
        const std::uint32_t q = areasOf[m][i];
        areas[q] = vectors.areaUnder(areaQueries[q].linear);
      });
    }
  };
  SceneFingerprinter fingerprint(scene);
  std::uint32_t next = 0;
  const std::size_t inFlight = 2 * std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  tbb::parallel_pipeline(
      inFlight, tbb::make_filter<void, std::uint32_t>(tbb::filter_mode::serial_in_order,
                                                      [&](tbb::flow_control& control) -> std::uint32_t {
                                                        if (next == meshCount) control.stop();
                                                        return next++;
                                                      }) &
                    tbb::make_filter<std::uint32_t, std::shared_ptr<const Mesh>>(tbb::filter_mode::parallel,
                                                                                 [&](std::uint32_t m) {
                                                                                   std::shared_ptr<const Mesh> mesh =
                                                                                       read(m);
                                                                                   answer(m, *mesh);
                                                                                   return mesh;
                                                                                 }) &
                    tbb::make_filter<std::shared_ptr<const Mesh>, void>(
                        tbb::filter_mode::serial_in_order,
                        [&](const std::shared_ptr<const Mesh>& mesh) { fingerprint.add(*mesh); }));
  scan.sceneFingerprint = fingerprint.finish();
  if (request.ownFrameAreas) scan.ownFrameAreas = ownFrameSurfaceAreas(scene, structure, areas);
  return scan;
}

}  // namespace pbs
