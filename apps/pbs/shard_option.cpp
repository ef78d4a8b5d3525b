// parseShard: "I/N" or "auto/N", the index then read from the scheduler's job-array variable.
#include "shard_option.hpp"

#include <pbs/surfels/surfel_file.hpp>

#include <charconv>
#include <cstdlib>

namespace pbs::cli {
namespace {

// `text` as a whole number of 32 bits, or nothing (signs, spaces and trailing characters refused).
std::optional<std::uint32_t> wholeNumber(const std::string& text) {
  std::uint32_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// The shard index the scheduler gave this task.
std::uint32_t indexFromEnvironment() {
  for (const char* variable : kShardIndexVariables) {
    const char* value = std::getenv(variable);
    if (!value) continue;
    if (const std::optional<std::uint32_t> index = wholeNumber(value)) return *index;
    throw CLI::ValidationError("--shard", std::string("auto: $") + variable + " is '" + value +
                                              "', not a shard index (a whole number from 0)");
  }
  std::string names;
  for (const char* variable : kShardIndexVariables) names += (names.empty() ? "$" : ", $") + std::string(variable);
  throw CLI::ValidationError("--shard", "auto: none of " + names + " is set (not a job-array task): give I/N");
}

}  // namespace

ShardChoice parseShard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const std::optional<std::uint32_t> count =
      slash == std::string::npos ? std::nullopt : wholeNumber(text.substr(slash + 1));
  if (!count || *count == 0)
    throw CLI::ValidationError("--shard", "expected I/N (shard I of N, 0 <= I < N) or auto/N, got '" + text + "'");
  if (*count > kMaxSurfelShards)
    throw CLI::ValidationError("--shard",
                               std::to_string(*count) + " shards: at most " + std::to_string(kMaxSurfelShards));
  const std::string first = text.substr(0, slash);
  const std::optional<std::uint32_t> index = first == "auto" ? indexFromEnvironment() : wholeNumber(first);
  if (!index) throw CLI::ValidationError("--shard", "expected I/N (shard I of N, 0 <= I < N), got '" + text + "'");
  if (*index >= *count)
    throw CLI::ValidationError("--shard", "shard " + std::to_string(*index) + " of " + std::to_string(*count) +
                                              ": the index must be below the count (shards count from 0)");
  return {*index, *count};
}

void addShardOption(CLI::App& command, std::optional<ShardChoice>& shard, const std::string& help) {
  command.add_option_function<std::string>(
      "--shard", [&shard](const std::string& text) { shard = parseShard(text); },
      help +
          "; I/N (0 <= I < N), or auto/N for I from $SLURM_ARRAY_TASK_ID, $JOB_COMPLETION_INDEX, "
          "$AWS_BATCH_JOB_ARRAY_INDEX or $BATCH_TASK_INDEX");
}

}  // namespace pbs::cli
