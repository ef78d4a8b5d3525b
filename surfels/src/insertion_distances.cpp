// insertionDistances: how far each point of an order lands from the points placed before it.
#include "pbs/surfels/prefilter_colors.hpp"

#include "order_nearest_grid.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace pbs {

std::vector<float> insertionDistances(std::span<const glm::vec3> points, std::span<const std::uint32_t> order) {
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (order[i] >= points.size()) {
      throw std::invalid_argument("insertionDistances: order entry " + std::to_string(i) + " names point " +
                                  std::to_string(order[i]) + " of " + std::to_string(points.size()));
    }
  }
  std::vector<float> distances(order.size());
  if (order.empty()) return distances;
  // The grid the dart ordering uses: built for the whole point set, filled in the order's order.
  NearestPointGrid chosen(points, "insertionDistances");
  for (std::size_t i = 0; i < order.size(); ++i) {
    distances[i] = std::sqrt(chosen.nearestSquared(points[order[i]]));
    chosen.insert(order[i]);
  }
  return distances;
}

}  // namespace pbs
