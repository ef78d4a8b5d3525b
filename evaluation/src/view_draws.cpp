// drawView: a view's draws, ordered by time.
#include "pbs/evaluation/view_draws.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace pbs {

ViewDraws drawView(FrameRenderer& renderer, const Camera& camera, int draws,
                   const std::function<double(const FrameResult&)>& time) {
  ViewDraws result{.first = renderer.render(camera), .byTime = {}};
  // The first draw's image set aside while it is copied, so that no draw's image is copied.
  std::vector<glm::vec4> image = std::move(result.first.image);
  std::vector<std::uint8_t> rgba8 = std::move(result.first.rgba8);
  result.byTime.push_back(result.first);
  result.first.image = std::move(image);
  result.first.rgba8 = std::move(rgba8);
  for (int draw = 1; draw < draws; ++draw) {
    FrameResult frame = renderer.render(camera);
    // Released, not only emptied: a kept image's memory would make each later draw fault in a new one.
    frame.image = std::vector<glm::vec4>();
    frame.rgba8 = std::vector<std::uint8_t>();
    result.byTime.push_back(std::move(frame));
  }
  std::stable_sort(result.byTime.begin(), result.byTime.end(),
                   [&](const FrameResult& a, const FrameResult& b) { return time(a) < time(b); });
  return result;
}

}  // namespace pbs
