// The orderings by name: one switch for every option parser and file reader.
#include "pbs/surfels/ordering.hpp"

#include "pbs/raster/value_names.hpp"

namespace pbs {

namespace {

constexpr ValueNames<SurfelOrdering, 3> kOrderingNames{
    {{{SurfelOrdering::Farthest, "farthest"}, {SurfelOrdering::Dart, "dart"}, {SurfelOrdering::Random, "random"}}}};

}  // namespace

std::string_view orderingName(SurfelOrdering ordering) { return kOrderingNames.name(ordering); }

std::optional<SurfelOrdering> parseOrdering(std::string_view name) { return kOrderingNames.parse(name); }

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
