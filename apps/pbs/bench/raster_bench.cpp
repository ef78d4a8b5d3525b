// The raster benchmark: medians of repeated runs, peers measured in the same process and run, and
// a coverage count next to every timing so a peer that drew nothing cannot look fast.
#include "raster_bench.hpp"

#include "llvmpipe_peer.hpp"
#include "timing.hpp"

#include <pbs/raster/box_view.hpp>
#include <pbs/raster/points.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/embree_caster.hpp>
#include <pbs/scene/scene_draws.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pbs::bench {
namespace {

constexpr ChannelMask kCaptureChannels = kChannelColor | kChannelPosition | kChannelNormal;

std::uint64_t coveredPixels(const Framebuffer& framebuffer) {
  std::uint64_t covered = 0;
  for (std::size_t i = 0; i < framebuffer.pixelCount(); ++i) covered += framebuffer.covered(i);
  return covered;
}

struct CaptureViews {
  std::vector<Camera> cameras;
  std::vector<Framebuffer> framebuffers;
};

CaptureViews makeCaptureViews(const Bounds& box, std::uint32_t resolution) {
  CaptureViews views;
  for (const glm::dvec3& direction : boxCornerDirections()) {
    views.cameras.push_back(boxViewCamera(box, direction, resolution));
    const Camera& camera = views.cameras.back();
    views.framebuffers.push_back(makeFramebuffer(camera.width, camera.height, kCaptureChannels, box.center()));
  }
  return views;
}

// pbs: the eight views into depth + colour + position + normal, the framebuffers cleared each time.
nlohmann::json timePbsCapture(const Scene& scene, const Hierarchy& hierarchy, CaptureViews& views, int threads,
                              int repeats) {
  double seconds = 0;
  runWithThreads(threads, [&] {
    seconds = medianSeconds(repeats, [&] {
      for (std::size_t v = 0; v < views.cameras.size(); ++v) {
        clearFramebuffer(views.framebuffers[v]);
        drawSceneTriangles(scene, hierarchy, views.cameras[v], views.framebuffers[v]);
      }
    });
  });
  std::uint64_t covered = 0;
  for (const Framebuffer& framebuffer : views.framebuffers) covered += coveredPixels(framebuffer);
  return {{"seconds", seconds}, {"threads", resolveThreadCount(threads)}, {"covered_pixels", covered}};
}

// The share of pixels covered by both pbs and llvmpipe whose positions agree within 1e-4 of the
// box's diagonal: evidence that llvmpipe fills the same position channel, not just covers the
// same pixels. Pixels on silhouettes and shared edges may go to different triangles.
double positionAgreement(const Framebuffer& pbs, const std::vector<glm::vec3>& llvmpipe, const Bounds& box) {
  const float tolerance = float(1e-4 * glm::length(box.max - box.min));
  std::uint64_t both = 0, agree = 0;
  for (std::size_t i = 0; i < pbs.pixelCount(); ++i) {
    if (!pbs.covered(i) || std::isnan(llvmpipe[i].x)) continue;
    ++both;
    agree += glm::length(pbs.position[i] - llvmpipe[i]) <= tolerance;
  }
  return both > 0 ? double(agree) / double(both) : 0.0;
}

// llvmpipe fills the same channels as pbs's capture: depth, base colour, world position and
// normal (untextured: a textured material gets its base colour only, which spares llvmpipe work).
nlohmann::json timeLlvmpipeCapture(const Scene& scene, const Hierarchy& hierarchy, const CaptureViews& views,
                                   const Bounds& box, int threads, int repeats) {
  std::uint32_t width = 0, height = 0;
  for (const Camera& camera : views.cameras) {
    width = std::max(width, camera.width);
    height = std::max(height, camera.height);
  }
  LlvmpipePeer peer(width, height, resolveThreadCount(threads));
  if (!peer.available() || !peer.useCaptureGBuffer()) return {{"missing", peer.missingReason()}};
  std::uint64_t covered = 0;
  const double seconds = medianSeconds(repeats, [&] {
    covered = 0;
    for (std::size_t v = 0; v < views.cameras.size(); ++v) {
      const Camera& camera = views.cameras[v];
      // One context as large as the largest view; each view draws into its own viewport size.
      peer.setViewport(camera.width, camera.height);
      peer.clear();
      const glm::dmat4 clipFromWorld = camera.clipFromWorld();
      const glm::dmat4 positionFromWorld = glm::translate(glm::dmat4(1.0), -views.framebuffers[v].positionOrigin);
      for (std::uint32_t n : hierarchy.preorder) {
        const Node& node = scene.nodes[n];
        if (node.mesh < 0) continue;
        const Mesh& mesh = scene.meshes[std::size_t(node.mesh)];
        const glm::dmat4& world = hierarchy.world[n];
        const glm::mat3 normalFromObject(glm::transpose(glm::inverse(glm::dmat3(world))));
        for (const MeshPart& part : mesh.parts) {
          const glm::vec4 color =
              part.material < scene.materials.size() ? scene.materials[part.material].baseColorFactor : glm::vec4(1.0f);
          peer.drawCaptureTriangles(glm::mat4(clipFromWorld * world), glm::mat4(positionFromWorld * world),
                                    normalFromObject, color, mesh.positions, mesh.normals,
                                    std::span(mesh.indices).subspan(part.firstIndex, part.indexCount));
        }
      }
      peer.finish();
      covered += peer.coveredPixels();
    }
  });
  return {{"seconds", seconds},
          {"threads", resolveThreadCount(threads)},
          {"covered_pixels", covered},
          {"channels", "depth, colour, position, normal"},
          {"position_agreement", positionAgreement(views.framebuffers.back(), peer.capturePositions(), box)}};
}

nlohmann::json timeEmbreeCapture(const Scene& scene, const Hierarchy& hierarchy, CaptureViews& views, int threads,
                                 int repeats) {
  nlohmann::json result;
  runWithThreads(threads, [&] {
    const auto start = std::chrono::steady_clock::now();
    const EmbreeScene embree(scene, hierarchy);
    result["bvh_seconds"] = cli::secondsSince(start);
    // render overwrites every pixel (a miss with the cleared values): no separate clear to time.
    result["seconds"] = medianSeconds(repeats, [&] {
      for (std::size_t v = 0; v < views.cameras.size(); ++v) embree.render(views.cameras[v], views.framebuffers[v]);
    });
  });
  std::uint64_t covered = 0;
  for (const Framebuffer& framebuffer : views.framebuffers) covered += coveredPixels(framebuffer);
  result["covered_pixels"] = covered;
  result["threads"] = resolveThreadCount(threads);
  return result;
}

struct RandomPoints {
  std::vector<glm::vec3> positions;
  std::vector<glm::u8vec4> colors;
};

// Points spread through a cube in front of the camera; a fixed 64-bit LCG keeps them identical on
// every machine.
RandomPoints makeRandomPoints(std::uint64_t count) {
  RandomPoints points;
  points.positions.resize(count);
  points.colors.resize(count);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  const auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return float(state >> 40) / float(1 << 24);
  };
  for (std::uint64_t i = 0; i < count; ++i) {
    points.positions[i] = glm::vec3(next(), next(), next()) * 2.0f - 1.0f;
    points.colors[i] = glm::u8vec4(std::uint8_t(next() * 255), std::uint8_t(next() * 255), 128, 255);
  }
  return points;
}

Camera pointsCamera(std::uint32_t resolution) {
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0, 0, 3), glm::dvec3(0), glm::dvec3(0, 1, 0));
  return orthographicCamera(view, -1.0, 1.0, -1.0, 1.0, 0.5, 5.0, resolution, resolution);
}

nlohmann::json timePoints(const RandomPoints& points, std::uint32_t resolution, float size, int threads, int repeats) {
  const Camera camera = pointsCamera(resolution);
  Framebuffer framebuffer = makeFramebuffer(resolution, resolution, kChannelColor);
  PointSet set;
  set.positions = points.positions;
  set.colors = points.colors;
  set.pointSize = size;
  double seconds = 0;
  runWithThreads(threads, [&] {
    seconds = medianSeconds(repeats, [&] {
      clearFramebuffer(framebuffer);
      drawPoints(framebuffer, camera, std::span(&set, 1));
    });
  });
  const double mpoints = double(points.positions.size()) / seconds / 1e6;
  return {{"seconds", seconds}, {"mpoints_per_s", mpoints}, {"threads", resolveThreadCount(threads)},
          {"covered_pixels", coveredPixels(framebuffer)}};
}

nlohmann::json timeLlvmpipePoints(const RandomPoints& points, std::uint32_t resolution, float size, int threads,
                                  int repeats) {
  LlvmpipePeer peer(resolution, resolution, resolveThreadCount(threads));
  if (!peer.available()) return {{"missing", peer.missingReason()}};
  const glm::mat4 clip(pointsCamera(resolution).clipFromWorld());
  const double seconds = medianSeconds(repeats, [&] {
    peer.clear();
    peer.drawPoints(clip, points.positions, points.colors, size);
    peer.finish();
  });
  return {{"seconds", seconds}, {"mpoints_per_s", double(points.positions.size()) / seconds / 1e6},
          {"threads", resolveThreadCount(threads)}, {"covered_pixels", peer.coveredPixels()}};
}

double ratio(const nlohmann::json& slow, const nlohmann::json& fast, const char* key, bool higherIsBetter) {
  if (!slow.contains(key) || !fast.contains(key)) return 0.0;
  const double a = slow[key].get<double>(), b = fast[key].get<double>();
  return higherIsBetter ? b / a : a / b;
}

}  // namespace

nlohmann::json benchRaster(const Scene& scene, const Hierarchy& hierarchy, const RasterBenchOptions& options) {
  const int all = resolveThreadCount(options.threads);
  Bounds box;
  for (std::uint32_t root : scene.roots) box.extend(hierarchy.worldBounds[root]);

  CaptureViews views = makeCaptureViews(box, options.resolution);
  nlohmann::json capture;
  capture["pbs_1_thread"] = timePbsCapture(scene, hierarchy, views, 1, options.repeats);
  capture["pbs"] = timePbsCapture(scene, hierarchy, views, all, options.repeats);
  capture["llvmpipe"] = timeLlvmpipeCapture(scene, hierarchy, views, box, all, options.repeats);
  capture["embree"] = timeEmbreeCapture(scene, hierarchy, views, all, options.repeats);
  capture["pbs_s"] = capture["pbs"]["seconds"];
  capture["llvmpipe_s"] = capture["llvmpipe"].value("seconds", nlohmann::json());
  capture["embree_s"] = capture["embree"]["seconds"];
  capture["vs_llvmpipe"] = ratio(capture["llvmpipe"], capture["pbs"], "seconds", false);
  capture["vs_embree"] = ratio(capture["embree"], capture["pbs"], "seconds", false);
  capture["thread_scaling"] = ratio(capture["pbs_1_thread"], capture["pbs"], "seconds", false);

  const RandomPoints points = makeRandomPoints(options.points);
  nlohmann::json pointsReport;
  for (const float size : {1.0f, 4.0f}) {
    const std::string key = std::to_string(int(size)) + "px";
    nlohmann::json entry;
    entry["pbs_1_thread"] = timePoints(points, options.resolution, size, 1, options.repeats);
    entry["pbs"] = timePoints(points, options.resolution, size, all, options.repeats);
    entry["llvmpipe"] = timeLlvmpipePoints(points, options.resolution, size, all, options.repeats);
    entry["vs_llvmpipe"] = ratio(entry["llvmpipe"], entry["pbs"], "mpoints_per_s", true);
    entry["thread_scaling"] = ratio(entry["pbs_1_thread"], entry["pbs"], "mpoints_per_s", true);
    pointsReport[key] = entry;
  }
  pointsReport["pbs_mpoints_per_s"] = pointsReport["1px"]["pbs"]["mpoints_per_s"];
  pointsReport["llvmpipe_mpoints_per_s"] = pointsReport["1px"]["llvmpipe"].value("mpoints_per_s", nlohmann::json());
  pointsReport["vs_llvmpipe"] = pointsReport["1px"]["vs_llvmpipe"];

  return {{"capture", capture},
          {"points", pointsReport},
          {"threads", all},
          {"resolution", options.resolution},
          {"point_count", options.points},
          {"repeats", options.repeats}};
}

}  // namespace pbs::bench
