// Casting a camera's rays at a top-level Embree scene: coherent 16-ray packets over 4×4 pixel blocks,
// rows of blocks in parallel.
#include "embree_instances.hpp"
#include "embree_rays.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <stdexcept>

namespace pbs {
namespace {

bool finiteRay(const Ray& ray) {
  const auto finite = [](const glm::dvec3& v) { return !glm::any(glm::isnan(v)) && !glm::any(glm::isinf(v)); };
  return finite(ray.origin) && finite(ray.direction);
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
    // Lanes left invalid still hold whatever they held: zeros or an earlier block's valid rays, never
    // garbage, which Embree's coherent traversal was seen to trip on (an assertion in its kernels).
    RTCRayHit16 packet{};
    alignas(64) int valid[16];
    std::size_t pixels[16];
    InstanceMatrices matrices(view);

    for (std::uint32_t by = rows.begin(); by != rows.end(); ++by) {
      for (std::uint32_t bx = 0; bx < blocksX; ++bx) {
        if (!castBlocks[std::size_t(by) * blocksX + bx]) {
          for (std::uint32_t py = by * kRayBlock; py < std::min(by * kRayBlock + kRayBlock, camera.height); ++py)
            for (std::uint32_t px = bx * kRayBlock; px < std::min(bx * kRayBlock + kRayBlock, camera.width); ++px)
              clearMissedPixel(framebuffer, std::size_t(py) * camera.width + px);
          continue;
        }
        for (std::uint32_t lane = 0; lane < 16; ++lane) {
          const std::uint32_t px = bx * kRayBlock + lane % kRayBlock;
          const std::uint32_t py = by * kRayBlock + lane / kRayBlock;
          valid[lane] = 0;
          if (px >= camera.width || py >= camera.height) continue;
          pixels[lane] = std::size_t(py) * camera.width + px;
          const RaySegment segment = rays.at(px + 0.5, py + 0.5);
          // A camera whose volume has no extent (a zero-size capture view) gives rays of no direction
          // (NaN or infinite): they hit nothing, and Embree must never see them.
          if (!(segment.tNear <= segment.tFar) || !finiteRay(segment.ray)) {
            clearMissedPixel(framebuffer, pixels[lane]);
            continue;
          }
          valid[lane] = -1;
          const Ray& ray = segment.ray;
          const glm::vec3 origin(ray.origin - instances.origin);
          packet.ray.org_x[lane] = origin.x;
          packet.ray.org_y[lane] = origin.y;
          packet.ray.org_z[lane] = origin.z;
          packet.ray.dir_x[lane] = float(ray.direction.x);
          packet.ray.dir_y[lane] = float(ray.direction.y);
          packet.ray.dir_z[lane] = float(ray.direction.z);
          packet.ray.tnear[lane] = float(segment.tNear);
          packet.ray.tfar[lane] = float(segment.tFar);
          packet.ray.time[lane] = 0.0f;
          packet.ray.mask[lane] = 0xffffffffu;
          packet.ray.flags[lane] = 0;
          packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
          packet.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, instances.top.get(), &context, &packet);
        for (std::uint32_t lane = 0; lane < 16; ++lane) {
          if (!valid[lane]) continue;
          if (packet.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) {
            clearMissedPixel(framebuffer, pixels[lane]);
            continue;
          }
          shadeHit(view, instances.shaded[packet.hit.instID[0][lane]], matrices, packet.hit.primID[lane],
                   packet.hit.u[lane], packet.hit.v[lane], framebuffer, pixels[lane]);
        }
      }
    }
  });
}

}  // namespace pbs
