// SurfelFileWriter: data written array by array behind a reserved table space, the tables last, then a
// rename; writeSurfelFile feeds it a whole file.
#include "pbs/surfels/surfel_file.hpp"

#include "surfel_file_layout.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unistd.h>

namespace pbs {
namespace {

using namespace surfel_file;

constexpr std::uint64_t kU32Max = std::numeric_limits<std::uint32_t>::max();

void checkNodes(std::span<const SurfelNodeRecord> nodes, std::uint64_t arrayCount) {
  if (nodes.size() > kU32Max) throw std::invalid_argument("surfel file: too many nodes");
  for (const SurfelNodeRecord& node : nodes) {
    if (node.array >= arrayCount) {
      throw std::invalid_argument("surfel file: node " + node.path + " uses array " + std::to_string(node.array) +
                                  " of " + std::to_string(arrayCount));
    }
    if (node.path.size() > kU32Max) throw std::invalid_argument("surfel file: node path too long");
  }
}

void checkArray(std::size_t index, const SurfelArray& array) {
  if (array.surfels.size() > kU32Max)
    throw std::invalid_argument("surfel file: array " + std::to_string(index) + " has more than 2^32 - 1 surfels");
  if (const char* problem = invalidArrayValue(array))
    throw std::invalid_argument("surfel file: array " + std::to_string(index) + ": " + problem);
}

void appendChecksum(ByteSink& sink, std::size_t from, std::uint64_t seed) {
  sink.u64(Hash64::of(sink.bytes.data() + from, sink.bytes.size() - from, seed));
}

// The node records as stored, each front-coded against the one before.
std::vector<StoredNode> storedNodes(std::span<const SurfelNodeRecord> nodes) {
  std::vector<StoredNode> stored;
  stored.reserve(nodes.size());
  const std::string none;
  for (std::size_t n = 0; n < nodes.size(); ++n)
    stored.push_back(storedNode(nodes[n], n > 0 ? nodes[n - 1].path : none));
  return stored;
}

std::uint64_t nodeTableBytes(std::span<const StoredNode> stored) {
  std::uint64_t bytes = 0;
  for (const StoredNode& node : stored) bytes += nodeRecordMinBytes(kSurfelFileVersion) + node.suffix.size();
  return bytes;
}

void checkSceneTable(const SurfelSceneTable& table) {
  if (table.instanceBounds.size() > kU32Max || table.meshes.size() > kU32Max)
    throw std::invalid_argument("surfel file: too many nodes or meshes in the scene table");
  const std::span<const Bounds> boxes = table.instanceBounds;
  for (std::size_t n = 0; n < boxes.size(); ++n)
    if (!validInstanceBox(boxes[n]))
      throw std::invalid_argument("surfel file: instance box of node " + std::to_string(n) +
                                  " is neither empty nor finite with min <= max");
}

void checkShardTable(const SurfelShardTable& shard, std::uint64_t arrayCount) {
  if (shard.count == 0 || shard.index >= shard.count || shard.count > kMaxSurfelShards)
    throw std::invalid_argument("surfel file: shard " + std::to_string(shard.index) + " of " +
                                std::to_string(shard.count) + " (at most " + std::to_string(kMaxSurfelShards) +
                                " shards)");
  for (std::size_t i = 0; i < shard.arrays.size(); ++i)
    if (shard.arrays[i] >= arrayCount || (i > 0 && shard.arrays[i] <= shard.arrays[i - 1]))
      throw std::invalid_argument("surfel file: a shard's arrays must be ascending and below the array count");
}

// Where the data begins: after the header and the tables with their checksums.
std::uint64_t dataStart(std::uint64_t arrayCount, std::span<const SurfelNodeRecord> nodes,
                        const SurfelSceneTable& scene, const std::optional<SurfelShardTable>& shard) {
  return kHeaderBytes + arrayCount * arrayRecordBytes(kSurfelFileVersion) + kChecksumBytes +
         nodeTableBytes(storedNodes(nodes)) + kChecksumBytes +
         sceneTableBytes(scene.instanceBounds.size(), scene.meshes.size()) +
         (shard ? shardTableBytes(shard->arrays.size()) : 0);
}

// The smallest colour encoding that keeps every surfel's colour: one colour for all, or no alpha where
// every surfel is opaque.
SurfelColorEncoding colorEncodingOf(const std::vector<Surfel>& surfels) {
  if (surfels.empty()) return SurfelColorEncoding::Rgba;
  const glm::u8vec4 first = surfels.front().color;
  if (std::all_of(surfels.begin(), surfels.end(), [&](const Surfel& s) { return s.color == first; }))
    return SurfelColorEncoding::Constant;
  if (std::all_of(surfels.begin(), surfels.end(), [](const Surfel& s) { return s.color.a == 255; }))
    return SurfelColorEncoding::Rgb;
  return SurfelColorEncoding::Rgba;
}

// One array's chunks, then its chunk checksums. A packed surfel's first surfelBytes(encoding) bytes are
// what the encoding stores (position, normal, then as many colour channels as it keeps).
std::vector<std::uint8_t> encodeArrayData(const SurfelArray& array, SurfelColorEncoding encoding) {
  std::vector<std::uint8_t> data;
  data.reserve(storedSurfelBytes(array.surfels.size(), encoding));
  ByteSink checksums;
  const auto stored = std::ptrdiff_t(surfelBytes(encoding));
  for (std::size_t first = 0; first < array.surfels.size(); first += kSurfelsPerChunk) {
    const std::size_t chunkStart = data.size();
    const std::size_t end = std::min<std::size_t>(first + kSurfelsPerChunk, array.surfels.size());
    for (std::size_t i = first; i < end; ++i) {
      const PackedSurfel packed = encodeSurfel(array.surfels[i], array.box);
      data.insert(data.end(), packed.begin(), packed.begin() + stored);
    }
    checksums.u64(chunkChecksum(std::span(data).subspan(chunkStart), first / kSurfelsPerChunk));
  }
  data.insert(data.end(), checksums.bytes.begin(), checksums.bytes.end());
  return data;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& why) {
  throw std::runtime_error("cannot write surfel file " + path.string() + ": " + why);
}

}  // namespace

SurfelFileWriter::SurfelFileWriter(const std::filesystem::path& path, std::uint64_t sceneFingerprint,
                                   const SurfelFileOptions& options, std::vector<SurfelNodeRecord> nodes,
                                   SurfelSceneTable sceneTable, std::uint32_t arrayCount,
                                   std::optional<SurfelShardTable> shard)
    : path_(path),
      fingerprint_(sceneFingerprint),
      options_(options),
      nodes_(std::move(nodes)),
      sceneTable_(std::move(sceneTable)),
      shard_(std::move(shard)),
      infos_(arrayCount),
      waiting_(arrayCount) {
  checkNodes(nodes_, arrayCount);
  checkSceneTable(sceneTable_);
  if (shard_) checkShardTable(*shard_, arrayCount);
  temporary_ = path_;
  temporary_ += ".tmp-" + std::to_string(::getpid());
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) fail(path_, "cannot create " + temporary_.string());
  dataEnd_ = dataStart(arrayCount, nodes_, sceneTable_, shard_);
  out_.seekp(std::streamoff(dataEnd_));
  if (!out_) fail(path_, "cannot seek in " + temporary_.string());
}

SurfelFileWriter::~SurfelFileWriter() {
  if (finished_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
}

void SurfelFileWriter::add(std::uint32_t index, const SurfelArray& array) {
  checkArray(index, array);
  const SurfelColorEncoding encoding = colorEncodingOf(array.surfels);
  const SurfelArrayInfo info{
      .box = array.box,
      .coverage = array.coverage,
      .packing = array.packing,
      .packingEnd = array.packingEnd,
      .area = array.area,
      .twoSidedShare = array.twoSidedShare,
      .count = std::uint32_t(array.surfels.size()),
      .dataOffset = 0,
      .colorEncoding = encoding,
      .constantColor = encoding == SurfelColorEncoding::Constant ? array.surfels.front().color : glm::u8vec4(0)};
  addStored(index, info, encodeArrayData(array, encoding));
}

void SurfelFileWriter::addStored(std::uint32_t index, const SurfelArrayInfo& info, std::vector<std::uint8_t> data) {
  if (index >= infos_.size() || index < written_ || waiting_[index])
    throw std::invalid_argument("surfel file: array " + std::to_string(index) + " added twice or out of range");
  if (data.size() != storedSurfelBytes(info.count, info.colorEncoding))
    throw std::invalid_argument("surfel file: array " + std::to_string(index) + ": " + std::to_string(data.size()) +
                                " bytes of data for " + std::to_string(info.count) + " surfels");
  infos_[index] = info;
  infos_[index].dataOffset = 0;
  bytesWaiting_ += data.size();
  waiting_[index] = std::move(data);
  writeReadyArrays();
}

void SurfelFileWriter::writeReadyArrays() {
  for (; written_ < infos_.size() && waiting_[written_]; ++written_) {
    const std::vector<std::uint8_t>& data = *waiting_[written_];
    out_.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
    if (!out_) fail(path_, "write failed");
    infos_[written_].dataOffset = dataEnd_;
    dataEnd_ += data.size();
    bytesWaiting_ -= data.size();
    waiting_[written_].reset();
  }
}

void SurfelFileWriter::finish() {
  if (written_ != infos_.size()) throw std::logic_error("SurfelFileWriter::finish: arrays are missing");
  Header header;
  header.fingerprint = fingerprint_;
  header.threshold = options_.threshold;
  header.maxSurfels = options_.maxSurfels;
  header.resolution = options_.resolution;
  header.directions = options_.directions;
  header.ordering = static_cast<std::uint32_t>(options_.ordering);
  header.colors = static_cast<std::uint32_t>(options_.colors);
  header.seed = options_.seed;
  header.octreeLeafTriangles = options_.octreeLeafTriangles;
  header.flags = shard_ ? kShardPartFlag : 0;
  header.arrayCount = static_cast<std::uint32_t>(infos_.size());
  header.nodeCount = static_cast<std::uint32_t>(nodes_.size());
  header.arrayTableOffset = kHeaderBytes;
  header.nodeTableOffset = header.arrayTableOffset + infos_.size() * arrayRecordBytes(header.version) + kChecksumBytes;
  std::vector<StoredNode> stored = storedNodes(nodes_);
  header.nodeTableBytes = nodeTableBytes(stored);
  header.fileBytes = dataEnd_;

  ByteSink sink;
  layoutHeader(sink, header);
  appendChecksum(sink, 0, kHeaderSeed);
  const std::size_t arrayTable = sink.bytes.size();
  for (SurfelArrayInfo& info : infos_) {
    auto encoding = static_cast<std::uint32_t>(info.colorEncoding);
    layoutArray(sink, info, encoding, header.version);
  }
  appendChecksum(sink, arrayTable, kArrayTableSeed);
  const std::size_t nodeTable = sink.bytes.size();
  for (StoredNode& node : stored) layoutNode(sink, node, header.version);
  appendChecksum(sink, nodeTable, kNodeTableSeed);
  const std::size_t sceneTable = sink.bytes.size();
  sink.u32(std::uint32_t(sceneTable_.instanceBounds.size()));
  sink.u32(std::uint32_t(sceneTable_.meshes.size()));
  sink.u64(sceneTable_.structure);
  for (const std::uint64_t mesh : sceneTable_.meshes) sink.u64(mesh);
  for (Bounds& box : sceneTable_.instanceBounds) layoutBox(sink, box);
  appendChecksum(sink, sceneTable, kSceneTableSeed);
  if (shard_) {
    const std::size_t shardTable = sink.bytes.size();
    auto held = std::uint32_t(shard_->arrays.size());
    layoutShardHead(sink, *shard_, held);
    for (const std::uint32_t array : shard_->arrays) sink.u32(array);
    appendChecksum(sink, shardTable, kShardTableSeed);
  }

  out_.seekp(0);
  out_.write(reinterpret_cast<const char*>(sink.bytes.data()), std::streamsize(sink.bytes.size()));
  out_.flush();
  if (!out_) fail(path_, "write failed");
  out_.close();
  if (out_.fail()) fail(path_, "close failed");
  std::error_code ec;
  std::filesystem::rename(temporary_, path_, ec);
  if (ec) fail(path_, "rename failed: " + ec.message());
  finished_ = true;
}

void writeSurfelFile(const std::filesystem::path& path, const SurfelFile& file) {
  if (file.arrays.size() > kU32Max) throw std::invalid_argument("surfel file: too many arrays");
  // Every check before the first byte: a bad file writes nothing at all.
  checkNodes(file.nodes, file.arrays.size());
  checkSceneTable(file.sceneTable);
  for (std::size_t a = 0; a < file.arrays.size(); ++a) checkArray(a, file.arrays[a]);
  SurfelFileWriter writer(path, file.sceneFingerprint, file.options, file.nodes, file.sceneTable,
                          std::uint32_t(file.arrays.size()));
  for (std::size_t a = 0; a < file.arrays.size(); ++a) writer.add(std::uint32_t(a), file.arrays[a]);
  writer.finish();
}

}  // namespace pbs
