// The byte layout of a .surfels file, shared by the writer and the reader: each record's fields are
// listed once, in a layout function that a byte sink (writing) and a byte source (reading) both walk.
//
// Version 5, all integers little-endian, doubles as their IEEE-754 bits:
//   header (112 bytes at offset 0)
//     0  magic "PBSURFEL"          8 bytes
//     8  version                   u32
//    12  flags                     u32 (version 5: kShardPartFlag; reserved, 0, before)
//    16  scene fingerprint         u64
//    24  options.threshold         u64
//    32  options.maxSurfels        u32
//    36  options.resolution        u32
//    40  options.directions        u32
//    44  options.ordering          u32
//    48  options.colors            u32
//    52  options.octreeLeafTriangles u32 (version 5; reserved, 0, before)
//    56  options.seed              u64
//    64  array count               u32
//    68  node count                u32
//    72  array table offset        u64
//    80  node table offset         u64
//    88  node table bytes          u64 (records only, without the checksum)
//    96  file bytes                u64 (the whole file)
//   104  header checksum           u64 (Hash64 of bytes 0…103)
//   array table: array count × 104-byte records, then u64 checksum of the records
//     box.min xyz f64×3, box.max xyz f64×3, coverage f64, packing f64, packing end f64, area f64, surfel count u32,
//     colour encoding u32 (SurfelColorEncoding), data offset u64, constant colour RGBA u8×4, two-sided share
//     f32 (version 6; a reserved u32, 0, before)
//   node table: node count × (shared u32, suffix length u32, suffix bytes, array index u32), then u64
//     checksum; a node's path is the first `shared` bytes of the previous node's path, then the suffix
//     (front coding: paths in preorder share most of their bytes with the one before)
//   scene table (version 4), right after the node table's checksum: scene node count u32, mesh count u32,
//     structure fingerprint u64, per mesh its fingerprint u64, then per scene node in index order its mesh
//     instance's exact world box, min xyz f64×3 and max xyz f64×3 (an empty box, +inf then -inf, for a node
//     without a mesh), then u64 checksum
//   shard table (a part made by one shard, kShardPartFlag), right after the scene table's checksum: shard
//     index u32, shard count u32, plan identity u64, held array count u32, the held arrays' indices u32 each
//     (ascending), then u64 checksum; the arrays a part does not hold are empty in it (no surfels)
//   data, per array at its data offset: count × surfelBytes(encoding) surfels (chunks of kSurfelsPerChunk), then
//     one u64 checksum per chunk (Hash64 of the chunk's bytes, seeded by the chunk's index); a surfel is
//     position u64, normal 2 × i16, then its colour: RGBA u8×4, RGB u8×3 or nothing
// Version 4 has 0 in place of the octree. Version 3 has no scene table. Version 2 differs in its 96-byte array records
// (the colour encoding's place is reserved, 0 so RGBA, and the record ends after the data offset) and in its node
// records (path length u32, the whole path, array index u32).
#pragma once

#include "pbs/raster/hash64.hpp"
#include "pbs/surfels/surfel_file.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbs::surfel_file {

inline constexpr std::array<std::uint8_t, 8> kMagic = {'P', 'B', 'S', 'U', 'R', 'F', 'E', 'L'};
inline constexpr std::uint64_t kHeaderBytes = 112;
inline constexpr std::uint64_t kHeaderChecksumOffset = 104;
// An array record's size in a file of `version`.
inline constexpr std::uint64_t arrayRecordBytes(std::uint32_t version) { return version >= 3 ? 104 : 96; }
// The least a node record takes (an empty path or suffix) in a file of `version`.
inline constexpr std::uint64_t nodeRecordMinBytes(std::uint32_t version) { return version >= 3 ? 12 : 8; }
inline constexpr std::uint64_t kChecksumBytes = 8;
// The scene table of `nodes` boxes and `meshes` fingerprints with its checksum (version 4).
inline constexpr std::uint64_t kSceneTableHeadBytes = 16;  // the counts and the structure's fingerprint
inline constexpr std::uint64_t kBoxBytes = 48;
inline constexpr std::uint64_t sceneTableBytes(std::uint64_t nodes, std::uint64_t meshes) {
  return kSceneTableHeadBytes + meshes * 8 + nodes * kBoxBytes + kChecksumBytes;
}
// The header flag of a shard's part, and its shard table of `arrays` held arrays with its checksum.
inline constexpr std::uint32_t kShardPartFlag = 1;
inline constexpr std::uint64_t kShardTableHeadBytes = 20;  // index, count, plan, held array count
inline constexpr std::uint64_t shardTableBytes(std::uint64_t arrays) {
  return kShardTableHeadBytes + arrays * 4 + kChecksumBytes;
}

// Distinct seeds, so that a table's bytes never pass for another element's.
inline constexpr std::uint64_t kHeaderSeed = 0x50425348'45414452ull;
inline constexpr std::uint64_t kArrayTableSeed = 0x50425341'52524159ull;
inline constexpr std::uint64_t kNodeTableSeed = 0x5042534E'4F444553ull;
inline constexpr std::uint64_t kChunkSeed = 0x50425344'41544100ull;
inline constexpr std::uint64_t kSceneTableSeed = 0x50425353'43454E45ull;
inline constexpr std::uint64_t kShardTableSeed = 0x50425353'48415244ull;

struct Header {
  std::array<std::uint8_t, 8> magic = kMagic;
  std::uint32_t version = kSurfelFileVersion;
  std::uint32_t flags = 0;  // version 5 (0 before: a reserved field)
  std::uint64_t fingerprint = 0;
  std::uint64_t threshold = 0;
  std::uint32_t maxSurfels = 0;
  std::uint32_t resolution = 0;
  std::uint32_t directions = 0;
  std::uint32_t ordering = 0;
  std::uint32_t colors = 0;
  std::uint32_t octreeLeafTriangles = 0;  // version 5 (0 before: a reserved field); keeps the seed 8-byte aligned
  std::uint64_t seed = 0;
  std::uint32_t arrayCount = 0;
  std::uint32_t nodeCount = 0;
  std::uint64_t arrayTableOffset = 0;
  std::uint64_t nodeTableOffset = 0;
  std::uint64_t nodeTableBytes = 0;
  std::uint64_t fileBytes = 0;
};

// The header's fields in file order, up to (not including) its checksum.
template <class Io>
void layoutHeader(Io& io, Header& h) {
  io.raw(h.magic);
  io.u32(h.version);
  io.u32(h.flags);
  io.u64(h.fingerprint);
  io.u64(h.threshold);
  io.u32(h.maxSurfels);
  io.u32(h.resolution);
  io.u32(h.directions);
  io.u32(h.ordering);
  io.u32(h.colors);
  io.u32(h.octreeLeafTriangles);
  io.u64(h.seed);
  io.u32(h.arrayCount);
  io.u32(h.nodeCount);
  io.u64(h.arrayTableOffset);
  io.u64(h.nodeTableOffset);
  io.u64(h.nodeTableBytes);
  io.u64(h.fileBytes);
}

// An array record of a file of `version`. The encoding is read as a number: the reader checks it.
// A box: min xyz, then max xyz.
template <class Io>
void layoutBox(Io& io, Bounds& box) {
  for (int i = 0; i < 3; ++i) io.f64(box.min[i]);
  for (int i = 0; i < 3; ++i) io.f64(box.max[i]);
}

template <class Io>
void layoutArray(Io& io, SurfelArrayInfo& a, std::uint32_t& encoding, std::uint32_t version) {
  std::uint32_t reserved = 0;
  layoutBox(io, a.box);
  io.f64(a.coverage);
  io.f64(a.packing);
  io.f64(a.packingEnd);
  io.f64(a.area);
  io.u32(a.count);
  io.u32(encoding);  // reserved (0: RGBA) in version 2
  io.u64(a.dataOffset);
  if (version < 3) return;
  for (int i = 0; i < 4; ++i) io.u8(a.constantColor[i]);
  if (version < 6) {
    io.u32(reserved);
    return;
  }
  std::uint32_t share = std::bit_cast<std::uint32_t>(a.twoSidedShare);
  io.u32(share);
  a.twoSidedShare = std::bit_cast<float>(share);
}

// A shard table's fields before its held arrays' indices.
template <class Io>
void layoutShardHead(Io& io, SurfelShardTable& shard, std::uint32_t& arrays) {
  io.u32(shard.index);
  io.u32(shard.count);
  io.u64(shard.plan);
  io.u32(arrays);
}

// A node record as stored: version 3 keeps of its path only what differs from the previous node's.
struct StoredNode {
  std::uint32_t shared = 0;  // bytes taken from the previous path (version 3; 0 in version 2)
  std::string suffix;        // the rest of the path (version 2: all of it)
  std::uint32_t array = 0;
};

template <class Io>
void layoutNode(Io& io, StoredNode& n, std::uint32_t version) {
  if (version >= 3) io.u32(n.shared);
  io.string(n.suffix);
  io.u32(n.array);
}

// `node` as stored after a node whose path is `previous`.
inline StoredNode storedNode(const SurfelNodeRecord& node, const std::string& previous) {
  const auto end = std::mismatch(previous.begin(), previous.end(), node.path.begin(), node.path.end()).first;
  const auto shared = std::uint32_t(end - previous.begin());
  return {shared, node.path.substr(shared), node.array};
}

// What is wrong with the first of an array's values that is NaN or Inf ("box is not finite", also
// "coverage", "packing", "area") or out of its range ("two-sided share is not in [0, 1]"), or nullptr. pbs never
// writes one and the reader refuses one: a renderer would place, count or cull surfels with it.
template <class Array>
const char* invalidArrayValue(const Array& a) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(a.box.min[i]) || !std::isfinite(a.box.max[i])) return "box is not finite";
  if (!std::isfinite(a.coverage)) return "coverage is not finite";
  if (!std::isfinite(a.packing) || !std::isfinite(a.packingEnd)) return "packing is not finite";
  if (!std::isfinite(a.area)) return "area is not finite";
  if (!(a.twoSidedShare >= 0.0f && a.twoSidedShare <= 1.0f)) return "two-sided share is not in [0, 1]";
  return nullptr;
}

// An instance box as the file allows it: empty (as Bounds{} is, +inf then -inf) or finite with min ≤ max.
inline bool validInstanceBox(const Bounds& box) {
  const Bounds none;
  if (box.min == none.min && box.max == none.max) return true;
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(box.min[i]) || !std::isfinite(box.max[i]) || box.min[i] > box.max[i]) return false;
  return true;
}

inline std::uint64_t chunkCount(std::uint64_t surfels) { return (surfels + kSurfelsPerChunk - 1) / kSurfelsPerChunk; }

inline std::uint64_t chunkChecksum(std::span<const std::uint8_t> chunk, std::uint64_t chunkIndex) {
  return Hash64::of(chunk.data(), chunk.size(), kChunkSeed + chunkIndex);
}

inline std::uint64_t readU64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

// Appends fields as little-endian bytes.
struct ByteSink {
  std::vector<std::uint8_t> bytes;

  void raw(const std::array<std::uint8_t, 8>& v) { bytes.insert(bytes.end(), v.begin(), v.end()); }
  void u8(const std::uint8_t& v) { bytes.push_back(v); }
  void u32(const std::uint32_t& v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(std::uint8_t(v >> (8 * i)));
  }
  void u64(const std::uint64_t& v) {
    for (int i = 0; i < 8; ++i) bytes.push_back(std::uint8_t(v >> (8 * i)));
  }
  void f64(const double& v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void string(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
};

// A field ran past the end of the bytes it was read from (the reader turns it into an InputError).
struct ShortRecord : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads fields from a byte range, never past its end.
struct ByteSource {
  std::span<const std::uint8_t> bytes;
  std::size_t at = 0;

  std::size_t remaining() const { return bytes.size() - at; }
  const std::uint8_t* take(std::size_t n) {
    if (n > remaining()) throw ShortRecord("record runs past the end of its table");
    const std::uint8_t* p = bytes.data() + at;
    at += n;
    return p;
  }
  void raw(std::array<std::uint8_t, 8>& v) { std::memcpy(v.data(), take(8), 8); }
  void u8(std::uint8_t& v) { v = *take(1); }
  void u32(std::uint32_t& v) {
    const std::uint8_t* p = take(4);
    v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  }
  void u64(std::uint64_t& v) { v = readU64(take(8)); }
  void f64(double& v) {
    std::uint64_t bits = 0;
    u64(bits);
    v = std::bit_cast<double>(bits);
  }
  // The length is checked against the bytes left before anything is allocated.
  void string(std::string& s) {
    std::uint32_t size = 0;
    u32(size);
    const std::uint8_t* p = take(size);
    s.assign(reinterpret_cast<const char*>(p), size);
  }
};

}  // namespace pbs::surfel_file
