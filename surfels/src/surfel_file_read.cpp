// SurfelFileReader and readSurfelFile: checks header and tables at open, reads checked chunks on demand.
#include "pbs/surfels/surfel_file.hpp"

#include "pbs/scene/input_error.hpp"
#include "surfel_file_layout.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace pbs {
namespace {

using namespace surfel_file;

std::string number(std::uint64_t v) { return std::to_string(v); }

// The message for [offset, offset + size) not inside the file (the first offset past its end, without
// wrapping around for a corrupt offset).
std::string beyond(std::uint64_t offset, std::uint64_t size, std::uint64_t fileSize) {
  const std::uint64_t end = offset > fileSize ? offset : offset + size;
  return "truncated: offset " + number(end) + " beyond file size " + number(fileSize);
}

}  // namespace

SurfelFileReader::SurfelFileReader(const std::filesystem::path& path) : path_(path) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(file, "", "not a regular file (or missing)");
  stream_.open(path, std::ios::binary);
  if (!stream_) throw InputError(file, "", "cannot open for reading");
  stream_.seekg(0, std::ios::end);
  const std::streamoff end = stream_.tellg();
  if (end < 0) throw InputError(file, "", "cannot determine the file size");
  const auto fileSize = static_cast<std::uint64_t>(end);

  // Reads [offset, offset + size) after checking it lies inside the file (so nothing is allocated for
  // a corrupt size).
  auto readRange = [&](const std::string& element, std::uint64_t offset, std::uint64_t size) {
    if (offset > fileSize || size > fileSize - offset) throw InputError(file, element, beyond(offset, size, fileSize));
    std::vector<std::uint8_t> bytes(size);
    stream_.clear();
    stream_.seekg(static_cast<std::streamoff>(offset));
    stream_.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
    if (!stream_) throw InputError(file, element, "read failed at offset " + number(offset));
    return bytes;
  };
  // The checksum in the last 8 bytes of `bytes` against the rest.
  auto checkTable = [&](const std::string& element, const std::vector<std::uint8_t>& bytes, std::uint64_t seed) {
    const std::size_t body = bytes.size() - kChecksumBytes;
    if (Hash64::of(bytes.data(), body, seed) != readU64(bytes.data() + body)) {
      throw InputError(file, element, "checksum mismatch");
    }
  };

  // Header: the magic first so that any other file is called what it is.
  const std::vector<std::uint8_t> headerBytes = readRange("header", 0, std::min(fileSize, kHeaderBytes));
  if (headerBytes.size() < kMagic.size() || !std::equal(kMagic.begin(), kMagic.end(), headerBytes.begin())) {
    throw InputError(file, "header", "bad magic (not a .surfels file)");
  }
  if (fileSize < kHeaderBytes) throw InputError(file, "header", beyond(0, kHeaderBytes, fileSize));
  Header header;
  ByteSource headerSource{headerBytes};
  layoutHeader(headerSource, header);
  if (header.version < kOldestReadSurfelFileVersion || header.version > kSurfelFileVersion) {
    throw InputError(file, "header",
                     "unsupported version " + number(header.version) + " (this build reads versions " +
                         number(kOldestReadSurfelFileVersion) + " to " + number(kSurfelFileVersion) + ")");
  }
  checkTable("header", headerBytes, kHeaderSeed);
  if (header.ordering > static_cast<std::uint32_t>(SurfelOrdering::Random)) {
    throw InputError(file, "header", "unknown ordering " + number(header.ordering));
  }
  if (header.colors > static_cast<std::uint32_t>(SurfelColors::Prefiltered)) {
    throw InputError(file, "header", "unknown colour filter " + number(header.colors));
  }
  if (header.version >= 5 && (header.flags & ~kShardPartFlag) != 0)
    throw InputError(file, "header", "unknown flags " + number(header.flags));
  if (header.fileBytes > fileSize) throw InputError(file, "header", beyond(header.fileBytes, 0, fileSize));
  if (header.fileBytes < fileSize) {
    throw InputError(
        file, "header",
        "file size " + number(fileSize) + " exceeds the " + number(header.fileBytes) + " bytes it declares");
  }
  fingerprint_ = header.fingerprint;
  version_ = header.version;
  options_ = {.threshold = header.threshold,
              .maxSurfels = header.maxSurfels,
              .resolution = header.resolution,
              .directions = header.directions,
              .ordering = static_cast<SurfelOrdering>(header.ordering),
              .colors = static_cast<SurfelColors>(header.colors),
              .seed = header.seed,
              .octreeLeafTriangles = header.version >= 5 ? header.octreeLeafTriangles : 0};

  // Array table: the count is bounded by the file size before the table is read.
  const std::uint64_t recordBytes = arrayRecordBytes(header.version);
  if (header.arrayCount > fileSize / recordBytes) {
    throw InputError(
        file, "array table",
        "counts absurd: " + number(header.arrayCount) + " arrays cannot fit in " + number(fileSize) + " bytes");
  }
  const std::vector<std::uint8_t> arrayTable =
      readRange("array table", header.arrayTableOffset, header.arrayCount * recordBytes + kChecksumBytes);
  checkTable("array table", arrayTable, kArrayTableSeed);
  arrays_.resize(header.arrayCount);
  std::vector<std::uint32_t> encodings(header.arrayCount);  // checked below, where errors can name a node
  ByteSource arraySource{arrayTable};
  for (std::size_t a = 0; a < arrays_.size(); ++a) layoutArray(arraySource, arrays_[a], encodings[a], header.version);

  // Node table: every record takes at least nodeRecordMinBytes, so the count is bounded by the size.
  if (header.nodeTableBytes > fileSize ||
      header.nodeCount > header.nodeTableBytes / nodeRecordMinBytes(header.version)) {
    throw InputError(file, "node table",
                     "counts absurd: " + number(header.nodeCount) + " nodes in " + number(header.nodeTableBytes) +
                         " bytes, file size " + number(fileSize));
  }
  const std::vector<std::uint8_t> nodeTable =
      readRange("node table", header.nodeTableOffset, header.nodeTableBytes + kChecksumBytes);
  checkTable("node table", nodeTable, kNodeTableSeed);
  ByteSource nodeSource{std::span(nodeTable).first(header.nodeTableBytes)};
  nodes_.resize(header.nodeCount);
  try {
    const std::string none;
    for (std::size_t n = 0; n < nodes_.size(); ++n) {
      StoredNode stored;
      layoutNode(nodeSource, stored, header.version);
      const std::string& previous = n > 0 ? nodes_[n - 1].path : none;
      if (stored.shared > previous.size())
        throw ShortRecord("node record " + number(n) + " shares " + number(stored.shared) + " bytes with a path of " +
                          number(previous.size()));
      nodes_[n] = {previous.substr(0, stored.shared) + stored.suffix, stored.array};
    }
  } catch (const ShortRecord& e) {
    throw InputError(file, "node table", e.what());
  }
  if (nodeSource.remaining() != 0) {
    throw InputError(file, "node table", number(nodeSource.remaining()) + " bytes after the last node");
  }
  for (const SurfelNodeRecord& node : nodes_) {
    if (node.array >= arrays_.size()) {
      throw InputError(file, "node " + node.path, "uses array " + number(node.array) + " of " + number(arrays_.size()));
    }
  }

  // Scene table (version 4): right after the node table, its counts bounded by the file size.
  std::uint64_t tablesEnd =
      std::max(header.arrayTableOffset + arrayTable.size(), header.nodeTableOffset + nodeTable.size());
  tablesBytes_ = headerBytes.size() + arrayTable.size() + nodeTable.size();
  if (header.version >= 4) {
    const std::uint64_t offset = header.nodeTableOffset + nodeTable.size();
    const std::vector<std::uint8_t> head = readRange("scene table", offset, kSceneTableHeadBytes);
    std::uint32_t nodeCount = 0, meshCount = 0;
    ByteSource counts{head};
    counts.u32(nodeCount);
    counts.u32(meshCount);
    if (nodeCount > fileSize / kBoxBytes || meshCount > fileSize / 8)
      throw InputError(file, "scene table",
                       "counts absurd: " + number(nodeCount) + " boxes and " + number(meshCount) +
                           " fingerprints cannot fit in " + number(fileSize) + " bytes");
    const std::vector<std::uint8_t> table = readRange("scene table", offset, sceneTableBytes(nodeCount, meshCount));
    checkTable("scene table", table, kSceneTableSeed);
    ByteSource source{std::span(table).subspan(8)};
    source.u64(sceneTable_.structure);
    sceneTable_.meshes.resize(meshCount);
    for (std::uint64_t& mesh : sceneTable_.meshes) source.u64(mesh);
    sceneTable_.instanceBounds.resize(nodeCount);
    for (std::uint32_t n = 0; n < nodeCount; ++n) {
      layoutBox(source, sceneTable_.instanceBounds[n]);
      if (!validInstanceBox(sceneTable_.instanceBounds[n]))
        throw InputError(file, "scene table", "box of node " + number(n) + " is neither empty nor finite");
    }
    tablesEnd = std::max(tablesEnd, offset + table.size());
    tablesBytes_ += table.size();
  }

  // Shard table (a part of one shard): right after the scene table, its count bounded by the arrays'.
  if (header.version >= 5 && (header.flags & kShardPartFlag) != 0) {
    const std::uint64_t offset = tablesEnd;
    const std::vector<std::uint8_t> head = readRange("shard table", offset, kShardTableHeadBytes);
    SurfelShardTable shard;
    std::uint32_t held = 0;
    ByteSource counts{head};
    layoutShardHead(counts, shard, held);
    if (held > header.arrayCount)
      throw InputError(file, "shard table", "holds " + number(held) + " arrays of " + number(header.arrayCount));
    const std::vector<std::uint8_t> table = readRange("shard table", offset, shardTableBytes(held));
    checkTable("shard table", table, kShardTableSeed);
    ByteSource source{std::span(table).subspan(kShardTableHeadBytes)};
    shard.arrays.resize(held);
    for (std::uint32_t& array : shard.arrays) source.u32(array);
    if (shard.count == 0 || shard.index >= shard.count || shard.count > kMaxSurfelShards)
      throw InputError(file, "shard table",
                       "shard " + number(shard.index) + " of " + number(shard.count) + " (at most " +
                           number(kMaxSurfelShards) + " shards)");
    for (std::size_t i = 0; i < shard.arrays.size(); ++i)
      if (shard.arrays[i] >= header.arrayCount || (i > 0 && shard.arrays[i] <= shard.arrays[i - 1]))
        throw InputError(file, "shard table", "held arrays not ascending below " + number(header.arrayCount));
    shard_ = std::move(shard);
    tablesEnd += table.size();
    tablesBytes_ += table.size();
  }

  // Every array's data inside the file, after the tables.
  const std::uint64_t dataStart = tablesEnd;
  // Errors name the first node using the array: one pass finds them all (a search per array would be
  // arrays × nodes, seconds on a city).
  constexpr std::size_t kUnused = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> firstUser(arrays_.size(), kUnused);
  for (std::size_t n = nodes_.size(); n-- > 0;) firstUser[nodes_[n].array] = n;
  for (std::uint32_t a = 0; a < arrays_.size(); ++a) {
    SurfelArrayInfo& info = arrays_[a];
    auto element = [&] { return firstUser[a] != kUnused ? "node " + nodes_[firstUser[a]].path : "array " + number(a); };
    if (header.version < 3 && encodings[a] != 0)
      throw InputError(file, element(), "reserved field is " + number(encodings[a]) + ", not 0");
    if (encodings[a] > static_cast<std::uint32_t>(SurfelColorEncoding::Constant))
      throw InputError(file, element(), "unknown colour encoding " + number(encodings[a]));
    info.colorEncoding = static_cast<SurfelColorEncoding>(encodings[a]);
    const std::uint64_t bytes = storedSurfelBytes(info.count, info.colorEncoding);
    if (info.dataOffset < dataStart && bytes > 0) {
      throw InputError(file, element(), "data offset " + number(info.dataOffset) + " inside the tables");
    }
    if (info.dataOffset > fileSize || bytes > fileSize - info.dataOffset) {
      throw InputError(file, element(), beyond(info.dataOffset, bytes, fileSize));
    }
    if (const char* problem = invalidArrayValue(info)) throw InputError(file, element(), problem);
  }
}

void SurfelFileReader::requireScene(std::uint64_t fingerprint) {
  sceneRequired_ = fingerprint == fingerprint_;
  if (sceneRequired_) return;
  char text[224];
  // A file of a loose octree is checked against the scene rebuilt as that octree: say so, since the
  // scene a user named is then not the one compared.
  const std::string octree =
      options_.octreeLeafTriangles > 0
          ? " as a loose octree of leaves of at most " + std::to_string(options_.octreeLeafTriangles) + " triangles"
          : std::string();
  std::snprintf(text, sizeof text,
                "made for another scene (fingerprint %016llx, this scene's%s is %016llx): run pbs surfelize again",
                static_cast<unsigned long long>(fingerprint_), octree.c_str(),
                static_cast<unsigned long long>(fingerprint));
  throw InputError(path_.string(), "header", text);
}

void SurfelFileReader::requireStructure(std::uint64_t structure) {
  if (sceneTable_.instanceBounds.empty())
    throw InputError(path_.string(), "scene table",
                     "none in a file of version " + number(version_) +
                         ": run pbs surfelize again to read the scene's "
                         "meshes as frames draw them");
  sceneRequired_ = structure == sceneTable_.structure;
  if (sceneRequired_) return;
  char text[160];
  std::snprintf(text, sizeof text,
                "made for another scene (structure fingerprint %016llx, this scene's is %016llx): run pbs surfelize "
                "again",
                static_cast<unsigned long long>(sceneTable_.structure), static_cast<unsigned long long>(structure));
  throw InputError(path_.string(), "scene table", text);
}

std::vector<Surfel> SurfelFileReader::readPrefix(std::uint32_t array, std::uint32_t count) {
  return readRange(array, 0, count);
}

std::vector<Surfel> SurfelFileReader::readRange(std::uint32_t array, std::uint32_t first, std::uint32_t count) {
  if (array >= arrays_.size()) {
    throw std::out_of_range("surfel file " + path_.string() + ": array " + number(array) + " of " +
                            number(arrays_.size()));
  }
  if (first % kSurfelsPerChunk != 0)
    throw std::invalid_argument("surfel file: a range starts at a chunk, not at surfel " + number(first));
  const SurfelArrayInfo& info = arrays_[array];
  if (first >= info.count) return {};
  const std::uint32_t wanted = std::min(count, info.count - first);
  if (wanted == 0) return {};

  // Whole chunks, since a checksum covers a whole chunk; the last chunk of an array may be short.
  const std::uint64_t surfelsRead = std::min<std::uint64_t>(chunkCount(wanted) * kSurfelsPerChunk, info.count - first);
  const std::vector<std::uint8_t> data = readChunks(array, first, std::uint32_t(surfelsRead)).data;

  // A packed surfel gets the stored bytes over the colour the array's encoding leaves out (bytes 12–15).
  const std::uint64_t stored = surfelBytes(info.colorEncoding);
  PackedSurfel packed{};
  if (info.colorEncoding == SurfelColorEncoding::Constant)
    for (int c = 0; c < 4; ++c) packed[std::size_t(12 + c)] = info.constantColor[c];
  if (info.colorEncoding == SurfelColorEncoding::Rgb) packed[15] = 255;
  std::vector<Surfel> surfels(wanted);
  for (std::uint32_t i = 0; i < wanted; ++i) {
    std::copy_n(data.begin() + std::ptrdiff_t(i * stored), stored, packed.begin());
    surfels[i] = decodeSurfel(packed, info.box);
  }
  return surfels;
}

std::vector<std::uint8_t> SurfelFileReader::readStored(std::uint32_t array) {
  if (array >= arrays_.size()) {
    throw std::out_of_range("surfel file " + path_.string() + ": array " + number(array) + " of " +
                            number(arrays_.size()));
  }
  StoredChunks chunks = readChunks(array, 0, arrays_[array].count);
  chunks.data.insert(chunks.data.end(), chunks.checksums.begin(), chunks.checksums.end());
  return std::move(chunks.data);
}

SurfelFileReader::StoredChunks SurfelFileReader::readChunks(std::uint32_t array, std::uint32_t first,
                                                            std::uint32_t surfels) {
  const SurfelArrayInfo& info = arrays_[array];
  auto element = [&] {
    for (const SurfelNodeRecord& node : nodes_) {
      if (node.array == array) return "node " + node.path;
    }
    return "array " + number(array);
  };
  auto read = [&](std::uint64_t offset, std::vector<std::uint8_t>& bytes) {
    stream_.clear();
    stream_.seekg(static_cast<std::streamoff>(offset));
    stream_.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!stream_) throw InputError(path_.string(), element(), "read failed at offset " + number(offset));
    dataBytesRead_ += bytes.size();
  };

  const std::uint64_t firstChunk = first / kSurfelsPerChunk;
  const std::uint64_t chunks = chunkCount(surfels);
  const std::uint64_t stored = surfelBytes(info.colorEncoding);
  StoredChunks result{std::vector<std::uint8_t>(std::uint64_t(surfels) * stored),
                      std::vector<std::uint8_t>(chunks * kChecksumBytes)};
  read(info.dataOffset + std::uint64_t(first) * stored, result.data);
  read(info.dataOffset + std::uint64_t(info.count) * stored + firstChunk * kChecksumBytes, result.checksums);

  for (std::uint64_t c = 0; c < chunks; ++c) {
    const std::uint64_t at = c * kSurfelsPerChunk * stored;
    const std::uint64_t size = std::min<std::uint64_t>(kSurfelsPerChunk * stored, result.data.size() - at);
    if (chunkChecksum(std::span(result.data).subspan(at, size), firstChunk + c) !=
        readU64(result.checksums.data() + c * kChecksumBytes)) {
      throw InputError(
          path_.string(), element(),
          "checksum mismatch in surfel chunk " + number(firstChunk + c) + " (array " + number(array) + ")");
    }
  }
  return result;
}

SurfelFile readSurfelFile(const std::filesystem::path& path) {
  SurfelFileReader reader(path);
  SurfelFile file;
  file.sceneFingerprint = reader.sceneFingerprint();
  file.options = reader.options();
  file.nodes.assign(reader.nodes().begin(), reader.nodes().end());
  file.sceneTable = reader.sceneTable();
  const auto infos = reader.arrays();
  file.arrays.resize(infos.size());
  for (std::uint32_t a = 0; a < infos.size(); ++a) {
    SurfelArray& array = file.arrays[a];
    array.box = infos[a].box;
    array.coverage = infos[a].coverage;
    array.packing = infos[a].packing;
    array.packingEnd = infos[a].packingEnd;
    array.area = infos[a].area;
    array.twoSidedShare = infos[a].twoSidedShare;
    array.surfels = reader.readPrefix(a, infos[a].count);
  }
  return file;
}

}  // namespace pbs
