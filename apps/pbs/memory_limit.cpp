// Memory sizes as options, the machine's physical memory, and the refusal message.
#include "memory_limit.hpp"

#include <unistd.h>

#include <cstdio>
#include <stdexcept>

namespace pbs::cli {
namespace {

std::string gigabytes(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f GB", double(bytes) / double(1ull << 30));
  return text;
}

}  // namespace

std::uint64_t physicalMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long pageSize = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && pageSize > 0 ? std::uint64_t(pages) * std::uint64_t(pageSize) : ~std::uint64_t(0);
}

void addMaxMemoryOption(CLI::App& command, std::uint64_t& bytes) {
  command
      .add_option("--max-memory", bytes, "refuse jobs estimated to need more (e.g. 512MB, 4GB; default: all of RAM)")
      ->transform(CLI::AsSizeValue(false));
}

void requireMemory(std::uint64_t estimate, const std::string& what, std::uint64_t limit) {
  const bool given = limit != 0;
  if (!given) limit = physicalMemory();
  if (estimate <= limit) return;
  throw std::runtime_error(what + " would need about " + gigabytes(estimate) + ", more than the limit of " +
                           gigabytes(limit) +
                           (given ? " (--max-memory)" : " (the machine's memory; see --max-memory)"));
}

}  // namespace pbs::cli
