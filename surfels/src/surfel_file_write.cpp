// writeSurfelFile: lays out header, tables and chunked data, writes them beside the target, renames.
#include "pbs/surfels/surfel_file.hpp"

#include "surfel_file_layout.hpp"

#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unistd.h>

namespace pbs {
namespace {

using namespace surfel_file;

void checkInput(const SurfelFile& file) {
  constexpr std::uint64_t kU32Max = std::numeric_limits<std::uint32_t>::max();
  if (file.arrays.size() > kU32Max) throw std::invalid_argument("surfel file: too many arrays");
  if (file.nodes.size() > kU32Max) throw std::invalid_argument("surfel file: too many nodes");
  for (std::size_t a = 0; a < file.arrays.size(); ++a) {
    if (file.arrays[a].surfels.size() > kU32Max) {
      throw std::invalid_argument("surfel file: array " + std::to_string(a) + " has more than 2^32 - 1 surfels");
    }
    if (const char* value = nonFiniteArrayValue(file.arrays[a]))
      throw std::invalid_argument("surfel file: array " + std::to_string(a) + ": " + value + " is not finite");
  }
  for (const SurfelNodeRecord& node : file.nodes) {
    if (node.array >= file.arrays.size()) {
      throw std::invalid_argument("surfel file: node " + node.path + " uses array " + std::to_string(node.array) +
                                  " of " + std::to_string(file.arrays.size()));
    }
    if (node.path.size() > kU32Max) throw std::invalid_argument("surfel file: node path too long");
  }
}

void appendChecksum(ByteSink& sink, std::size_t from, std::uint64_t seed) {
  sink.u64(Hash64::of(sink.bytes.data() + from, sink.bytes.size() - from, seed));
}

// Header, array table and node table, with every offset filled in.
std::vector<std::uint8_t> layoutTables(const SurfelFile& file) {
  std::vector<SurfelArrayInfo> infos(file.arrays.size());
  std::uint64_t nodeTableBytes = 0;
  for (const SurfelNodeRecord& node : file.nodes) nodeTableBytes += kNodeRecordMinBytes + node.path.size();

  Header header;
  header.fingerprint = file.sceneFingerprint;
  header.threshold = file.options.threshold;
  header.maxSurfels = file.options.maxSurfels;
  header.resolution = file.options.resolution;
  header.directions = file.options.directions;
  header.ordering = static_cast<std::uint32_t>(file.options.ordering);
  header.colors = static_cast<std::uint32_t>(file.options.colors);
  header.seed = file.options.seed;
  header.arrayCount = static_cast<std::uint32_t>(file.arrays.size());
  header.nodeCount = static_cast<std::uint32_t>(file.nodes.size());
  header.arrayTableOffset = kHeaderBytes;
  header.nodeTableOffset = header.arrayTableOffset + infos.size() * kArrayRecordBytes + kChecksumBytes;
  header.nodeTableBytes = nodeTableBytes;
  std::uint64_t offset = header.nodeTableOffset + nodeTableBytes + kChecksumBytes;
  for (std::size_t a = 0; a < infos.size(); ++a) {
    const SurfelArray& array = file.arrays[a];
    infos[a] = {array.box,        array.coverage,
                array.packing,    array.packingEnd,
                array.area,       static_cast<std::uint32_t>(array.surfels.size()),
                offset};
    offset += arrayDataBytes(array.surfels.size());
  }
  header.fileBytes = offset;

  ByteSink sink;
  layoutHeader(sink, header);
  appendChecksum(sink, 0, kHeaderSeed);
  const std::size_t arrayTable = sink.bytes.size();
  for (SurfelArrayInfo& info : infos) layoutArray(sink, info);
  appendChecksum(sink, arrayTable, kArrayTableSeed);
  const std::size_t nodeTable = sink.bytes.size();
  for (SurfelNodeRecord node : file.nodes) layoutNode(sink, node);
  appendChecksum(sink, nodeTable, kNodeTableSeed);
  return std::move(sink.bytes);
}

void writeBytes(std::ofstream& out, const std::uint8_t* data, std::size_t size) {
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

// One array's chunks, then its chunk checksums.
void writeArrayData(std::ofstream& out, const SurfelArray& array) {
  std::vector<std::uint8_t> chunk;
  ByteSink checksums;
  for (std::size_t first = 0; first < array.surfels.size(); first += kSurfelsPerChunk) {
    const std::size_t end = std::min<std::size_t>(first + kSurfelsPerChunk, array.surfels.size());
    chunk.clear();
    for (std::size_t i = first; i < end; ++i) {
      const PackedSurfel packed = encodeSurfel(array.surfels[i], array.box);
      chunk.insert(chunk.end(), packed.begin(), packed.end());
    }
    checksums.u64(chunkChecksum(chunk, first / kSurfelsPerChunk));
    writeBytes(out, chunk.data(), chunk.size());
  }
  writeBytes(out, checksums.bytes.data(), checksums.bytes.size());
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& why) {
  throw std::runtime_error("cannot write surfel file " + path.string() + ": " + why);
}

}  // namespace

void writeSurfelFile(const std::filesystem::path& path, const SurfelFile& file) {
  checkInput(file);
  const std::vector<std::uint8_t> tables = layoutTables(file);

  std::filesystem::path temporary = path;
  temporary += ".tmp-" + std::to_string(::getpid());
  try {
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) fail(path, "cannot create " + temporary.string());
      writeBytes(out, tables.data(), tables.size());
      for (const SurfelArray& array : file.arrays) writeArrayData(out, array);
      out.flush();
      if (!out) fail(path, "write failed");
      out.close();
      if (out.fail()) fail(path, "close failed");
    }
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) fail(path, "rename failed: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

}  // namespace pbs
