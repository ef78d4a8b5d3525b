// Owners of Embree objects (one release each, never leaked on an exception) and the device whose
// errors throw.
#pragma once

#include <embree3/rtcore.h>

#include <atomic>
#include <cstdint>
#include <memory>

namespace pbs {

struct EmbreeRelease {
  void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
  void operator()(RTCGeometry geometry) const { rtcReleaseGeometry(geometry); }
};

using EmbreeDevice = std::unique_ptr<RTCDeviceTy, EmbreeRelease>;
using EmbreeSceneHandle = std::unique_ptr<RTCSceneTy, EmbreeRelease>;
using EmbreeGeometry = std::unique_ptr<RTCGeometryTy, EmbreeRelease>;

// What Embree holds on a device (BVHs, its copies of vertex buffers), as its memory monitor reports
// each allocation and release.
struct EmbreeAllocations {
  std::atomic<std::int64_t> bytes{0};
  std::atomic<std::int64_t> peakBytes{0};
};

// A device whose error callback throws std::runtime_error("Embree: <code>: <message>") out of the
// failing API call, and whose allocations are counted in `allocations` (which must outlive it).
EmbreeDevice makeEmbreeDevice(EmbreeAllocations& allocations);

EmbreeSceneHandle makeEmbreeScene(RTCDevice device, RTCSceneFlags flags);
EmbreeGeometry makeEmbreeGeometry(RTCDevice device, RTCGeometryType type);

// A second owner of an existing object: Embree counts references, so each owner releases its own.
EmbreeDevice shareEmbreeDevice(RTCDevice device);
EmbreeSceneHandle shareEmbreeScene(RTCScene scene);

}  // namespace pbs
