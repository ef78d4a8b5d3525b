// Creates Embree objects behind owners, on a device that turns every Embree error into an exception.
#include "embree_handles.hpp"

#include <stdexcept>
#include <string>

namespace pbs {
namespace {

const char* errorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

[[noreturn]] void throwEmbreeError(RTCError code, const char* message) {
  throw std::runtime_error(std::string("Embree: ") + errorName(code) + (message ? std::string(": ") + message : ""));
}

// Embree calls this on the thread of the failing API call, which the exception then leaves.
void onEmbreeError(void*, RTCError code, const char* message) { throwEmbreeError(code, message); }

// Embree calls this before each allocation (bytes > 0) and after each release (bytes < 0); true lets
// it go ahead.
bool onEmbreeMemory(void* user, ssize_t bytes, bool) {
  auto& allocations = *static_cast<EmbreeAllocations*>(user);
  const std::int64_t now = allocations.bytes += std::int64_t(bytes);
  std::int64_t peak = allocations.peakBytes.load();
  while (now > peak && !allocations.peakBytes.compare_exchange_weak(peak, now)) {
  }
  return true;
}

}  // namespace

EmbreeDevice makeEmbreeDevice(EmbreeAllocations& allocations) {
  EmbreeDevice device(rtcNewDevice(nullptr));
  // A device that failed to start has no callback yet: its error is kept for the null device.
  if (!device) throwEmbreeError(rtcGetDeviceError(nullptr), "could not create a device");
  rtcSetDeviceErrorFunction(device.get(), onEmbreeError, nullptr);
  rtcSetDeviceMemoryMonitorFunction(device.get(), onEmbreeMemory, &allocations);
  return device;
}

EmbreeSceneHandle makeEmbreeScene(RTCDevice device, RTCSceneFlags flags) {
  EmbreeSceneHandle scene(rtcNewScene(device));
  rtcSetSceneFlags(scene.get(), flags);
  return scene;
}

EmbreeGeometry makeEmbreeGeometry(RTCDevice device, RTCGeometryType type) {
  return EmbreeGeometry(rtcNewGeometry(device, type));
}

EmbreeDevice shareEmbreeDevice(RTCDevice device) {
  if (device) rtcRetainDevice(device);
  return EmbreeDevice(device);
}

EmbreeSceneHandle shareEmbreeScene(RTCScene scene) {
  if (scene) rtcRetainScene(scene);
  return EmbreeSceneHandle(scene);
}

}  // namespace pbs
