// The subcommands of `pbs`: each file registers one on the application.
#pragma once

#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <CLI/CLI.hpp>

#include <cstdint>

namespace pbs::cli {

void addDemoCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addGenerateCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addCaptureCommand(CLI::App& app);
void addAnalyzeCommand(CLI::App& app);
void addPrefixesCommand(CLI::App& app);
void addSurfelizeCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addFigureCommand(CLI::App& app);

// The `--threads` option every command has (0: all hardware threads).
void addThreadsOption(CLI::App& command, int& threads);

// `--resolution` and `--directions` of the commands that capture nodes (see CaptureOptions).
void addCaptureOptions(CLI::App& command, std::uint32_t& resolution, std::uint32_t& directions);

// The LOD options of `pbs render` (and the baseline `pbs eval` sweeps from): --threshold, --band,
// --overdraw, --point-size, --prefix-rule.
void addLodOptions(CLI::App& command, LodOptions& lod);

// `--ordering farthest|dart|random`.
void addOrderingOption(CLI::App& command, SurfelOrdering& ordering);

// `--capture-from auto|triangles|children`: what inner nodes' captures draw (see CaptureSource).
void addCaptureSourceOption(CLI::App& command, CaptureSource& source, const std::string& help);

}  // namespace pbs::cli
