// The orderings by name: one switch for every option parser and file reader.
#include "pbs/surfels/ordering.hpp"

namespace pbs {

std::string_view orderingName(SurfelOrdering ordering) {
  switch (ordering) {
    case SurfelOrdering::Farthest: return "farthest";
    case SurfelOrdering::Dart: return "dart";
    case SurfelOrdering::Random: return "random";
  }
  return "unknown";
}

std::optional<SurfelOrdering> parseOrdering(std::string_view name) {
  for (SurfelOrdering ordering : {SurfelOrdering::Farthest, SurfelOrdering::Dart, SurfelOrdering::Random})
    if (orderingName(ordering) == name) return ordering;
  return std::nullopt;
}

std::vector<std::uint32_t> orderPoints(SurfelOrdering ordering, std::span<const glm::vec3> points, std::uint32_t max,
                                       std::uint64_t seed) {
  switch (ordering) {
    case SurfelOrdering::Farthest: return orderFarthest(points, max, seed);
    case SurfelOrdering::Dart: return orderDart(points, max, seed);
    case SurfelOrdering::Random: return orderRandom(points, max, seed);
  }
  return {};
}

}  // namespace pbs
