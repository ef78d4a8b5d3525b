// Surfelize split into shards and merged, from the command line: what the shard tests share.
#pragma once

#include "test_support.hpp"

#include <pbs/surfels/surfel_file.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pbs::test {

// Makes shard `index` of `count` of `scene` into `dir`/part-count-index.surfels; returns the path.
inline std::filesystem::path makePart(const std::string& scene, const std::filesystem::path& dir, std::uint32_t index,
                                      std::uint32_t count, const std::string& options) {
  const std::filesystem::path part = dir / ("part-" + std::to_string(count) + "-" + std::to_string(index) + ".surfels");
  const CommandResult made = runPbs("surfelize " + scene + " -o " + quoted(part) + " --shard " + std::to_string(index) +
                                    "/" + std::to_string(count) + options);
  EXPECT_EQ(made.status, 0) << made.err;
  return part;
}

inline std::string quotedAll(const std::vector<std::filesystem::path>& files) {
  std::string text;
  for (const std::filesystem::path& file : files) text.append(" ").append(quoted(file));
  return text;
}

// For 1, 2, 3 and 7 shards: every shard's part, merged, is the one-machine file.
inline void expectShardsMergeToTheSingleRun(const std::string& scene, const ScratchDir& scratch,
                                            const std::string& options) {
  const std::filesystem::path single = scratch / "single.surfels";
  const CommandResult whole = runPbs("surfelize " + scene + " -o " + quoted(single) + options);
  ASSERT_EQ(whole.status, 0) << whole.err;
  const std::string expected = readFile(single);
  EXPECT_GE(SurfelFileReader(single).arrays().size(), 10u) << "arrays for the shards to share";
  for (std::uint32_t count : {1u, 2u, 3u, 7u}) {
    std::vector<std::filesystem::path> parts;
    for (std::uint32_t index = count; index-- > 0;)  // in reverse: merge takes parts in any order
      parts.push_back(makePart(scene, scratch.path(), index, count, options));
    const std::filesystem::path merged = scratch / ("merged-" + std::to_string(count) + ".surfels");
    const CommandResult merge = runPbs("merge" + quotedAll(parts) + " -o " + quoted(merged));
    ASSERT_EQ(merge.status, 0) << merge.err;
    EXPECT_TRUE(readFile(merged) == expected) << count << " shards";
  }
}

}  // namespace pbs::test
