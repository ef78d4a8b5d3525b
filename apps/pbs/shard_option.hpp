// `--shard I/N`: the one of N machines (a job array's task) that a command does its share of the work on.
#pragma once

#include <pbs/surfels/surfelize.hpp>

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace pbs::cli {

// One type for surfelize's shards and render's: index 0 ≤ index < count.
using ShardChoice = SurfelizeShard;

// The job-array variables `--shard auto/N` reads, first set first: Slurm, Kubernetes Indexed Jobs, AWS
// Batch, Google Cloud Batch. Each counts tasks from 0 (a Slurm array must be submitted as --array=0-(N-1)).
inline constexpr const char* kShardIndexVariables[] = {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX",
                                                       "AWS_BATCH_JOB_ARRAY_INDEX", "BATCH_TASK_INDEX"};

// "I/N" with 0 ≤ I < N, or "auto/N" with I from the first of kShardIndexVariables that is set; a
// CLI::ValidationError naming what is wrong otherwise.
ShardChoice parseShard(const std::string& text);

// `--shard I/N` on `command`, filling `shard`; `help` says what a shard does there.
void addShardOption(CLI::App& command, std::optional<ShardChoice>& shard, const std::string& help);

}  // namespace pbs::cli
