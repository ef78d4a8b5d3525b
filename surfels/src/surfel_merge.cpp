// mergeSurfelParts: the parts of every shard checked against each other, then copied into one file.
#include "pbs/surfels/surfel_merge.hpp"

#include "pbs/scene/input_error.hpp"
#include "pbs/surfels/surfel_file.hpp"

#include <cstdio>
#include <deque>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbs {
namespace {

std::string hex(std::uint64_t value) {
  char text[20];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

std::string shardName(const SurfelShardTable& shard) {
  return "shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count);
}

// The first option in which `a` differs from `b`, as "NAME A, not B", or "" when they agree.
std::string optionDifference(const SurfelFileOptions& a, const SurfelFileOptions& b) {
  const auto differs = [](const char* name, std::uint64_t x, std::uint64_t y) {
    return x == y ? std::string() : std::string(name) + " " + std::to_string(x) + ", not " + std::to_string(y);
  };
  for (const std::string& difference :
       {differs("min triangles", a.threshold, b.threshold), differs("max surfels", a.maxSurfels, b.maxSurfels),
        differs("resolution", a.resolution, b.resolution), differs("directions", a.directions, b.directions),
        differs("ordering", std::uint64_t(a.ordering), std::uint64_t(b.ordering)),
        differs("colours", std::uint64_t(a.colors), std::uint64_t(b.colors)), differs("seed", a.seed, b.seed),
        differs("octree leaf", a.octreeLeafTriangles, b.octreeLeafTriangles)})
    if (!difference.empty()) return difference;
  return "";
}

// Refuses `part` unless it belongs with `first`: the same scene, options and plan.
void requireSamePlan(const SurfelFileReader& part, const SurfelFileReader& first) {
  const SurfelShardTable& shard = *part.shard();
  const std::string name = shardName(shard);
  const std::string firstName = first.path().string();
  if (part.sceneFingerprint() != first.sceneFingerprint())
    throw InputError(part.path().string(), name,
                     "made for another scene (fingerprint " + hex(part.sceneFingerprint()) + ", " + firstName +
                         "'s is " + hex(first.sceneFingerprint()) + ")");
  if (const std::string difference = optionDifference(part.options(), first.options()); !difference.empty())
    throw InputError(part.path().string(), name, "made with other options than " + firstName + " (" + difference + ")");
  if (shard.count != first.shard()->count || shard.plan != first.shard()->plan ||
      part.arrays().size() != first.arrays().size())
    throw InputError(part.path().string(), name,
                     "of another plan than " + firstName + " (" + shardName(*first.shard()) + ", plan " +
                         hex(first.shard()->plan) + "; this one's " + hex(shard.plan) +
                         "): made with another shard count, --capture-from or pbs");
}

}  // namespace

void mergeSurfelParts(std::span<const std::filesystem::path> parts, const std::filesystem::path& output) {
  if (parts.empty()) throw std::invalid_argument("merge: no parts given");
  std::deque<SurfelFileReader> readers;  // a deque: readers stay where they are as more are opened
  for (const std::filesystem::path& part : parts) {
    readers.emplace_back(part);
    if (!readers.back().shard())
      throw InputError(part.string(), "header",
                       "not a shard's part (a whole .surfels file, or one made by pbs surfelize without --shard)");
  }

  SurfelFileReader& first = readers.front();
  const std::uint32_t count = first.shard()->count;
  std::vector<SurfelFileReader*> byShard(count, nullptr);
  for (SurfelFileReader& part : readers) {
    requireSamePlan(part, first);
    const std::uint32_t index = part.shard()->index;
    if (byShard[index])
      throw InputError(part.path().string(), shardName(*part.shard()),
                       "given twice (also " + byShard[index]->path().string() + ")");
    byShard[index] = &part;
  }
  for (std::uint32_t s = 0; s < count; ++s)
    if (!byShard[s])
      throw InputError(output.string(), "shard " + std::to_string(s) + "/" + std::to_string(count),
                       "missing: no part given holds it (nothing written)");

  // Which part holds each array: every array in exactly one (the plan says so; a part made by a pbs
  // with another plan under the same identity would not).
  const std::size_t arrays = first.arrays().size();
  std::vector<SurfelFileReader*> holder(arrays, nullptr);
  for (SurfelFileReader& part : readers)
    for (std::uint32_t a : part.shard()->arrays) {
      if (holder[a])
        throw InputError(part.path().string(), shardName(*part.shard()),
                         "holds array " + std::to_string(a) + ", which " + holder[a]->path().string() + " holds too");
      holder[a] = &part;
    }
  for (std::size_t a = 0; a < arrays; ++a)
    if (!holder[a]) throw InputError(first.path().string(), "shard table", "no part holds array " + std::to_string(a));

  SurfelFileWriter writer(output, first.sceneFingerprint(), first.options(),
                          std::vector<SurfelNodeRecord>(first.nodes().begin(), first.nodes().end()), first.sceneTable(),
                          std::uint32_t(arrays));
  for (std::uint32_t a = 0; a < arrays; ++a) writer.addStored(a, holder[a]->arrays()[a], holder[a]->readStored(a));
  writer.finish();
}

}  // namespace pbs
