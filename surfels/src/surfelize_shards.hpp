// How surfelize splits over machines: which shard writes each array, and what each shard must make.
#pragma once

#include "surfelize_plan.hpp"

#include <cstdint>
#include <vector>

namespace pbs::detail {

struct ShardPlan {
  std::uint32_t count = 1;
  std::vector<std::uint32_t> owner;  // per array: the shard whose part holds it
  // Per shard: the arrays it makes, ascending. Besides its own, those its arrays' captures draw (and theirs)
  // that other shards hold: they are made again, since a part must not wait on another machine.
  std::vector<std::vector<std::uint32_t>> made;
  std::vector<double> arraySeconds;  // per array: the estimated seconds to make it
  std::vector<double> shardSeconds;  // per shard: the estimated seconds of what it makes
  std::uint64_t identity = 0;        // a hash of `count` and `owner`: parts of one plan share it
};

// The estimated seconds to make an array on one core of the 2-core machine the constants were measured
// on: a part for each capture pixel (G-buffers, candidates, their ordering) and a part for each
// triangle or splat the capture draws.
double estimatedArraySeconds(const SurfelizeOptions& options, std::uint64_t primitivesDrawn);

// `count` shards of `plan`, a pure function of the plan and the options. Arrays are grouped into units that
// a shard must make whole: an array no other capture draws, with every array its capture draws, down to
// captures of triangles. The units go, largest estimate first, to the shard whose estimate grows least
// (arrays it already makes count once; ties to the lowest shard), and each array belongs to the
// shard of the first unit that holds it.
ShardPlan planShards(const SurfelPlan& plan, const SurfelizeOptions& options, std::uint32_t count);

}  // namespace pbs::detail
