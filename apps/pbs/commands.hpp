// The subcommands of `pbs`: each file registers one on the application.
#pragma once

#include <CLI/CLI.hpp>

namespace pbs::cli {

void addDemoCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addGenerateCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addCaptureCommand(CLI::App& app);

// The `--threads` option every command has (0: all hardware threads).
void addThreadsOption(CLI::App& command, int& threads);

}  // namespace pbs::cli
