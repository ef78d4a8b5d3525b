// Owners of Embree objects (one release each, never leaked on an exception) and the device whose
// errors throw.
#pragma once

#include <embree3/rtcore.h>

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

// A device whose error callback throws std::runtime_error("Embree: <code>: <message>") out of the
// failing API call.
EmbreeDevice makeEmbreeDevice();

EmbreeSceneHandle makeEmbreeScene(RTCDevice device, RTCSceneFlags flags);
EmbreeGeometry makeEmbreeGeometry(RTCDevice device, RTCGeometryType type);

// A second owner of an existing object: Embree counts references, so each owner releases its own.
EmbreeDevice shareEmbreeDevice(RTCDevice device);
EmbreeSceneHandle shareEmbreeScene(RTCScene scene);

}  // namespace pbs
