// One view drawn several times by one renderer, for a time that is not one draw's noise: what `pbs eval`,
// `pbs calibrate` and `pbs demo` time their frames with.
#pragma once

#include <pbs/raster/camera.hpp>
#include <pbs/surfels/frame_renderer.hpp>

#include <functional>
#include <vector>

namespace pbs {

struct ViewDraws {
  FrameResult first;                // the first draw whole: its image, and what it read and built
  std::vector<FrameResult> byTime;  // every draw (the first too) without its image, fastest first
};

// Draws `camera` `draws` times (at least once) with `renderer`, one draw after the other, and orders the
// draws by `time` (stable: equal times keep their order). Later draws find what the first read and built
// in place, as the frames after it on a path would.
ViewDraws drawView(FrameRenderer& renderer, const Camera& camera, int draws,
                   const std::function<double(const FrameResult&)>& time);

}  // namespace pbs
