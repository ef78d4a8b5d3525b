// planShards: the arrays of a surfelize plan split into shards balanced by estimated cost.
#include "surfelize_shards.hpp"

#include "pbs/raster/hash64.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace pbs::detail {
namespace {

// Measured on the default scene at the default options, one thread of the 2-core machine (406 arrays,
// 43 s; docs/cluster.md): a capture's fixed part is about 0.061 s at 512² pixels × 8 views, and a
// captured triangle adds 1.66 µs (median error of the fit 11 %).
constexpr double kSecondsPerCapturePixel = 0.0615 / (512.0 * 512.0 * 8.0);
constexpr double kSecondsPerPrimitive = 1.66e-6;

// `root` and every array its capture draws, transitively, marked in `inUnit` and listed in `unit`.
void collectUnit(const SurfelPlan& plan, std::uint32_t root, std::vector<bool>& inUnit,
                 std::vector<std::uint32_t>& unit) {
  std::vector<std::uint32_t> stack{root};
  while (!stack.empty()) {
    const std::uint32_t a = stack.back();
    stack.pop_back();
    if (inUnit[a]) continue;
    inUnit[a] = true;
    unit.push_back(a);
    for (std::uint32_t child : plan.childArrays[a]) stack.push_back(child);
  }
}

}  // namespace

double estimatedArraySeconds(const SurfelizeOptions& options, std::uint64_t primitivesDrawn) {
  const double pixels = double(options.file.resolution) * options.file.resolution * options.file.directions;
  return kSecondsPerCapturePixel * pixels + kSecondsPerPrimitive * double(primitivesDrawn);
}

ShardPlan planShards(const SurfelPlan& plan, const SurfelizeOptions& options, std::uint32_t count) {
  if (count == 0) throw std::invalid_argument("a shard plan needs at least one shard");
  const std::size_t arrays = plan.representative.size();
  ShardPlan shards;
  shards.count = count;
  shards.arraySeconds.resize(arrays);
  for (std::size_t a = 0; a < arrays; ++a)
    shards.arraySeconds[a] = estimatedArraySeconds(options, plan.primitivesDrawn[a]);

  // Units: the arrays no capture draws, each with what its capture needs.
  std::vector<bool> drawn(arrays, false);
  for (const std::vector<std::uint32_t>& children : plan.childArrays)
    for (std::uint32_t child : children) drawn[child] = true;
  struct Unit {
    std::vector<std::uint32_t> arrays;
    double seconds = 0.0;
  };
  std::vector<Unit> units;
  std::vector<bool> inUnit(arrays, false);  // cleared after each unit
  for (std::uint32_t a = 0; a < arrays; ++a) {
    if (drawn[a]) continue;
    Unit unit;
    collectUnit(plan, a, inUnit, unit.arrays);
    for (std::uint32_t u : unit.arrays) inUnit[u] = false;
    std::sort(unit.arrays.begin(), unit.arrays.end());
    for (std::uint32_t u : unit.arrays) unit.seconds += shards.arraySeconds[u];
    units.push_back(std::move(unit));
  }
  std::stable_sort(units.begin(), units.end(), [](const Unit& x, const Unit& y) { return x.seconds > y.seconds; });

  constexpr std::uint32_t kUnowned = ~std::uint32_t(0);
  shards.owner.assign(arrays, kUnowned);
  shards.shardSeconds.assign(count, 0.0);
  // Per array: the shards that make it, ascending. Few: an array is made again only where another unit
  // needs it, so this stays the size of the plan, not shards × arrays.
  std::vector<std::vector<std::uint32_t>> makers(arrays);
  const auto makes = [&](std::uint32_t s, std::uint32_t a) {
    return std::binary_search(makers[a].begin(), makers[a].end(), s);
  };
  for (const Unit& unit : units) {
    // The growth of each shard's estimate: the unit's arrays it does not make yet.
    std::uint32_t best = 0;
    double bestTotal = 0.0;
    for (std::uint32_t s = 0; s < count; ++s) {
      double total = shards.shardSeconds[s];
      for (std::uint32_t a : unit.arrays)
        if (!makes(s, a)) total += shards.arraySeconds[a];
      if (s == 0 || total < bestTotal) best = s, bestTotal = total;
    }
    shards.shardSeconds[best] = bestTotal;
    for (std::uint32_t a : unit.arrays) {
      if (!makes(best, a)) makers[a].insert(std::lower_bound(makers[a].begin(), makers[a].end(), best), best);
      if (shards.owner[a] == kUnowned) shards.owner[a] = best;
    }
  }

  shards.made.resize(count);
  for (std::uint32_t a = 0; a < arrays; ++a)
    for (std::uint32_t s : makers[a]) shards.made[s].push_back(a);
  Hash64 identity(count);
  for (std::uint32_t owner : shards.owner) identity.u32(owner);
  shards.identity = identity.digest();
  return shards;
}

}  // namespace pbs::detail
