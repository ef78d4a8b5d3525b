// `--max-memory`: commands estimate what a job needs before starting it and refuse, with a clear error,
// what would not fit, instead of being killed by the system half-way.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace pbs::cli {

// The machine's physical memory in bytes.
std::uint64_t physicalMemory();

// `--max-memory SIZE` (bytes, or with KB/MB/GB/TB, powers of 1024; default: the physical memory).
// The value lands in `bytes`; 0 means the default.
void addMaxMemoryOption(CLI::App& command, std::uint64_t& bytes);

// Throws std::runtime_error ("… would need about X GB …, more than the limit of Y GB (--max-memory)")
// when `estimate` exceeds `limit` (0: the physical memory).
void requireMemory(std::uint64_t estimate, const std::string& what, std::uint64_t limit);

}  // namespace pbs::cli
