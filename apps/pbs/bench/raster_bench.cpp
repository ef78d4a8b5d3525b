// The raster benchmark: pbs and its peers timed in interleaved rounds of the same run (medians, and
// ratios round by round), with a coverage count next to every timing so a peer that drew nothing
// cannot look fast.
#include "raster_bench.hpp"

#include "llvmpipe_peer.hpp"
#include "timing.hpp"

#include <pbs/raster/box_view.hpp>
#include <pbs/raster/points.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/embree_caster.hpp>
#include <pbs/scene/scene_draws.hpp>
#include <pbs/surfels/capture.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <optional>
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
  CaptureViews views{captureCameras(box, resolution), {}};
  for (const Camera& camera : views.cameras)
    views.framebuffers.push_back(makeFramebuffer(camera.width, camera.height, kCaptureChannels, box.center()));
  return views;
}

// The smallest rectangle holding both.
PixelRect enclosing(const PixelRect& a, const PixelRect& b) {
  return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

// Seconds of one run of `work` inside an arena of `threads` workers.
template <typename Work>
double timedOnThreads(int threads, Work&& work) {
  double seconds = 0.0;
  runWithThreads(threads, [&] { seconds = timedRun(work); });
  return seconds;
}

// What pbs's capture draws of the scene: every node, each mesh's sides as its meshClosure says (captureNode).
struct CaptureDraws {
  explicit CaptureDraws(const Scene& scene) : nodes(scene.nodes.size()), closures(meshClosures(scene)) {
    std::iota(nodes.begin(), nodes.end(), 0u);
  }
  std::vector<std::uint32_t> nodes;
  std::vector<MeshClosure> closures;
};

// pbs: the eight views into depth + colour + position + normal, each time after clearing depth,
// as the capture does (captureBox): the other channels are read only where a pixel is covered; as many views at
// once as it draws.
void drawPbsViews(const Scene& scene, const Hierarchy& hierarchy, const CaptureDraws& draws, CaptureViews& views) {
  const std::size_t count = views.cameras.size();
  drawViewsInGroups(count, concurrentCaptureViews(count, views.framebuffers.at(0).pixelCount()), [&](std::size_t v) {
    clearFramebuffer(views.framebuffers[v], 0);
    drawNodeTriangles(scene, hierarchy, draws.nodes, views.cameras[v], views.framebuffers[v], {}, draws.closures);
  });
}

std::uint64_t coveredPixels(const CaptureViews& views) {
  std::uint64_t covered = 0;
  for (const Framebuffer& framebuffer : views.framebuffers) covered += coveredPixels(framebuffer);
  return covered;
}

// The share of the pixels both pbs and llvmpipe cover (llvmpipe's position not NaN) for which `agrees(i)`.
template <typename Agrees>
double shareAgreeing(const Framebuffer& pbs, const std::vector<glm::vec3>& llvmpipePositions, Agrees&& agrees) {
  std::uint64_t both = 0, agree = 0;
  for (std::size_t i = 0; i < pbs.pixelCount(); ++i) {
    if (!pbs.covered(i) || std::isnan(llvmpipePositions[i].x)) continue;
    ++both;
    agree += agrees(i);
  }
  return both > 0 ? double(agree) / double(both) : 0.0;
}

// Positions within 1e-4 of the box's diagonal: evidence that llvmpipe fills the same position channel, not just
// covers the same pixels. Pixels on silhouettes and shared edges may go to different triangles.
double positionAgreement(const Framebuffer& pbs, const std::vector<glm::vec3>& llvmpipe, const Bounds& box) {
  const float tolerance = float(1e-4 * glm::length(box.max - box.min));
  return shareAgreeing(pbs, llvmpipe,
                       [&](std::size_t i) { return glm::length(pbs.position[i] - llvmpipe[i]) <= tolerance; });
}

// Colours within 4 of 255 in every channel: evidence that llvmpipe samples the textures pbs samples (its level of
// detail and filtering differ in the last bits).
double colorAgreement(const Framebuffer& pbs, const std::vector<glm::u8vec4>& llvmpipe,
                      const std::vector<glm::vec3>& llvmpipePositions) {
  return shareAgreeing(pbs, llvmpipePositions, [&](std::size_t i) {
    const glm::ivec4 difference = glm::abs(glm::ivec4(pbs.color[i]) - glm::ivec4(llvmpipe[i]));
    return glm::all(glm::lessThanEqual(difference, glm::ivec4(4)));
  });
}

// llvmpipe filling the same channels as pbs's capture: depth, base colour (textured where the material
// is, with the texture's filters and wrap modes), world position and normal.
class LlvmpipeCapture {
 public:
  LlvmpipeCapture(const Scene& scene, const CaptureViews& views, int threads)
      : LlvmpipeCapture(views, largestViewport(views), threads) {
    if (!available_) return;
    // Uploaded before any timing, as Embree's BVH is built before its.
    for (const Texture& texture : scene.textures)
      textureNames_.push_back(isSampleable(texture) ? peer_.uploadTexture(texture) : 0);
  }
  bool available() const { return available_; }
  const std::string& missingReason() const { return peer_.missingReason(); }

  // Draws the eight views; each is timed up to glFinish, and reading its depth back to count its
  // coverage is left out of the time, as pbs's count is.
  double run(const Scene& scene, const Hierarchy& hierarchy, const CaptureDraws& draws) {
    covered_ = 0;
    double drawing = 0.0;
    for (std::size_t v = 0; v < views_.cameras.size(); ++v) {
      drawing += timedRun([&] { drawView(scene, hierarchy, draws, v); });
      covered_ += peer_.coveredPixels();
    }
    return drawing;
  }
  std::uint64_t covered() const { return covered_; }
  // The position and colour channels of the view drawn last.
  std::vector<glm::vec3> positions() { return peer_.capturePositions(); }
  std::vector<glm::u8vec4> colors() { return peer_.captureColors(); }

 private:
  LlvmpipeCapture(const CaptureViews& views, glm::uvec2 context, int threads)
      : views_(views), peer_(context.x, context.y, threads) {
    available_ = peer_.available() && peer_.useCaptureGBuffer();
  }

  // One context as large as the largest view; each view draws into its own viewport size.
  static glm::uvec2 largestViewport(const CaptureViews& views) {
    glm::uvec2 largest(0);
    for (const Camera& camera : views.cameras) largest = glm::max(largest, glm::uvec2(camera.width, camera.height));
    return largest;
  }

  // The faces pbs's capture draws (CaptureDraws), culled the same way.
  void drawView(const Scene& scene, const Hierarchy& hierarchy, const CaptureDraws& draws, std::size_t v) {
    const Camera& camera = views_.cameras[v];
    peer_.setViewport(camera.width, camera.height);
    peer_.clearDepth();
    const glm::dmat4 clipFromWorld = camera.clipFromWorld();
    const glm::dmat4 positionFromWorld = glm::translate(glm::dmat4(1.0), -views_.framebuffers[v].positionOrigin);
    for (std::uint32_t n : hierarchy.preorder) {
      const Node& node = scene.nodes[n];
      if (node.mesh < 0) continue;
      const Mesh& mesh = scene.meshes[std::size_t(node.mesh)];
      const glm::dmat4& world = hierarchy.world[n];
      const glm::mat3 normalFromObject(glm::transpose(glm::inverse(glm::dmat3(world))));
      const MeshClosure& closure = draws.closures[std::size_t(node.mesh)];
      const FaceSides sides = visibleSides(closure.facing);
      const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
      // The hidden side, where a hole may show it: pbs tests each triangle's box against each hole's, in setup;
      // llvmpipe draws that side once more, scissored to the box around every hole's.
      std::optional<PixelRect> throughHoles;
      for (const Bounds& hole : closure.holes) {
        const PixelRect r = holePixels(camera, clipFromWorld * world, hole);
        throughHoles = throughHoles ? enclosing(*throughHoles, r) : r;
      }
      const FaceSides hidden = sides == FaceSides::front ? FaceSides::back : FaceSides::front;
      for (const MeshPart& part : mesh.parts) {
        const Material* material = part.material < scene.materials.size() ? &scene.materials[part.material] : nullptr;
        const glm::vec4 color = material ? material->baseColorFactor : glm::vec4(1.0f);
        const std::int32_t texture = material ? material->baseColorTexture : -1;
        const auto drawSide = [&](FaceSides side) {
          peer_.drawCaptureTriangles(
              glm::mat4(clipFromWorld * world), glm::mat4(positionFromWorld * world), normalFromObject, color,
              mesh.positions, mesh.normals, std::span(mesh.indices).subspan(part.firstIndex, part.indexCount), mesh.uvs,
              texture >= 0 && std::size_t(texture) < textureNames_.size() ? textureNames_[std::size_t(texture)] : 0u,
              side, mirrored);
        };
        drawSide(sides);
        if (!throughHoles) continue;
        peer_.setScissor(throughHoles);
        drawSide(hidden);
        peer_.setScissor(std::nullopt);
      }
    }
    peer_.finish();
  }

  const CaptureViews& views_;
  LlvmpipePeer peer_;
  std::vector<std::uint32_t> textureNames_;  // per scene texture, 0 where it cannot be sampled
  bool available_ = false;
  std::uint64_t covered_ = 0;
};

nlohmann::json timingEntry(const std::vector<double>& rounds, int threads, std::uint64_t covered) {
  return {{"seconds", median(rounds)}, {"threads", threads}, {"covered_pixels", covered}};
}

}  // namespace

// pbs and Embree share the framebuffers: coverage is counted from one more, untimed run of each
// after the rounds.
nlohmann::json benchCapture(const Scene& scene, const Hierarchy& hierarchy, const RasterBenchOptions& options) {
  const Bounds box = sceneBounds(scene, hierarchy);
  const int all = resolveThreadCount(options.threads);
  CaptureViews views = makeCaptureViews(box, options.resolution);
  const CaptureDraws draws(scene);  // once per mesh, as surfelize's scan finds it (Embree's BVH is built apart too)
  const auto pbsRun = [&](int threads) {
    return [&, threads] { return timedOnThreads(threads, [&] { drawPbsViews(scene, hierarchy, draws, views); }); };
  };
  std::optional<EmbreeScene> embree;
  double bvhSeconds = 0.0;
  runWithThreads(all, [&] { bvhSeconds = timedRun([&] { embree.emplace(scene, hierarchy); }); });
  // render overwrites every pixel (a miss with the cleared values): no separate clear to time.
  const auto embreeRun = [&] {
    return timedOnThreads(all, [&] {
      for (std::size_t v = 0; v < views.cameras.size(); ++v) embree->render(views.cameras[v], views.framebuffers[v]);
    });
  };
  LlvmpipeCapture llvmpipe(scene, views, all);
  std::vector<std::function<double()>> runs = {pbsRun(1), pbsRun(all), embreeRun};
  if (llvmpipe.available()) runs.push_back([&] { return llvmpipe.run(scene, hierarchy, draws); });
  const auto rounds = interleavedRounds(runs, options.repeats);

  nlohmann::json capture;
  embreeRun();
  capture["embree"] = timingEntry(rounds[2], all, coveredPixels(views));
  capture["embree"]["bvh_seconds"] = bvhSeconds;
  pbsRun(1)();
  capture["pbs_1_thread"] = timingEntry(rounds[0], 1, coveredPixels(views));
  pbsRun(all)();
  capture["pbs"] = timingEntry(rounds[1], all, coveredPixels(views));
  if (llvmpipe.available()) {
    capture["llvmpipe"] = timingEntry(rounds[3], all, llvmpipe.covered());
    capture["llvmpipe"]["channels"] = "depth, colour, position, normal";
    const std::vector<glm::vec3> positions = llvmpipe.positions();
    capture["llvmpipe"]["position_agreement"] = positionAgreement(views.framebuffers.back(), positions, box);
    capture["llvmpipe"]["color_agreement"] = colorAgreement(views.framebuffers.back(), llvmpipe.colors(), positions);
    capture["vs_llvmpipe"] = medianRatio(rounds[3], rounds[1]);
  } else {
    capture["llvmpipe"] = {{"missing", llvmpipe.missingReason()}};
    capture["vs_llvmpipe"] = nullptr;
  }
  capture["pbs_s"] = capture["pbs"]["seconds"];
  capture["llvmpipe_s"] = capture["llvmpipe"].value("seconds", nlohmann::json());
  capture["embree_s"] = capture["embree"]["seconds"];
  capture["vs_embree"] = medianRatio(rounds[2], rounds[1]);
  capture["thread_scaling"] = medianRatio(rounds[0], rounds[1]);
  return capture;
}

namespace {

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

// `points` random points of one size by pbs on one thread and on all, and by llvmpipe's GL_POINTS,
// in interleaved rounds; pbs draws into a framebuffer of its own per thread count.
nlohmann::json benchPoints(const RandomPoints& points, const RasterBenchOptions& options, float size) {
  const int all = resolveThreadCount(options.threads);
  const std::uint32_t resolution = options.resolution;
  const Camera camera = pointsCamera(resolution);
  PointSet set;
  set.positions = points.positions;
  set.colors = points.colors;
  set.pointSize = size;
  Framebuffer single = makeFramebuffer(resolution, resolution, kChannelColor);
  Framebuffer multi = makeFramebuffer(resolution, resolution, kChannelColor);
  const auto pbsRun = [&](Framebuffer& framebuffer, int threads) {
    return [&, threads] {
      return timedOnThreads(threads, [&] {
        clearFramebuffer(framebuffer);
        drawPoints(framebuffer, camera, std::span(&set, 1));
      });
    };
  };
  LlvmpipePeer llvmpipe(resolution, resolution, all);
  const glm::mat4 clip(camera.clipFromWorld());
  std::vector<std::function<double()>> runs = {pbsRun(single, 1), pbsRun(multi, all)};
  if (llvmpipe.available())
    runs.push_back([&] {
      return timedRun([&] {
        llvmpipe.clear();
        llvmpipe.drawPoints(clip, points.positions, points.colors, size);
        llvmpipe.finish();
      });
    });
  const auto rounds = interleavedRounds(runs, options.repeats);

  const double count = double(points.positions.size());
  const auto entry = [&](const std::vector<double>& seconds, int threads, std::uint64_t covered) {
    nlohmann::json json = timingEntry(seconds, threads, covered);
    json["mpoints_per_s"] = count / median(seconds) / 1e6;
    return json;
  };
  nlohmann::json report;
  report["pbs_1_thread"] = entry(rounds[0], 1, coveredPixels(single));
  report["pbs"] = entry(rounds[1], all, coveredPixels(multi));
  report["thread_scaling"] = medianRatio(rounds[0], rounds[1]);
  if (llvmpipe.available()) {
    report["llvmpipe"] = entry(rounds[2], all, llvmpipe.coveredPixels());
    report["vs_llvmpipe"] = medianRatio(rounds[2], rounds[1]);
  } else {
    report["llvmpipe"] = {{"missing", llvmpipe.missingReason()}};
    report["vs_llvmpipe"] = nullptr;
  }
  return report;
}

}  // namespace

Bounds sceneBounds(const Scene& scene, const Hierarchy& hierarchy) {
  Bounds box;
  for (std::uint32_t root : scene.roots) box.extend(hierarchy.worldBounds[root]);
  return box;
}

std::vector<Camera> captureCameras(const Bounds& box, std::uint32_t resolution) {
  std::vector<Camera> cameras;
  for (const glm::dvec3& direction : boxCornerDirections())
    cameras.push_back(boxViewCamera(box, direction, resolution));
  return cameras;
}

nlohmann::json benchRaster(const Scene& scene, const Hierarchy& hierarchy, const RasterBenchOptions& options) {
  const nlohmann::json capture = benchCapture(scene, hierarchy, options);

  const RandomPoints points = makeRandomPoints(options.points);
  nlohmann::json pointsReport;
  for (const float size : {1.0f, 4.0f})
    pointsReport[std::to_string(int(size)) + "px"] = benchPoints(points, options, size);
  pointsReport["pbs_mpoints_per_s"] = pointsReport["1px"]["pbs"]["mpoints_per_s"];
  pointsReport["llvmpipe_mpoints_per_s"] = pointsReport["1px"]["llvmpipe"].value("mpoints_per_s", nlohmann::json());
  pointsReport["vs_llvmpipe"] = pointsReport["1px"]["vs_llvmpipe"];

  return {{"capture", capture},
          {"points", pointsReport},
          {"threads", resolveThreadCount(options.threads)},
          {"resolution", options.resolution},
          {"point_count", options.points},
          {"repeats", options.repeats},
          {"timing", kInterleavedTiming}};
}

}  // namespace pbs::bench
