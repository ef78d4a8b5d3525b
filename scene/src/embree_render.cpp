// Casting a camera's rays at a top-level Embree scene: coherent 16-ray packets over 4×4 pixel blocks,
// rows of blocks in parallel.
#include "embree_instances.hpp"
#include "embree_rays.hpp"
#include "pbs/raster/simd_clones.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace pbs {
namespace {

constexpr std::uint32_t kLanes = kRayBlock * kRayBlock;

// The lanes of one block's packet that cast a ray (-1, as rtcIntersect16 reads them) and those inside the window.
struct BlockLanes {
  alignas(64) int valid[kLanes];
  alignas(64) int inWindow[kLanes];  // int, not bool, as the other lanes' values: then the lanes vectorise alike
};

// Conditions are ints, 1 or 0, combined with & rather than &&: no branch, so the lanes' loop vectorises.
PBS_CLONE_INLINE int finite(double x, double y, double z) {
  return int(std::isfinite(x)) & int(std::isfinite(y)) & int(std::isfinite(z));
}

// The rays of block (bx, by), one per pixel centre, into `packet`. A lane casts where its pixel lies in the
// window and its ray is finite with a visible stretch: a camera whose volume has no extent (a zero-size capture
// view) gives rays of no direction (NaN or infinite), which hit nothing, and Embree must never see them. Lanes
// that cast nothing get zeros, never garbage, which Embree's coherent traversal was seen to trip on (an assertion
// in its kernels). One loop over the lanes without branches, so that each clone does their double arithmetic in
// vector lanes: the same IEEE operations as one lane at a time (no contraction: -ffp-contract=off), the same rays.
// Made one lane at a time, the rays took a third of an Embree capture's time (its views' rays mostly miss).
template <bool Orthographic>
PBS_CLONE_INLINE void blockRaysOf(const WindowRays& rays, const Camera& camera, const glm::dvec3& frameOrigin,
                                  std::uint32_t bx, std::uint32_t by, RTCRayHit16& packet, BlockLanes& lanes) {
  // Read before the loop, so that no lane's condition guards a load.
  const int width = int(std::min<std::uint32_t>(camera.width, INT32_MAX));
  const int height = int(std::min<std::uint32_t>(camera.height, INT32_MAX));
  const double frameX = frameOrigin.x, frameY = frameOrigin.y, frameZ = frameOrigin.z;
  for (std::uint32_t lane = 0; lane < kLanes; ++lane) {
    // Signed: integers convert to double in vector lanes without AVX-512 only from signed ones.
    const int px = int(bx * kRayBlock + lane % kRayBlock);
    const int py = int(by * kRayBlock + lane / kRayBlock);
    const RaySegment ray = rays.at<Orthographic>(px + 0.5, py + 0.5);
    const int inWindow = int(px < width) & int(py < height);
    const int cast = inWindow & int(ray.tNear <= ray.tFar) & finite(ray.originX, ray.originY, ray.originZ) &
                     finite(ray.directionX, ray.directionY, ray.directionZ);
    lanes.inWindow[lane] = inWindow;
    lanes.valid[lane] = -cast;
    packet.ray.org_x[lane] = cast ? float(ray.originX - frameX) : 0.0f;
    packet.ray.org_y[lane] = cast ? float(ray.originY - frameY) : 0.0f;
    packet.ray.org_z[lane] = cast ? float(ray.originZ - frameZ) : 0.0f;
    packet.ray.dir_x[lane] = cast ? float(ray.directionX) : 0.0f;
    packet.ray.dir_y[lane] = cast ? float(ray.directionY) : 0.0f;
    packet.ray.dir_z[lane] = cast ? float(ray.directionZ) : 0.0f;
    packet.ray.tnear[lane] = cast ? float(ray.tNear) : 0.0f;
    packet.ray.tfar[lane] = cast ? float(ray.tFar) : 0.0f;
    packet.ray.time[lane] = 0.0f;
    packet.ray.mask[lane] = 0xffffffffu;
    packet.ray.flags[lane] = 0;
    packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
    packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
  }
}

PBS_AVX512_CLONES
void blockRays(const WindowRays& rays, const Camera& camera, const glm::dvec3& frameOrigin, std::uint32_t bx,
               std::uint32_t by, RTCRayHit16& packet, BlockLanes& lanes) {
  if (rays.orthographic())
    blockRaysOf<true>(rays, camera, frameOrigin, bx, by, packet, lanes);
  else
    blockRaysOf<false>(rays, camera, frameOrigin, bx, by, packet, lanes);
}

}  // namespace

void castRays(const EmbreeInstances& instances, const Camera& camera, Framebuffer& framebuffer) {
  if (framebuffer.width != camera.width || framebuffer.height != camera.height)
    throw std::invalid_argument("Embree rays: the framebuffer is not the size of the camera's viewport");
  const ShadingView view(camera);
  const WindowRays rays(camera);
  const std::uint32_t blocksX = (camera.width + kRayBlock - 1) / kRayBlock;
  const std::uint32_t blocksY = (camera.height + kRayBlock - 1) / kRayBlock;
  const std::vector<std::uint8_t> castBlocks = footprintBlocks(camera, instances.footprint);

  // Every pixel depends on its own ray only, so any split of the rows gives the same image.
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, blocksY), [&](const tbb::blocked_range<std::uint32_t>& rows) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    RTCRayHit16 packet{};
    BlockLanes lanes;
    InstanceMatrices matrices(view);

    for (std::uint32_t by = rows.begin(); by != rows.end(); ++by) {
      const std::uint8_t* castRow = castBlocks.data() + std::size_t(by) * blocksX;
      for (std::uint32_t bx = 0; bx < blocksX; ++bx) {
        const auto pixel = [&](std::uint32_t lane) {
          return std::size_t(by * kRayBlock + lane / kRayBlock) * camera.width + bx * kRayBlock + lane % kRayBlock;
        };
        if (!castRow[bx]) {
          // A run of blocks no instance shows in is cleared row by row, as a miss clears it.
          std::uint32_t end = bx + 1;
          while (end < blocksX && !castRow[end]) ++end;
          const std::uint32_t x0 = bx * kRayBlock, x1 = std::min(end * kRayBlock, camera.width);
          for (std::uint32_t py = by * kRayBlock; py < std::min(by * kRayBlock + kRayBlock, camera.height); ++py)
            clearMissedPixels(framebuffer, std::size_t(py) * camera.width + x0, x1 - x0);
          bx = end - 1;
          continue;
        }
        blockRays(rays, camera, instances.origin, bx, by, packet, lanes);
        rtcIntersect16(lanes.valid, instances.top.get(), &context, &packet);
        const auto hit = [&](std::uint32_t lane) {
          return lanes.valid[lane] && packet.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID;
        };
        // The hit triangles lie scattered over their meshes: their indices are fetched for every lane before any is
        // shaded, so that the lanes wait for memory together (7 % of horse's Embree capture; fetching the vertices
        // too, a stage later, bought nothing more).
        for (std::uint32_t lane = 0; lane < kLanes; ++lane)
          if (hit(lane)) prefetchHitIndices(instances.shaded[packet.hit.instID[0][lane]], packet.hit.primID[lane]);
        for (std::uint32_t lane = 0; lane < kLanes; ++lane) {
          if (!lanes.inWindow[lane]) continue;
          if (!hit(lane)) {
            clearMissedPixels(framebuffer, pixel(lane), 1);
            continue;
          }
          shadeHit(view, instances.shaded[packet.hit.instID[0][lane]], matrices, packet.hit.primID[lane],
                   packet.hit.u[lane], packet.hit.v[lane], framebuffer, pixel(lane));
        }
      }
    }
  });
}

}  // namespace pbs
