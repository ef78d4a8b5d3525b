// Per-camera set-up of the Embree caster's rays: windowRay's inverses, computed once.
#include "embree_rays.hpp"

namespace pbs {

WindowRays::WindowRays(const Camera& camera)
    : xScale_(2.0 / camera.width),
      yScale_(2.0 / camera.height),
      orthographic_(camera.isOrthographic()),
      worldFromClip_(glm::inverse(camera.clipFromWorld())),
      nearColumn_(worldFromClip_[3] - worldFromClip_[2]),
      farColumn_(worldFromClip_[3] + worldFromClip_[2]),
      eye_(glm::inverse(camera.view)[3]) {}

}  // namespace pbs
