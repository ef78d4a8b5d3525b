// The entry points the fuzz targets drive, shared with test_fuzz_regressions so that every crash
// input and seed is replayed through exactly what the fuzzer ran. Each takes the input's bytes and
// either returns (the input loaded) or throws pbs::InputError; anything else escaping is a finding.
#pragma once

#include "pbs/raster/hash64.hpp"
#include "pbs/scene/gltf_import.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/input_error.hpp"
#include "pbs/surfels/surfel_file.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbs::fuzz {

// glTF or GLB bytes: import (both are told apart by the magic, as for a file), then the checks and
// derived values every command computes next. baseDir names a directory that cannot exist (a child
// of /proc/self, where nothing can be created), so no external URI, not even one climbing out
// with "..", resolves to a file: the import reads the input's bytes and nothing else.
inline void importGltfBytes(std::span<const std::uint8_t> bytes) {
  static const std::filesystem::path kNoBaseDir = "/proc/self/pbs-fuzz-no-such-dir";
  const std::string name = "fuzz.gltf";
  const ImportResult result = importGltfFromMemory(bytes, name, kNoBaseDir);
  validateScene(result.scene, name);
  const Hierarchy hierarchy = analyzeHierarchy(result.scene);
  summarizeScene(result.scene, hierarchy);
}

// .surfels layout constants (surfels/src/surfel_file_layout.hpp, described in surfel_file.hpp):
// repeated here so that the fuzzer can repair checksums without reaching into the library's sources.
namespace surfel_layout {
inline constexpr std::uint64_t kHeaderBytes = 112;
inline constexpr std::uint64_t kHeaderChecksumOffset = 104;
inline constexpr std::uint64_t kVersionOffset = 8;
inline constexpr std::uint64_t arrayRecordBytes(std::uint32_t version) { return version >= 3 ? 104 : 96; }
// A stored surfel's bytes by colour encoding (RGBA, RGB, constant); version 2 stores RGBA.
inline constexpr std::uint64_t surfelBytes(std::uint32_t encoding) {
  return encoding == 1 ? 15 : encoding == 2 ? 12 : 16;
}
inline constexpr std::uint64_t kChecksumBytes = 8;
inline constexpr std::uint64_t kHeaderSeed = 0x50425348'45414452ull;
inline constexpr std::uint64_t kArrayTableSeed = 0x50425341'52524159ull;
inline constexpr std::uint64_t kNodeTableSeed = 0x5042534E'4F444553ull;
inline constexpr std::uint64_t kChunkSeed = 0x50425344'41544100ull;
}  // namespace surfel_layout

inline std::uint64_t loadU64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
inline std::uint32_t loadU32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}
inline void storeU64(std::uint8_t* p, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

// Rewrites every checksum whose range lies inside the bytes (header, array table, node table, each
// array's chunks) to match, so that mutations reach the checks behind the checksums instead of
// stopping at "checksum mismatch". Reads the layout defensively: the bytes are arbitrary.
inline void repairSurfelChecksums(std::vector<std::uint8_t>& bytes) {
  using namespace surfel_layout;
  const std::uint64_t size = bytes.size();
  if (size < kHeaderBytes) return;
  std::uint8_t* b = bytes.data();
  const auto fits = [&](std::uint64_t offset, std::uint64_t length) {
    return offset <= size && length <= size - offset;
  };
  // Table checksums first (the header does not cover them), the header's last.
  const std::uint32_t version = loadU32(b + kVersionOffset);
  const std::uint64_t recordBytes = arrayRecordBytes(version);
  const std::uint64_t arrayCount = loadU32(b + 64);
  const std::uint64_t arrayTable = loadU64(b + 72);
  const std::uint64_t nodeTable = loadU64(b + 80);
  const std::uint64_t nodeTableBytes = loadU64(b + 88);
  const bool arraysFit =
      arrayCount <= size / recordBytes && fits(arrayTable, arrayCount * recordBytes + kChecksumBytes);
  if (arraysFit) {
    for (std::uint64_t a = 0; a < arrayCount; ++a) {
      const std::uint8_t* record = b + arrayTable + a * recordBytes;
      const std::uint64_t count = loadU32(record + 80);
      const std::uint64_t stored = surfelBytes(version >= 3 ? loadU32(record + 84) : 0);
      const std::uint64_t data = loadU64(record + 88);
      const std::uint64_t chunks = (count + kSurfelsPerChunk - 1) / kSurfelsPerChunk;
      if (!fits(data, count * stored + chunks * kChecksumBytes)) continue;
      for (std::uint64_t c = 0; c < chunks; ++c) {
        const std::uint64_t first = c * kSurfelsPerChunk;
        const std::uint64_t n = std::min<std::uint64_t>(kSurfelsPerChunk, count - first);
        storeU64(b + data + count * stored + c * kChecksumBytes,
                 Hash64::of(b + data + first * stored, n * stored, kChunkSeed + c));
      }
    }
    const std::uint64_t body = arrayCount * recordBytes;
    storeU64(b + arrayTable + body, Hash64::of(b + arrayTable, body, kArrayTableSeed));
  }
  if (nodeTableBytes <= size && fits(nodeTable, nodeTableBytes + kChecksumBytes)) {
    storeU64(b + nodeTable + nodeTableBytes, Hash64::of(b + nodeTable, nodeTableBytes, kNodeTableSeed));
  }
  storeU64(b + kHeaderChecksumOffset, Hash64::of(b, kHeaderChecksumOffset, kHeaderSeed));
}

// A file the reader can open by path whose bytes live in memory (memfd, reached through
// /proc/self/fd): rewritten for each input without touching the disk.
class MemoryFile {
 public:
  MemoryFile() : fd_(memfd_create("pbs-fuzz.surfels", 0)) {
    if (fd_ < 0) throw std::runtime_error("memfd_create failed");
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  ~MemoryFile() { close(fd_); }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  void assign(std::span<const std::uint8_t> bytes) {
    if (ftruncate(fd_, 0) != 0) throw std::runtime_error("ftruncate failed");
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = pwrite(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(done));
      if (n <= 0) throw std::runtime_error("pwrite failed");
      done += static_cast<std::size_t>(n);
    }
  }

 private:
  int fd_;
  std::filesystem::path path_;
};

// Opens the bytes as a .surfels file, reads every array whole through readPrefix (and a one-surfel
// prefix, which reads only the first chunk), then the whole file through readSurfelFile.
inline void readSurfelFileAt(const std::filesystem::path& path) {
  SurfelFileReader reader(path);
  for (std::uint32_t a = 0; a < reader.arrays().size(); ++a) {
    reader.readPrefix(a, 1);
    reader.readPrefix(a, reader.arrays()[a].count);
  }
  readSurfelFile(path);
}

// The .surfels target: the bytes as given (every check, checksums included, sees them) and, when
// repairing the checksums changes them, the repaired bytes (the checks behind the checksums see
// them). The second read's InputError is the one that escapes when both fail.
inline void readSurfelBytes(std::span<const std::uint8_t> bytes) {
  static MemoryFile file;
  std::vector<std::uint8_t> repaired(bytes.begin(), bytes.end());
  repairSurfelChecksums(repaired);
  const bool same = std::equal(repaired.begin(), repaired.end(), bytes.begin(), bytes.end());
  file.assign(bytes);
  if (same) return readSurfelFileAt(file.path());
  try {
    readSurfelFileAt(file.path());
  } catch (const InputError&) {
  }
  file.assign(repaired);
  readSurfelFileAt(file.path());
}

}  // namespace pbs::fuzz
