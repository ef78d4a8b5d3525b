// The .surfels file: every surfel array of a scene, stored so that any prefix of any array can be read
// on its own, checked by checksums, and tied to the scene it was made from by a fingerprint.
//
// Layout (version 4, little-endian, every offset in bytes from the start of the file):
//   header      fixed size: magic "PBSURFEL", version, scene fingerprint, the options the arrays were
//               made with, the counts and offsets of the two tables, a checksum of the header itself
//   array table one fixed-size record per array: box, coverage, packing at 1000 and at the end, area, surfel count,
//               colour encoding, data offset, the constant colour; followed by a checksum of the whole table
//   node table  one record per node: its stable path and the array it uses (instances share arrays);
//               followed by a checksum of the whole table
//   scene table the fingerprints of the scene's structure and of each mesh, and the exact world box of every
//               mesh instance, so that a renderer reads no vertex to check the scene or to know where each node
//               lies; followed by its checksum
//   data        per array: its surfels in order, surfelBytes(encoding) each, in chunks of kSurfelsPerChunk, and
//               after the last chunk one 64-bit checksum per chunk. Reading the first k surfels reads
//               the chunks holding them (and their checksums) and nothing else.
//
// A surfel takes 12 to 16 bytes (the authors' format used 20): position quantized to 21 bits per axis
// against the array's box (one 64-bit word), normal octahedron-encoded as two 16-bit snorms, then its
// colour as the array's encoding says: RGBA8, RGB8 where every surfel is opaque, or nothing where every
// surfel has the one colour the array record holds. Only what varies within an array is stored.
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/surfels/capture_defaults.hpp"
#include "pbs/surfels/ordering.hpp"
#include "pbs/surfels/prefilter_colors.hpp"
#include "pbs/surfels/surfel.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pbs {

// Version 2 added the colour filter to the header (and made normals face their capture view); version 3
// stores colours by what varies per array (SurfelColorEncoding); version 4 adds the scene table; version 5
// the loose octree the scene was organised as (SurfelFileOptions::octreeLeafTriangles); version 6 each
// array's two-sided share (SurfelArray::twoSidedShare), in what was a reserved field. Version 2 to 5 files
// are still read (share 0: no array is drawn as an open sheet); version 2 to 4 ones have no octree (version 2: every
// surfel RGBA; both: the boxes are computed from the scene's vertices); a version 1 file is refused: run pbs surfelize
// again.
inline constexpr std::uint32_t kSurfelFileVersion = 6;
inline constexpr std::uint32_t kOldestReadSurfelFileVersion = 2;
inline constexpr std::size_t kSurfelBytes = 16;  // a surfel with every field (PackedSurfel)
inline constexpr std::uint32_t kSurfelsPerChunk = 1024;
inline constexpr std::uint32_t kPositionBits = 21;

// How an array stores its surfels' colours: the writer picks the smallest that is exact.
enum class SurfelColorEncoding : std::uint32_t {
  Rgba = 0,      // 4 bytes a surfel
  Rgb = 1,       // 3 bytes a surfel; every surfel opaque (alpha 255)
  Constant = 2,  // none: every surfel has the array record's colour
};

// "rgba", "rgb", "constant".
const char* colorEncodingName(SurfelColorEncoding encoding);

// Bytes of one stored surfel: 12 (position and normal) and the colour's.
inline constexpr std::uint64_t surfelBytes(SurfelColorEncoding encoding) {
  return encoding == SurfelColorEncoding::Rgba ? 16 : encoding == SurfelColorEncoding::Rgb ? 15 : 12;
}

// The bytes `surfels` surfels take in the file, in chunks with one checksum each: what a range costs to
// read when it starts a chunk and ends at a chunk's end or the array's.
inline constexpr std::uint64_t storedSurfelBytes(std::uint64_t surfels, SurfelColorEncoding encoding) {
  constexpr std::uint64_t kChunkChecksumBytes = 8;
  return surfels * surfelBytes(encoding) + (surfels + kSurfelsPerChunk - 1) / kSurfelsPerChunk * kChunkChecksumBytes;
}

// SurfelArray::packing is measured on the first min(kPackingSample, N) surfels.
inline constexpr std::size_t kPackingSample = 1000;

// The options an array set was made with: part of the file so that a reader knows what it holds.
struct SurfelFileOptions {
  std::uint64_t threshold = 10000;                       // nodes above this many subtree triangles have arrays
  std::uint32_t maxSurfels = 10000;                      // array length limit
  std::uint32_t resolution = kDefaultCaptureResolution;  // capture resolution
  std::uint32_t directions = kDefaultCaptureDirections;  // capture view count
  SurfelOrdering ordering = SurfelOrdering::Farthest;    // which ordering made the arrays
  SurfelColors colors = SurfelColors::Pixel;             // how the surfels' colours were chosen
  std::uint64_t seed = 1;
  // 0: the arrays are of the scene's own hierarchy; N: of the scene rebuilt as a loose octree of leaves of
  // at most N triangles (buildLooseOctree), which every reader must rebuild the same to use the file.
  std::uint32_t octreeLeafTriangles = 0;
};

// One array: surfels in the frame of the node(s) using it (world = node's world transform × point).
struct SurfelArray {
  Bounds box;             // node-frame box; positions are quantized against it. Its centre is the origin
                          // the surfel positions are relative to.
  double coverage = 0.0;  // capture coverage estimate in [0, 1]
  double packing = 0.0;   // (mean nearest-neighbour distance of the first k = min(1000, N) surfels)² × k
  // The same of all N surfels. Where a subtree's parts lie far apart (a city), its first surfels spread
  // over the gaps and the two differ: the renderer interpolates between them (SplatArray::spacing).
  double packingEnd = 0.0;
  // Surface area of the node's subtree in the node frame, times the sides the captures saw of it
  // (CaptureResult::sidesSeen: 1 for a closed mesh, 2 for an open sheet seen from both sides): the area
  // the surfels stand for (the renderer's splat coverage, ρ(k)).
  double area = 0.0;
  // The share of the surfels whose surface the captures also saw from its other side (twoSidedShare), in
  // [0, 1] (version 6; 0 in older files), where a capture from triangles saw back faces (kOpenSheetSidesSeen;
  // else 0), and the mean of the children's for a capture from their surfels: near 1, the subtree is an open
  // sheet, whose surfels a renderer draws facing either way.
  float twoSidedShare = 0.0f;
  std::vector<Surfel> surfels;  // in order: every prefix is a usable, evenly spread subset
};

struct SurfelNodeRecord {
  std::string path;     // stable path of the node in the scene graph (see nodePath in surfel_nodes.hpp)
  std::uint32_t array;  // index into the arrays
};

// What a renderer needs of the scene without reading a vertex (version 4): the fingerprints that check a
// scene opened without its mesh arrays (structureFingerprint at open, meshFingerprint of each mesh when it
// is read; scene_fingerprint.hpp) and Hierarchy::instanceBounds, one per scene node. All empty (and
// structure 0) in a file of version 3 or 2.
struct SurfelSceneTable {
  std::uint64_t structure = 0;
  std::vector<std::uint64_t> meshes;
  std::vector<Bounds> instanceBounds;
};

// What makes a .surfels file one part of a file made by several machines (pbs surfelize --shard I/N): the
// arrays of shard `index` of a plan of `count` shards. A part holds every table of the whole file, and the
// arrays of other shards are empty in it; pbs merge puts the parts of all shards together.
// The most shards a plan may have (Slurm allows job arrays of up to 4 M tasks; a million parts would
// already be unwieldy), so that a shard count from a command line or a file never sizes a table by
// billions.
inline constexpr std::uint32_t kMaxSurfelShards = 1'000'000;

struct SurfelShardTable {
  std::uint32_t index = 0;
  std::uint32_t count = 1;
  std::uint64_t plan = 0;             // the shard plan's identity: parts of one plan have the same
  std::vector<std::uint32_t> arrays;  // the arrays this part holds, ascending
};

struct SurfelFile {
  std::uint64_t sceneFingerprint = 0;  // sceneFingerprint() of the scene the arrays belong to
  SurfelFileOptions options;
  std::vector<SurfelArray> arrays;
  std::vector<SurfelNodeRecord> nodes;  // in preorder of the scene
  SurfelSceneTable sceneTable;
};

// The per-array values of the array table, without the surfels.
struct SurfelArrayInfo {
  Bounds box;
  double coverage = 0.0;
  double packing = 0.0;
  double packingEnd = 0.0;
  double area = 0.0;
  float twoSidedShare = 0.0f;
  std::uint32_t count = 0;
  std::uint64_t dataOffset = 0;
  SurfelColorEncoding colorEncoding = SurfelColorEncoding::Rgba;
  glm::u8vec4 constantColor{0};  // every surfel's colour when colorEncoding is Constant, else 0
};

// Writes `file` to a temporary name beside `path`, then renames it over `path`: readers see the old
// file or the whole new one, never a part. Throws std::runtime_error naming the path on I/O failure
// (the temporary is removed), std::invalid_argument for a node naming a missing array or an array
// whose box, coverage, packing or area is NaN or infinite or whose two-sided share lies outside [0, 1] (nothing
// is written; the reader refuses such values too).
void writeSurfelFile(const std::filesystem::path& path, const SurfelFile& file);

// Writes a .surfels file while its arrays are still being made: each array's data goes to the temporary
// file as soon as every array before it is there (an array that arrives early waits, encoded, for
// those before it), so memory holds only the arrays that wait, not the whole file. finish() writes
// the tables in front of the data and renames the temporary over `path`; a writer destroyed before
// finish() removes its temporary, so a failed run leaves no file under `path`. The bytes are the same
// as writeSurfelFile's (which is this writer fed every array in order). One call at a time. Errors as
// for writeSurfelFile: std::invalid_argument for a bad node or instance box (constructor) or array (add),
// then nothing more is written; std::runtime_error for I/O.
// With `shard`, the file is that shard's part (its table goes after the scene table).
class SurfelFileWriter {
 public:
  SurfelFileWriter(const std::filesystem::path& path, std::uint64_t sceneFingerprint, const SurfelFileOptions& options,
                   std::vector<SurfelNodeRecord> nodes, SurfelSceneTable sceneTable, std::uint32_t arrayCount,
                   std::optional<SurfelShardTable> shard = std::nullopt);
  ~SurfelFileWriter();
  SurfelFileWriter(const SurfelFileWriter&) = delete;
  SurfelFileWriter& operator=(const SurfelFileWriter&) = delete;

  // Array `index` (each index once, in any order).
  void add(std::uint32_t index, const SurfelArray& array);
  // Array `index` as another file stores it: its record (the data offset is this file's own) and its data
  // as SurfelFileReader::readStored returns it, copied as it is (std::invalid_argument for data of
  // another size than the record says).
  void addStored(std::uint32_t index, const SurfelArrayInfo& info, std::vector<std::uint8_t> data);
  // Throws std::logic_error unless every array was added.
  void finish();

  // Encoded bytes held for arrays waiting on an earlier one.
  std::uint64_t bytesWaiting() const { return bytesWaiting_; }

 private:
  void writeReadyArrays();

  std::filesystem::path path_, temporary_;
  std::ofstream out_;
  std::uint64_t fingerprint_;
  SurfelFileOptions options_;
  std::vector<SurfelNodeRecord> nodes_;
  SurfelSceneTable sceneTable_;
  std::optional<SurfelShardTable> shard_;
  std::vector<SurfelArrayInfo> infos_;
  std::vector<std::optional<std::vector<std::uint8_t>>> waiting_;  // encoded data by index, until written
  std::uint32_t written_ = 0;                                      // arrays [0, written_) are in the file
  std::uint64_t dataEnd_ = 0;                                      // where the next array's data goes
  std::uint64_t bytesWaiting_ = 0;
  bool finished_ = false;
};

// Random access to a .surfels file. Opening reads and checks the header and both tables (magic,
// version, checksums, every offset and count inside the file); readPrefix reads only the chunks
// holding the requested surfels and checks their checksums. Every problem throws InputError naming
// the file and the element ("header", "array table", "node /0/3" or, for data shared by several
// nodes, the first node using the array).
class SurfelFileReader {
 public:
  explicit SurfelFileReader(const std::filesystem::path& path);

  const std::filesystem::path& path() const { return path_; }
  std::uint64_t sceneFingerprint() const { return fingerprint_; }
  const SurfelFileOptions& options() const { return options_; }
  std::span<const SurfelArrayInfo> arrays() const { return arrays_; }
  std::span<const SurfelNodeRecord> nodes() const { return nodes_; }
  const SurfelSceneTable& sceneTable() const { return sceneTable_; }
  // The shard table of a part (see SurfelShardTable), or nothing for a whole file.
  const std::optional<SurfelShardTable>& shard() const { return shard_; }

  // Throws InputError naming the file and "header" unless the file was made for the scene with this
  // sceneFingerprint(): surfels of another scene (or an edited one) must never be drawn in its place.
  // Once it passed, sceneRequired() is true.
  void requireScene(std::uint64_t fingerprint);
  // The same for a scene opened without its mesh arrays, by structureFingerprint against the scene
  // table's (InputError naming "scene table" for a file without one: version 3 or 2); each mesh is
  // checked when it is read (LazyMeshes).
  void requireStructure(std::uint64_t structure);
  bool sceneRequired() const { return sceneRequired_; }

  // The first min(count, arrays()[array].count) surfels of an array, decoded (positions relative to the
  // box centre). Throws std::out_of_range for an array index out of range.
  std::vector<Surfel> readPrefix(std::uint32_t array, std::uint32_t count);
  // Surfels [first, first + count) of an array, clamped to it; `first` must start a chunk (a multiple of
  // kSurfelsPerChunk; std::invalid_argument otherwise). Reads and checks only the chunks holding them:
  // a prefix that grows reads only its new chunks.
  std::vector<Surfel> readRange(std::uint32_t array, std::uint32_t first, std::uint32_t count);
  // An array's data as stored, its chunks then their checksums, every checksum checked: what
  // SurfelFileWriter::addStored copies into another file.
  std::vector<std::uint8_t> readStored(std::uint32_t array);

  // Bytes read from the file by readPrefix calls so far (the data of the chunks and their checksums):
  // lets a test check that a prefix costs only its own bytes.
  std::uint64_t dataBytesRead() const { return dataBytesRead_; }
  // The header and both tables with their checksums: what opening the file reads.
  std::uint64_t tablesBytes() const { return tablesBytes_; }

 private:
  // Surfels [first, first + surfels) of `array` as stored (`first` starts a chunk, the range ends at a
  // chunk's end or the array's) and their chunks' checksums, each chunk checked.
  struct StoredChunks {
    std::vector<std::uint8_t> data, checksums;
  };
  StoredChunks readChunks(std::uint32_t array, std::uint32_t first, std::uint32_t surfels);

  std::filesystem::path path_;
  std::ifstream stream_;
  std::uint64_t fingerprint_ = 0;
  std::uint32_t version_ = 0;
  SurfelFileOptions options_;
  std::vector<SurfelArrayInfo> arrays_;
  std::vector<SurfelNodeRecord> nodes_;
  SurfelSceneTable sceneTable_;
  std::optional<SurfelShardTable> shard_;
  bool sceneRequired_ = false;
  std::uint64_t dataBytesRead_ = 0;
  std::uint64_t tablesBytes_ = 0;
};

// The whole file, every checksum checked.
SurfelFile readSurfelFile(const std::filesystem::path& path);

// The codec, exposed for tests and for the error bounds they assert. surfel.position is relative to
// box.center(), as in SurfelArray.
// Position: each axis maps [box.min, box.max] onto 0 … 2^21 − 1, rounding to nearest, so the error per
// axis is at most (box extent on that axis) / (2^21 − 1) / 2 plus float rounding; an axis of zero
// extent decodes exactly to the box's value. Points outside the box are clamped to it.
// Normal: octahedral map, 16-bit snorm per coordinate; decoded normals are unit length and within
// kMaxNormalErrorRadians of a unit input. A zero or non-finite normal encodes as +Z.
// NaN positions encode as the box centre. Neither function ever produces NaN or Inf.
inline constexpr double kMaxNormalErrorRadians = 1e-4;
using PackedSurfel = std::array<std::uint8_t, kSurfelBytes>;
PackedSurfel encodeSurfel(const Surfel& surfel, const Bounds& box);
Surfel decodeSurfel(const PackedSurfel& packed, const Bounds& box);

}  // namespace pbs
