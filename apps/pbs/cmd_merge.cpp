// `pbs merge PART... -o F.surfels`: the parts the shards of `pbs surfelize --shard I/N` wrote, put
// together into the one file a single surfelize run writes.
#include "commands.hpp"

#include <pbs/evaluation/report_numbers.hpp>
#include <pbs/surfels/surfel_file.hpp>
#include <pbs/surfels/surfel_merge.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace pbs::cli {

void addMergeCommand(CLI::App& app) {
  struct Options {
    std::vector<std::string> parts;
    std::string output;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command =
      app.add_subcommand("merge", "Put the parts of pbs surfelize --shard I/N together into the whole .surfels file");
  command->add_option("parts", options->parts, "one part of every shard, in any order")->required();
  command->add_option("-o,--output", options->output, "the .surfels file to write")->required();
  command->add_flag("--json", options->json, "print JSON instead of text");
  command->callback([options] {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<std::filesystem::path> parts(options->parts.begin(), options->parts.end());
    mergeSurfelParts(parts, options->output);
    const SurfelFileReader merged(options->output);
    const std::uint64_t bytes = std::filesystem::file_size(options->output);
    const double seconds = secondsSince(start);
    if (options->json) {
      const nlohmann::json report = {{"parts", parts.size()},
                                     {"arrays", merged.arrays().size()},
                                     {"output", options->output},
                                     {"bytes", bytes},
                                     {"seconds", seconds}};
      std::cout << report.dump(2) << "\n";
      return;
    }
    std::printf("merged %zu parts (%s arrays) into %s: %s bytes in %.2f s\n", parts.size(),
                withThousands(merged.arrays().size()).c_str(), options->output.c_str(), withThousands(bytes).c_str(),
                seconds);
  });
}

}  // namespace pbs::cli
