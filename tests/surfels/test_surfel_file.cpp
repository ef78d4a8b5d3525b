// The .surfels format: round trips, codec error bounds, prefix reads and their cost, corruption and
// truncation as InputError, atomic writes, and the scene fingerprint.
#include <pbs/raster/hash64.hpp>
#include <pbs/raster/seeded_random.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/surfels/surfel_file.hpp>

// The private layout, only to forge files whose checksums are right but whose counts are not.
#include "../../surfels/src/surfel_file_layout.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

namespace pbs {
namespace {

using test::readFile;
using test::ScratchDir;
using test::writeFile;

constexpr double kPositionSteps = double((1u << kPositionBits) - 1);

Bounds makeBox(glm::dvec3 centre, glm::dvec3 extent) { return {centre - extent * 0.5, centre + extent * 0.5}; }

glm::vec3 randomUnit(SeededRandom& rng) {
  const double z = rng.range(-1.0, 1.0);
  const double phi = rng.range(0.0, 2.0 * std::numbers::pi);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return glm::vec3(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
}

// A point of the box relative to its centre; the box's ends relative to the centre are exact
// differences, unlike ±size/2 for a small box far from the origin.
glm::vec3 randomInside(SeededRandom& rng, const Bounds& box) {
  const glm::dvec3 lo = box.min - box.center();
  const glm::dvec3 hi = box.max - box.center();
  return glm::vec3(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z));
}

// Surfels spread over the box (positions relative to its centre).
std::vector<Surfel> randomSurfels(std::size_t count, const Bounds& box, std::uint64_t seed) {
  SeededRandom rng(seed);
  std::vector<Surfel> surfels(count);
  for (Surfel& s : surfels) {
    s.position = randomInside(rng, box);
    s.normal = randomUnit(rng);
    s.color = glm::u8vec4(rng.below(256), rng.below(256), rng.below(256), rng.below(256));
  }
  return surfels;
}

SurfelArray makeArray(std::size_t count, const Bounds& box, std::uint64_t seed) {
  SurfelArray array;
  array.box = box;
  array.coverage = 0.25 + 0.001 * double(seed);
  array.packing = 1.5 * double(seed);
  array.area = 12.0 + double(seed);
  array.twoSidedShare = 0.25f * float(seed % 5);
  array.surfels = randomSurfels(count, box, seed);
  return array;
}

// Three arrays (one with three chunks, one empty, one tiny); node /0/3 and /1 share array 0.
SurfelFile sampleFile() {
  SurfelFile file;
  file.sceneFingerprint = 0x0123456789ABCDEFull;
  file.options = {.threshold = 5000,
                  .maxSurfels = 4000,
                  .resolution = 256,
                  .directions = 6,
                  .ordering = SurfelOrdering::Dart,
                  .colors = SurfelColors::Pixel,
                  .seed = 77};
  file.arrays.push_back(makeArray(2500, makeBox({1e6, -2e6, 3.5e5}, {10.0, 4.0, 0.5}), 1));
  file.arrays.push_back(makeArray(0, makeBox({0, 0, 0}, {1, 1, 1}), 2));
  file.arrays.push_back(makeArray(5, makeBox({-3, 2, 1}, {1e-3, 2e-3, 0.0}), 3));
  file.nodes = {{"/0/3", 0}, {"/0/3/1", 2}, {"/1", 0}, {"/2", 1}};
  file.sceneTable = {
      .structure = 0xFEDCBA9876543210ull,
      .meshes = {7, 8},
      .instanceBounds = {makeBox({1e6, -2e6, 3.5e5}, {10.0, 4.0, 0.5}), Bounds{}, makeBox({-3, 2, 1}, {0, 0, 0})}};
  return file;
}

// A small file for the exhaustive corruption loops.
SurfelFile smallFile() {
  SurfelFile file;
  file.sceneFingerprint = 42;
  file.arrays.push_back(makeArray(3, makeBox({1, 2, 3}, {1, 1, 1}), 4));
  file.arrays.push_back(makeArray(2, makeBox({0, 0, 0}, {2, 2, 2}), 5));
  file.nodes = {{"/0", 0}, {"/0/1", 1}, {"/1", 0}};
  file.sceneTable = {.structure = 3, .meshes = {5}, .instanceBounds = {Bounds{}, makeBox({1, 2, 3}, {1, 1, 1})}};
  return file;
}

Surfel roundTrip(const Surfel& s, const Bounds& box) { return decodeSurfel(encodeSurfel(s, box), box); }

bool finite(const Surfel& s) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(s.position[i]) || !std::isfinite(s.normal[i])) return false;
  }
  return true;
}

double angleBetween(glm::dvec3 a, glm::dvec3 b) {
  a = glm::normalize(a);
  b = glm::normalize(b);
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

std::string errorOf(const std::filesystem::path& path) {
  try {
    readSurfelFile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void putU32(std::string& bytes, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = char(std::uint8_t(v >> (8 * i)));
}
std::uint64_t u64At(const std::string& bytes, std::size_t at) {
  return surfel_file::readU64(reinterpret_cast<const std::uint8_t*>(bytes.data() + at));
}

void putU64(std::string& bytes, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) bytes[at + i] = char(std::uint8_t(v >> (8 * i)));
}
// Re-seals a table (or the header) whose bytes [from, to) were edited: the checksum follows at `to`.
void reseal(std::string& bytes, std::size_t from, std::size_t to, std::uint64_t seed) {
  putU64(bytes, to, Hash64::of(bytes.data() + from, to - from, seed));
}

// ---- round trips -------------------------------------------------------------------------------

TEST(SurfelFile, RoundTripKeepsEverything) {
  ScratchDir dir;
  const SurfelFile file = sampleFile();
  writeSurfelFile(dir / "a.surfels", file);
  const SurfelFile back = readSurfelFile(dir / "a.surfels");

  EXPECT_EQ(back.sceneFingerprint, file.sceneFingerprint);
  EXPECT_EQ(back.options.threshold, 5000u);
  EXPECT_EQ(back.options.maxSurfels, 4000u);
  EXPECT_EQ(back.options.resolution, 256u);
  EXPECT_EQ(back.options.directions, 6u);
  EXPECT_EQ(back.options.ordering, SurfelOrdering::Dart);
  EXPECT_EQ(back.options.colors, SurfelColors::Pixel);
  EXPECT_EQ(back.options.seed, 77u);
  ASSERT_EQ(back.nodes.size(), file.nodes.size());
  for (std::size_t n = 0; n < file.nodes.size(); ++n) {
    EXPECT_EQ(back.nodes[n].path, file.nodes[n].path);
    EXPECT_EQ(back.nodes[n].array, file.nodes[n].array);
  }
  EXPECT_EQ(back.sceneTable.structure, file.sceneTable.structure);
  EXPECT_EQ(back.sceneTable.meshes, file.sceneTable.meshes);
  ASSERT_EQ(back.sceneTable.instanceBounds.size(), file.sceneTable.instanceBounds.size());
  for (std::size_t n = 0; n < file.sceneTable.instanceBounds.size(); ++n) {
    EXPECT_EQ(back.sceneTable.instanceBounds[n].min, file.sceneTable.instanceBounds[n].min) << n;
    EXPECT_EQ(back.sceneTable.instanceBounds[n].max, file.sceneTable.instanceBounds[n].max) << n;
  }
  ASSERT_EQ(back.arrays.size(), file.arrays.size());
  for (std::size_t a = 0; a < file.arrays.size(); ++a) {
    const SurfelArray& in = file.arrays[a];
    const SurfelArray& out = back.arrays[a];
    EXPECT_EQ(out.box.min, in.box.min);
    EXPECT_EQ(out.box.max, in.box.max);
    EXPECT_EQ(out.coverage, in.coverage);
    EXPECT_EQ(out.packing, in.packing);
    EXPECT_EQ(out.area, in.area);
    EXPECT_EQ(out.twoSidedShare, in.twoSidedShare);
    ASSERT_EQ(out.surfels.size(), in.surfels.size());
    for (std::size_t i = 0; i < in.surfels.size(); ++i) {
      // The file holds exactly what the codec makes of each surfel.
      const Surfel expected = roundTrip(in.surfels[i], in.box);
      EXPECT_EQ(out.surfels[i].position, expected.position);
      EXPECT_EQ(out.surfels[i].normal, expected.normal);
      EXPECT_EQ(out.surfels[i].color, in.surfels[i].color);
      const glm::dvec3 step = in.box.size() / kPositionSteps;
      for (int k = 0; k < 3; ++k) {
        EXPECT_LE(std::abs(double(out.surfels[i].position[k]) - double(in.surfels[i].position[k])),
                  step[k] * 0.5 + 1e-6);
      }
    }
  }
  // Shared arrays are stored once: nodes /0/3 and /1 name the same table entry.
  SurfelFileReader reader(dir / "a.surfels");
  EXPECT_EQ(reader.nodes()[0].array, reader.nodes()[2].array);
  EXPECT_EQ(reader.arrays().size(), 3u);
  EXPECT_EQ(reader.arrays()[1].count, 0u);
  EXPECT_TRUE(reader.readPrefix(1, 100).empty());
}

TEST(SurfelFile, NoArraysNoNodesIsLegal) {
  ScratchDir dir;
  SurfelFile file;
  file.sceneFingerprint = 9;
  writeSurfelFile(dir / "empty.surfels", file);
  // Header, an empty array table, an empty node table and an empty scene table, each with its checksum.
  EXPECT_EQ(std::filesystem::file_size(dir / "empty.surfels"),
            surfel_file::kHeaderBytes + 8u + 8u + surfel_file::sceneTableBytes(0, 0));
  const SurfelFile back = readSurfelFile(dir / "empty.surfels");
  EXPECT_EQ(back.sceneFingerprint, 9u);
  EXPECT_TRUE(back.arrays.empty());
  EXPECT_TRUE(back.nodes.empty());
}

TEST(SurfelFile, SixteenBytesPerSurfel) {
  ScratchDir dir;
  const Bounds box = makeBox({5, 5, 5}, {3, 2, 1});
  SurfelFile large;
  large.arrays.push_back(makeArray(100000, box, 6));
  large.nodes = {{"/0", 0}};
  SurfelFile none = large;
  none.arrays[0].surfels.clear();
  writeSurfelFile(dir / "large.surfels", large);
  writeSurfelFile(dir / "none.surfels", none);
  const double perSurfel =
      double(std::filesystem::file_size(dir / "large.surfels") - std::filesystem::file_size(dir / "none.surfels")) /
      100000.0;
  EXPECT_GE(perSurfel, 16.0);
  EXPECT_LE(perSurfel, 16.01);
}

// Only what varies is stored: one colour for all (12 bytes a surfel, the colour in the array record),
// opaque colours without alpha (15), else RGBA (16); every colour and prefix reads back exactly.
TEST(SurfelFile, OnlyTheColourThatVariesIsStored) {
  ScratchDir dir;
  const Bounds box = makeBox({1, 2, 3}, {2, 2, 2});
  SurfelArray constant = makeArray(10000, box, 1), opaque = makeArray(3000, box, 2),
              translucent = makeArray(3000, box, 3);
  for (Surfel& s : constant.surfels) s.color = glm::u8vec4(120, 121, 122, 255);
  for (Surfel& s : opaque.surfels) s.color.a = 255;
  translucent.surfels[1234].color.a = 254;
  for (Surfel& s : translucent.surfels) s.color.a = s.color.a == 254 ? 254 : 255;
  SurfelFile file;
  file.arrays = {constant, opaque, translucent};
  file.nodes = {{"/0", 0}, {"/1", 1}, {"/2", 2}};
  writeSurfelFile(dir / "c.surfels", file);

  SurfelFileReader reader(dir / "c.surfels");
  ASSERT_EQ(reader.arrays().size(), 3u);
  EXPECT_EQ(reader.arrays()[0].colorEncoding, SurfelColorEncoding::Constant);
  EXPECT_EQ(reader.arrays()[0].constantColor, glm::u8vec4(120, 121, 122, 255));
  EXPECT_EQ(reader.arrays()[1].colorEncoding, SurfelColorEncoding::Rgb);
  EXPECT_EQ(reader.arrays()[2].colorEncoding, SurfelColorEncoding::Rgba);
  const std::uint64_t data = storedSurfelBytes(10000, SurfelColorEncoding::Constant) +
                             storedSurfelBytes(3000, SurfelColorEncoding::Rgb) +
                             storedSurfelBytes(3000, SurfelColorEncoding::Rgba);
  EXPECT_EQ(std::filesystem::file_size(dir / "c.surfels"), reader.tablesBytes() + data);
  EXPECT_LE(double(storedSurfelBytes(10000, SurfelColorEncoding::Constant)) / 10000.0, 12.01)
      << "one colour: 12 bytes a surfel and a checksum a chunk";

  EXPECT_EQ(reader.readPrefix(0, 1).size(), 1u);
  EXPECT_EQ(reader.dataBytesRead(), 1024u * 12u + 8u) << "a constant-colour chunk";
  const SurfelFile back = readSurfelFile(dir / "c.surfels");
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t i = 0; i < file.arrays[a].surfels.size(); ++i) {
      const Surfel expected = roundTrip(file.arrays[a].surfels[i], box);
      ASSERT_EQ(back.arrays[a].surfels[i].color, file.arrays[a].surfels[i].color) << a << " " << i;
      ASSERT_EQ(back.arrays[a].surfels[i].position, expected.position);
      ASSERT_EQ(back.arrays[a].surfels[i].normal, expected.normal);
    }
}

// Node paths in preorder share most of their bytes with the one before: each record keeps the rest.
TEST(SurfelFile, NodePathsAreFrontCoded) {
  ScratchDir dir;
  SurfelFile file;
  file.arrays.push_back(makeArray(10, makeBox({0, 0, 0}, {1, 1, 1}), 4));
  std::uint64_t wholePaths = 0;
  for (int a = 0; a < 10; ++a)
    for (int b = 0; b < 10; ++b)
      for (int c = 0; c < 10; ++c) {
        char path[16];
        std::snprintf(path, sizeof path, "/%d/%d/%d", a, b, c);
        file.nodes.push_back({path, 0});
        wholePaths += 8 + file.nodes.back().path.size();
      }
  writeSurfelFile(dir / "n.surfels", file);
  const SurfelFileReader reader(dir / "n.surfels");
  ASSERT_EQ(reader.nodes().size(), file.nodes.size());
  for (std::size_t n = 0; n < file.nodes.size(); ++n) ASSERT_EQ(reader.nodes()[n].path, file.nodes[n].path);
  const std::uint64_t nodeTable = reader.tablesBytes() - surfel_file::kHeaderBytes -
                                  surfel_file::arrayRecordBytes(kSurfelFileVersion) - 2 * 8 -
                                  surfel_file::sceneTableBytes(0, 0);
  // Suffixes: "/0/0/0" first, then "c" (900 times), "b/0" (90), "a/0/0" (9).
  EXPECT_EQ(nodeTable, 1000u * 12u + 6u + 900u * 1u + 90u * 3u + 9u * 5u);
  EXPECT_LT(nodeTable, wholePaths);
}

// A version 2 file (every surfel RGBA, 96-byte array records, whole paths in the node records) still
// reads: made here from a version 4 file of RGBA arrays by rewriting its tables in version 2's layout
// (and leaving out the scene table).
TEST(SurfelFile, VersionTwoFilesStillRead) {
  using namespace surfel_file;
  ScratchDir dir;
  const SurfelFile file = sampleFile();
  writeSurfelFile(dir / "v4.surfels", file);
  const std::string v4 = readFile(dir / "v4.surfels");
  const std::size_t arrays = file.arrays.size();
  const std::size_t newRecord = arrayRecordBytes(2), oldRecord = arrayRecordBytes(4);
  std::string nodes;
  for (const SurfelNodeRecord& node : file.nodes) {
    nodes += std::string(4, '\0') + node.path + std::string(4, '\0');
    putU32(nodes, nodes.size() - 8 - node.path.size(), std::uint32_t(node.path.size()));
    putU32(nodes, nodes.size() - 4, node.array);
  }
  const std::size_t v4Data = kHeaderBytes + arrays * oldRecord + 8 + u64At(v4, 88) + 8 +
                             sceneTableBytes(file.sceneTable.instanceBounds.size(), file.sceneTable.meshes.size());
  const std::size_t v2Data = kHeaderBytes + arrays * newRecord + 8 + nodes.size() + 8;
  const std::size_t shift = v4Data - v2Data;
  std::string v2 = v4.substr(0, kHeaderBytes);
  putU32(v2, 8, 2);
  putU64(v2, 80, kHeaderBytes + arrays * newRecord + 8);  // node table offset
  putU64(v2, 88, nodes.size());                           // node table bytes
  putU64(v2, 96, u64At(v4, 96) - shift);                  // file size
  reseal(v2, 0, kHeaderChecksumOffset, kHeaderSeed);
  for (std::size_t a = 0; a < arrays; ++a) {
    std::string record = v4.substr(kHeaderBytes + a * oldRecord, newRecord);
    ASSERT_EQ(record.substr(84, 4), std::string(4, '\0')) << "RGBA is encoding 0, version 2's reserved value";
    putU64(record, 88, u64At(record, 88) - shift);  // data offset
    v2 += record;
  }
  v2 += std::string(8, '\0');
  reseal(v2, kHeaderBytes, kHeaderBytes + arrays * newRecord, kArrayTableSeed);
  v2 += nodes + std::string(8, '\0');
  reseal(v2, v2.size() - 8 - nodes.size(), v2.size() - 8, kNodeTableSeed);
  v2 += v4.substr(v4Data);  // the data, unchanged
  writeFile(dir / "v2.surfels", v2);

  const SurfelFile a = readSurfelFile(dir / "v4.surfels"), b = readSurfelFile(dir / "v2.surfels");
  ASSERT_EQ(a.arrays.size(), b.arrays.size());
  for (std::size_t i = 0; i < a.arrays.size(); ++i) {
    ASSERT_EQ(a.arrays[i].surfels.size(), b.arrays[i].surfels.size());
    for (std::size_t k = 0; k < a.arrays[i].surfels.size(); ++k) {
      EXPECT_EQ(a.arrays[i].surfels[k].position, b.arrays[i].surfels[k].position);
      EXPECT_EQ(a.arrays[i].surfels[k].color, b.arrays[i].surfels[k].color);
    }
  }
  ASSERT_EQ(b.nodes.size(), a.nodes.size());
  for (std::size_t n = 0; n < a.nodes.size(); ++n) {
    EXPECT_EQ(b.nodes[n].path, a.nodes[n].path);
    EXPECT_EQ(b.nodes[n].array, a.nodes[n].array);
  }

  // Version 2's reserved field stays reserved: a colour encoding there is refused.
  putU32(v2, kHeaderBytes + 84, 2);
  reseal(v2, kHeaderBytes, kHeaderBytes + arrays * newRecord, kArrayTableSeed);
  writeFile(dir / "v2.surfels", v2);
  EXPECT_NE(errorOf(dir / "v2.surfels").find("reserved field is 2, not 0"), std::string::npos)
      << errorOf(dir / "v2.surfels");
}

// The loose octree a file's arrays were made for is in its header (version 5); a version 4 file, whose
// field was reserved, has none whatever the field holds.
TEST(SurfelFile, OctreeLeafTrianglesRoundTripAndVersionFourHasNone) {
  using namespace surfel_file;
  ScratchDir dir;
  SurfelFile file = sampleFile();
  file.options.octreeLeafTriangles = 5000;
  writeSurfelFile(dir / "v5.surfels", file);
  EXPECT_EQ(SurfelFileReader(dir / "v5.surfels").options().octreeLeafTriangles, 5000u);
  EXPECT_EQ(readSurfelFile(dir / "v5.surfels").options.octreeLeafTriangles, 5000u);

  std::string v4 = readFile(dir / "v5.surfels");
  ASSERT_EQ(u64At(v4, 52) & 0xFFFFFFFFu, 5000u);
  putU32(v4, 8, 4);
  reseal(v4, 0, kHeaderChecksumOffset, kHeaderSeed);
  writeFile(dir / "v4.surfels", v4);
  EXPECT_EQ(SurfelFileReader(dir / "v4.surfels").options().octreeLeafTriangles, 0u);
}

// Each array's two-sided share is in its record (version 6); a version 5 file, whose field was reserved, has
// share 0 for every array whatever the field holds. Shares outside [0, 1] are neither written nor read.
TEST(SurfelFile, TwoSidedShareRoundTripsAndVersionFiveHasNone) {
  using namespace surfel_file;
  ScratchDir dir;
  const SurfelFile file = sampleFile();
  ASSERT_EQ(file.arrays[0].twoSidedShare, 0.25f);
  writeSurfelFile(dir / "v6.surfels", file);
  EXPECT_EQ(SurfelFileReader(dir / "v6.surfels").arrays()[0].twoSidedShare, 0.25f);
  EXPECT_EQ(SurfelFileReader(dir / "v6.surfels").arrays()[2].twoSidedShare, 0.75f);

  const std::string v6 = readFile(dir / "v6.surfels");
  const std::size_t share = kHeaderBytes + 100;  // the first array record's last field
  ASSERT_EQ(v6.substr(share, 4), std::string("\0\0\x80\x3E", 4)) << "0.25 as a little-endian f32";
  std::string v5 = v6;
  putU32(v5, 8, 5);
  reseal(v5, 0, kHeaderChecksumOffset, kHeaderSeed);
  writeFile(dir / "v5.surfels", v5);
  for (const SurfelArray& array : readSurfelFile(dir / "v5.surfels").arrays) EXPECT_EQ(array.twoSidedShare, 0.0f);

  for (const float bad : {-0.5f, 1.5f, std::numeric_limits<float>::quiet_NaN()}) {
    std::string wrong = v6;
    putU32(wrong, share, std::bit_cast<std::uint32_t>(bad));
    reseal(wrong, kHeaderBytes, kHeaderBytes + file.arrays.size() * arrayRecordBytes(6), kArrayTableSeed);
    writeFile(dir / "w.surfels", wrong);
    EXPECT_NE(errorOf(dir / "w.surfels").find("node /0/3: two-sided share is not in [0, 1]"), std::string::npos)
        << errorOf(dir / "w.surfels");
    SurfelFile refused = file;
    refused.arrays[1].twoSidedShare = bad;
    EXPECT_THROW(writeSurfelFile(dir / "r.surfels", refused), std::invalid_argument) << bad;
  }
}

// A version 3 file (no scene table) still reads, with an empty table: made here from a version 4 file by
// leaving the table out. A damaged table is named; a box that is NaN is refused even when resealed.
TEST(SurfelFile, SceneTableIsCheckedAndVersionThreeFilesHaveNone) {
  using namespace surfel_file;
  ScratchDir dir;
  const SurfelFile file = sampleFile();
  writeSurfelFile(dir / "v4.surfels", file);
  const std::string v4 = readFile(dir / "v4.surfels");
  const std::size_t table = u64At(v4, 80) + u64At(v4, 88) + 8;  // after the node table and its checksum
  const std::size_t tableBytes = sceneTableBytes(3, 2);
  ASSERT_EQ(v4.substr(table, 8), std::string("\x03\0\0\0\x02\0\0\0", 8)) << "three boxes, two meshes";

  std::string v3 = v4.substr(0, table) + v4.substr(table + tableBytes);
  putU32(v3, 8, 3);
  putU64(v3, 96, v4.size() - tableBytes);
  reseal(v3, 0, kHeaderChecksumOffset, kHeaderSeed);
  for (std::size_t a = 0; a < file.arrays.size(); ++a) {
    const std::size_t offset = kHeaderBytes + a * arrayRecordBytes(3) + 88;
    putU64(v3, offset, u64At(v3, offset) - tableBytes);
  }
  reseal(v3, kHeaderBytes, kHeaderBytes + file.arrays.size() * arrayRecordBytes(3), kArrayTableSeed);
  writeFile(dir / "v3.surfels", v3);
  const SurfelFile old = readSurfelFile(dir / "v3.surfels");
  EXPECT_TRUE(old.sceneTable.instanceBounds.empty());
  EXPECT_TRUE(old.sceneTable.meshes.empty());
  ASSERT_EQ(old.arrays.size(), file.arrays.size());
  EXPECT_EQ(old.arrays[0].surfels.size(), file.arrays[0].surfels.size());
  EXPECT_EQ(old.arrays[0].surfels.back().position,
            readSurfelFile(dir / "v4.surfels").arrays[0].surfels.back().position);
  SurfelFileReader oldReader(dir / "v3.surfels");
  try {
    oldReader.requireStructure(0);
    ADD_FAILURE() << "a file without a scene table cannot check a scene opened without its meshes";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene table: none in a file of version 3"), std::string::npos) << e.what();
  }

  std::string damaged = v4;
  damaged[table + 20] ^= 0x10;
  writeFile(dir / "d.surfels", damaged);
  EXPECT_NE(errorOf(dir / "d.surfels").find("scene table: checksum mismatch"), std::string::npos)
      << errorOf(dir / "d.surfels");
  std::string nan = v4;
  putU64(nan, table + 16 + 2 * 8 + 48 * 2, 0x7FF8'0000'0000'0000ull);  // the third box's min.x
  reseal(nan, table, table + tableBytes - 8, kSceneTableSeed);
  writeFile(dir / "n.surfels", nan);
  EXPECT_NE(errorOf(dir / "n.surfels").find("scene table: box of node 2 is neither empty nor finite"),
            std::string::npos)
      << errorOf(dir / "n.surfels");

  SurfelFileReader reader(dir / "v4.surfels");
  EXPECT_THROW(reader.requireStructure(0xFEDCBA9876543211ull), InputError);
  EXPECT_FALSE(reader.sceneRequired());
  reader.requireStructure(0xFEDCBA9876543210ull);
  EXPECT_TRUE(reader.sceneRequired());
}

// ---- codec bounds --------------------------------------------------------------------------------

TEST(SurfelCodec, PositionErrorWithinBound) {
  const std::vector<Bounds> boxes = {
      makeBox({0, 0, 0}, {1, 1, 1}),
      makeBox({1e6, -2e6, 3e6}, {1e6, 1e6, 1e6}),
      makeBox({1e6, 1e6, -1e6}, {1e-6, 1e-6, 1e-6}),
      makeBox({-7e7, 3e5, 12.0}, {1e-6, 1e3, 1e6}),
      makeBox({0.5, 0.25, 0.125}, {1e-6, 1e6, 2.0}),
  };
  SeededRandom rng(11);
  for (const Bounds& box : boxes) {
    const glm::dvec3 size = box.size();
    for (int n = 0; n < 20000; ++n) {
      Surfel s;
      s.position = randomInside(rng, box);
      s.normal = {0, 0, 1};
      s.color = {1, 2, 3, 4};
      const Surfel out = roundTrip(s, box);
      for (int k = 0; k < 3; ++k) {
        const double in = s.position[k];
        const double got = out.position[k];
        // Half a step, plus the float rounding of the input (may sit just outside the box) and output.
        const double bound = size[k] / kPositionSteps * 0.5 * (1.0 + 1e-9) +
                             double(std::numeric_limits<float>::epsilon()) * std::max(std::abs(in), std::abs(got));
        ASSERT_LE(std::abs(got - in), bound) << "axis " << k << " extent " << size[k];
      }
    }
  }
}

TEST(SurfelCodec, ZeroExtentAxesDecodeExactlyAndOutsidePointsClamp) {
  const Bounds flat{{-1.0, 2.0, 1e6 + 0.125}, {3.0, 2.0, 1e6 + 0.125}};  // zero thickness in y and z
  SeededRandom rng(12);
  for (int n = 0; n < 1000; ++n) {
    Surfel s{glm::vec3(rng.range(-2, 2), rng.range(-1, 1), rng.range(-1e3, 1e3)), {0, 1, 0}, {}};
    const Surfel out = roundTrip(s, flat);
    EXPECT_EQ(flat.center().y + double(out.position.y), flat.min.y);
    EXPECT_EQ(flat.center().z + double(out.position.z), flat.min.z);
  }
  const Bounds point{{1, 2, 3}, {1, 2, 3}};
  const Surfel out = roundTrip({glm::vec3(5, -5, 1e30f), {1, 0, 0}, {}}, point);
  EXPECT_EQ(out.position, glm::vec3(0.0f));

  const Bounds box = makeBox({0, 0, 0}, {2, 4, 8});
  const Surfel clamped = roundTrip({glm::vec3(100, -100, 4.5f), {0, 0, 1}, {}}, box);
  EXPECT_FLOAT_EQ(clamped.position.x, 1.0f);
  EXPECT_FLOAT_EQ(clamped.position.y, -2.0f);
  EXPECT_FLOAT_EQ(clamped.position.z, 4.0f);
}

TEST(SurfelCodec, NormalErrorWithinBound) {
  std::vector<glm::vec3> normals = {{1, 0, 0},  {-1, 0, 0},   {0, 1, 0},       {0, -1, 0},      {0, 0, 1},
                                    {0, 0, -1}, {1, 1, 0},    {1, -1, 0},      {-1, 1, 0},      {-1, -1, 0},
                                    {1, 0, -1}, {0, 1, -1},   {-1, 0, -1},     {0, -1, -1},     {1, 1, 1},
                                    {1, 1, -1}, {-1, -1, -1}, {1e-30f, 0, -1}, {0, 1e-30f, -1}, {-1e-7f, 1e-7f, -1}};
  SeededRandom rng(13);
  for (int n = 0; n < 200000; ++n) normals.push_back(randomUnit(rng));
  // Seams: the equator (z = 0) and the folds of the lower half (x = 0 or y = 0 with z < 0).
  for (int n = 0; n < 20000; ++n) {
    const double phi = rng.range(0.0, 2.0 * std::numbers::pi);
    const double eps = rng.range(-1e-4, 1e-4);
    normals.emplace_back(glm::dvec3(std::cos(phi), std::sin(phi), eps));
    normals.emplace_back(glm::dvec3(eps, std::cos(phi), -std::abs(std::sin(phi))));
    normals.emplace_back(glm::dvec3(std::cos(phi), eps, -std::abs(std::sin(phi))));
  }
  // Scale does not matter: tiny and huge inputs encode like their unit versions.
  normals.emplace_back(3e-38f, -2e-38f, 1e-38f);
  normals.emplace_back(3e38f, -2e38f, 1e38f);
  normals.emplace_back(1e-45f, 0, 0);

  double worst = 0.0;
  const Bounds box = makeBox({0, 0, 0}, {1, 1, 1});
  for (const glm::vec3& normal : normals) {
    const Surfel out = roundTrip({glm::vec3(0), normal, {}}, box);
    ASSERT_TRUE(finite(out));
    EXPECT_NEAR(glm::length(glm::dvec3(out.normal)), 1.0, 1e-6);
    const double angle = angleBetween(glm::dvec3(normal), glm::dvec3(out.normal));
    worst = std::max(worst, angle);
    ASSERT_LE(angle, kMaxNormalErrorRadians) << normal.x << " " << normal.y << " " << normal.z;
  }
  EXPECT_GT(worst, 0.0);  // a real quantization happened
}

TEST(SurfelCodec, NonFiniteInputsGiveFiniteOutputs) {
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  constexpr float inf = std::numeric_limits<float>::infinity();
  const Bounds box = makeBox({1e6, 0, -3}, {2, 4, 8});
  const glm::dvec3 step = box.size() / kPositionSteps;

  const Surfel centre = roundTrip({glm::vec3(nan, nan, nan), glm::vec3(nan, 0, 1), {}}, box);
  ASSERT_TRUE(finite(centre));
  for (int k = 0; k < 3; ++k) EXPECT_LE(std::abs(double(centre.position[k])), step[k]);
  EXPECT_EQ(centre.normal, glm::vec3(0, 0, 1));

  const Surfel far = roundTrip({glm::vec3(inf, -inf, inf), glm::vec3(inf, 0, 0), {}}, box);
  ASSERT_TRUE(finite(far));
  EXPECT_FLOAT_EQ(far.position.x, 1.0f);
  EXPECT_FLOAT_EQ(far.position.y, -2.0f);
  EXPECT_EQ(far.normal, glm::vec3(0, 0, 1));

  EXPECT_EQ(roundTrip({glm::vec3(0), glm::vec3(0), {}}, box).normal, glm::vec3(0, 0, 1));
  EXPECT_EQ(roundTrip({glm::vec3(0), glm::vec3(-inf, inf, 0), {}}, box).normal, glm::vec3(0, 0, 1));

  // Boxes that pbs never writes (empty, infinite, NaN, huge) and any 16 bytes still decode finitely.
  const double dinf = std::numeric_limits<double>::infinity();
  const double dnan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Bounds> odd = {Bounds{},
                                   Bounds{glm::dvec3(-dinf), glm::dvec3(dinf)},
                                   Bounds{glm::dvec3(dnan), glm::dvec3(dnan)},
                                   Bounds{glm::dvec3(-1e300), glm::dvec3(1e300)},
                                   Bounds{glm::dvec3(-1e307), glm::dvec3(-1e300)},
                                   Bounds{glm::dvec3(1.7e308), glm::dvec3(1.7e308)}};
  SeededRandom rng(14);
  for (const Bounds& b : odd) {
    for (int n = 0; n < 1000; ++n) {
      PackedSurfel packed;
      for (std::uint8_t& byte : packed) byte = std::uint8_t(rng.below(256));
      ASSERT_TRUE(finite(decodeSurfel(packed, b)));
      ASSERT_TRUE(finite(roundTrip({glm::vec3(rng.range(-1e30, 1e30)), randomUnit(rng), {}}, b)));
    }
    ASSERT_TRUE(finite(roundTrip({glm::vec3(nan), glm::vec3(nan), {}}, b)));
  }
}

// ---- prefixes ------------------------------------------------------------------------------------

TEST(SurfelFile, PrefixReadsOnlyItsChunks) {
  ScratchDir dir;
  const SurfelFile file = sampleFile();  // array 0: 2500 surfels = chunks of 1024, 1024, 452
  writeSurfelFile(dir / "p.surfels", file);
  const SurfelFile whole = readSurfelFile(dir / "p.surfels");

  SurfelFileReader reader(dir / "p.surfels");
  EXPECT_EQ(reader.dataBytesRead(), 0u);
  EXPECT_TRUE(reader.readPrefix(0, 0).empty());
  EXPECT_EQ(reader.dataBytesRead(), 0u);

  struct Case {
    std::uint32_t k;
    std::size_t expectCount;
    std::uint64_t expectBytes;
  };
  const Case cases[] = {{1, 1, 1024 * 16 + 8},        {10, 10, 1024 * 16 + 8},       {1024, 1024, 1024 * 16 + 8},
                        {1025, 1025, 2048 * 16 + 16}, {2048, 2048, 2048 * 16 + 16},  {2049, 2049, 2500 * 16 + 24},
                        {2500, 2500, 2500 * 16 + 24}, {100000, 2500, 2500 * 16 + 24}};
  for (const Case& c : cases) {
    const std::uint64_t before = reader.dataBytesRead();
    const std::vector<Surfel> prefix = reader.readPrefix(0, c.k);
    EXPECT_EQ(reader.dataBytesRead() - before, c.expectBytes) << "k = " << c.k;
    ASSERT_EQ(prefix.size(), c.expectCount);
    for (std::size_t i = 0; i < prefix.size(); ++i) {
      ASSERT_EQ(prefix[i].position, whole.arrays[0].surfels[i].position);
      ASSERT_EQ(prefix[i].normal, whole.arrays[0].surfels[i].normal);
      ASSERT_EQ(prefix[i].color, whole.arrays[0].surfels[i].color);
    }
  }
  const std::uint64_t before = reader.dataBytesRead();
  EXPECT_EQ(reader.readPrefix(2, 3).size(), 3u);
  EXPECT_EQ(reader.dataBytesRead() - before, 5 * 16 + 8u);  // the whole (short) chunk and its checksum
  EXPECT_THROW(reader.readPrefix(3, 1), std::out_of_range);
}

TEST(SurfelFile, CorruptLaterChunkNamesTheNodeAndSparesEarlierPrefixes) {
  ScratchDir dir;
  const auto path = dir / "c.surfels";
  writeSurfelFile(path, sampleFile());
  std::uint64_t dataOffset = 0;
  {
    SurfelFileReader reader(path);
    dataOffset = reader.arrays()[0].dataOffset;
  }
  std::string bytes = readFile(path);
  bytes[dataOffset + 2100 * 16 + 5] ^= 0x10;  // a surfel in the third chunk of array 0
  writeFile(path, bytes);

  const std::string message = errorOf(path);
  EXPECT_NE(message.find("node /0/3"), std::string::npos) << message;
  EXPECT_NE(message.find("checksum mismatch"), std::string::npos) << message;
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;

  SurfelFileReader reader(path);
  EXPECT_EQ(reader.readPrefix(0, 100).size(), 100u);
  EXPECT_EQ(reader.readPrefix(0, 2048).size(), 2048u);
  EXPECT_THROW(reader.readPrefix(0, 2049), InputError);
  EXPECT_EQ(reader.readPrefix(2, 5).size(), 5u);
}

TEST(SurfelFile, CorruptUnusedArrayIsNamedByIndex) {
  ScratchDir dir;
  const auto path = dir / "u.surfels";
  SurfelFile file = smallFile();
  file.nodes = {{"/0", 0}};  // array 1 used by no node
  writeSurfelFile(path, file);
  std::uint64_t dataOffset = 0;
  {
    SurfelFileReader reader(path);
    dataOffset = reader.arrays()[1].dataOffset;
  }
  std::string bytes = readFile(path);
  bytes[dataOffset] ^= 1;
  writeFile(path, bytes);
  const std::string message = errorOf(path);
  EXPECT_NE(message.find("array 1"), std::string::npos) << message;
}

// ---- damaged files -------------------------------------------------------------------------------

TEST(SurfelFile, EveryTruncationIsAnInputError) {
  ScratchDir dir;
  const auto good = dir / "good.surfels";
  writeSurfelFile(good, smallFile());
  const std::string bytes = readFile(good);
  ASSERT_NO_THROW(readSurfelFile(good));
  const auto cut = dir / "cut.surfels";
  for (std::size_t size = 0; size < bytes.size(); ++size) {
    writeFile(cut, bytes.substr(0, size));
    EXPECT_THROW(readSurfelFile(cut), InputError) << "cut at " << size;
  }
  // Bytes after the end are as wrong as bytes missing.
  writeFile(cut, bytes + "x");
  EXPECT_THROW(readSurfelFile(cut), InputError);
}

TEST(SurfelFile, EveryFlippedByteIsAnInputError) {
  ScratchDir dir;
  const auto good = dir / "good.surfels";
  writeSurfelFile(good, smallFile());
  const std::string bytes = readFile(good);
  std::uint64_t tablesEnd = 0;
  {
    SurfelFileReader reader(good);
    tablesEnd = reader.arrays()[0].dataOffset;
  }
  const auto bad = dir / "bad.surfels";
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    for (std::uint8_t mask : {std::uint8_t(0x01), std::uint8_t(0x80), std::uint8_t(0xFF)}) {
      std::string flipped = bytes;
      flipped[at] = char(flipped[at] ^ mask);
      writeFile(bad, flipped);
      // Header and tables are checked at open; data when it is read.
      if (at < tablesEnd) {
        EXPECT_THROW(SurfelFileReader{bad}, InputError) << "byte " << at;
      }
      EXPECT_THROW(readSurfelFile(bad), InputError) << "byte " << at;
    }
  }
}

TEST(SurfelFile, BadMagicFutureVersionAndMissingFiles) {
  ScratchDir dir;
  const auto path = dir / "v.surfels";
  writeSurfelFile(path, smallFile());
  const std::string bytes = readFile(path);

  std::string magic = bytes;
  magic[0] = 'X';
  writeFile(path, magic);
  EXPECT_NE(errorOf(path).find("header: bad magic"), std::string::npos) << errorOf(path);

  // Version 1 (before the colour filter joined the header) and a future version are refused by name.
  for (std::uint32_t version : {1u, kSurfelFileVersion + 1}) {
    std::string other = bytes;
    putU32(other, 8, version);
    writeFile(path, other);
    EXPECT_NE(errorOf(path).find("unsupported version " + std::to_string(version) +
                                 " (this build reads versions 2 to " + std::to_string(kSurfelFileVersion) + ")"),
              std::string::npos)
        << errorOf(path);
  }

  writeFile(path, "");
  EXPECT_THROW(readSurfelFile(path), InputError);
  writeFile(path, "PBSURFEL");
  EXPECT_NE(errorOf(path).find("truncated"), std::string::npos) << errorOf(path);
  EXPECT_THROW(readSurfelFile(dir / "missing.surfels"), InputError);
  EXPECT_THROW(readSurfelFile(dir.path()), InputError);
}

// Files whose checksums are right but whose counts or offsets lie: refused at open, before any
// allocation sized by them.
TEST(SurfelFile, AbsurdCountsAndOffsetsAreRefused) {
  using namespace surfel_file;
  ScratchDir dir;
  const auto path = dir / "x.surfels";
  writeSurfelFile(path, smallFile());
  const std::string bytes = readFile(path);
  const std::size_t headerEnd = kHeaderChecksumOffset;

  auto forgedHeader = [&](std::size_t at, std::uint64_t value, bool wide) {
    std::string forged = bytes;
    if (wide)
      putU64(forged, at, value);
    else
      putU32(forged, at, std::uint32_t(value));
    reseal(forged, 0, headerEnd, kHeaderSeed);
    writeFile(path, forged);
    return errorOf(path);
  };
  EXPECT_NE(forgedHeader(64, 0xFFFFFFFFu, false).find("array table: counts absurd"), std::string::npos);
  EXPECT_NE(forgedHeader(68, 0xFFFFFFFFu, false).find("node table: counts absurd"), std::string::npos);
  EXPECT_NE(forgedHeader(88, ~0ull, true).find("node table: counts absurd"), std::string::npos);
  EXPECT_NE(forgedHeader(72, ~0ull - 4, true).find("array table: truncated: offset"), std::string::npos);
  EXPECT_NE(forgedHeader(80, 1ull << 40, true).find("node table: truncated: offset"), std::string::npos);
  EXPECT_NE(forgedHeader(96, 1ull << 40, true).find("truncated"), std::string::npos);
  EXPECT_NE(forgedHeader(44, 7, false).find("unknown ordering 7"), std::string::npos);
  EXPECT_NE(forgedHeader(48, 2, false).find("unknown colour filter 2"), std::string::npos);

  // An array record pointing its data past the end, named by the first node using it.
  const std::size_t arrayTable = kHeaderBytes;
  const std::size_t arrayTableEnd = arrayTable + 2 * arrayRecordBytes(kSurfelFileVersion);
  std::string forged = bytes;
  putU32(forged, arrayTable + 80, 0xFFFFFFFFu);  // surfel count of array 0
  reseal(forged, arrayTable, arrayTableEnd, kArrayTableSeed);
  writeFile(path, forged);
  EXPECT_NE(errorOf(path).find("node /0: truncated: offset"), std::string::npos) << errorOf(path);

  // A node record whose path length runs past its table (a record: bytes shared with the previous
  // path, the suffix's length, the suffix, the array index).
  const std::size_t nodeTable = arrayTableEnd + 8;
  forged = bytes;
  putU32(forged, nodeTable + 4, 0xFFFFFFF0u);
  const std::size_t nodeTableEnd =
      bytes.size() - (3 * 16 + 8) - (2 * 16 + 8) - 8 -
      sceneTableBytes(smallFile().sceneTable.instanceBounds.size(), smallFile().sceneTable.meshes.size());
  reseal(forged, nodeTable, nodeTableEnd, kNodeTableSeed);
  writeFile(path, forged);
  EXPECT_NE(errorOf(path).find("node table"), std::string::npos) << errorOf(path);

  // The first record sharing bytes with a previous path that does not exist.
  forged = bytes;
  putU32(forged, nodeTable, 5);
  reseal(forged, nodeTable, nodeTableEnd, kNodeTableSeed);
  writeFile(path, forged);
  EXPECT_NE(errorOf(path).find("node table: node record 0 shares 5 bytes with a path of 0"), std::string::npos)
      << errorOf(path);

  // A node naming an array that does not exist.
  forged = bytes;
  putU32(forged, nodeTable + 4 + 4 + 2, 9);  // "/0" then its array index
  reseal(forged, nodeTable, nodeTableEnd, kNodeTableSeed);
  writeFile(path, forged);
  EXPECT_NE(errorOf(path).find("node /0: uses array 9"), std::string::npos) << errorOf(path);
}

// ---- writing -------------------------------------------------------------------------------------

TEST(SurfelFile, OverwriteLeavesNoTemporary) {
  ScratchDir dir;
  const auto path = dir / "o.surfels";
  writeSurfelFile(path, sampleFile());
  SurfelFile second = smallFile();
  second.sceneFingerprint = 1234;
  writeSurfelFile(path, second);
  EXPECT_EQ(readSurfelFile(path).sceneFingerprint, 1234u);
  std::size_t entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    ++entries;
    EXPECT_EQ(entry.path().filename(), "o.surfels");
  }
  EXPECT_EQ(entries, 1u);
}

TEST(SurfelFile, FailedWritesLeaveNothing) {
  ScratchDir dir;
  const auto path = dir / "missing-dir" / "f.surfels";
  try {
    writeSurfelFile(path, smallFile());
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "missing-dir"));

  SurfelFile wrong = smallFile();
  wrong.nodes.push_back({"/9", 2});
  EXPECT_THROW(writeSurfelFile(dir / "w.surfels", wrong), std::invalid_argument);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// Arrays handed over out of order wait for the earlier ones, then the file is writeSurfelFile's.
TEST(SurfelFileWriter, ArraysInAnyOrderGiveTheSameBytes) {
  ScratchDir dir;
  const SurfelFile file = sampleFile();
  writeSurfelFile(dir / "whole.surfels", file);
  {
    SurfelFileWriter writer(dir / "streamed.surfels", file.sceneFingerprint, file.options, file.nodes, file.sceneTable,
                            3);
    writer.add(2, file.arrays[2]);
    writer.add(1, file.arrays[1]);
    EXPECT_EQ(writer.bytesWaiting(), (5 + 0) * kSurfelBytes + 8) << "arrays 1 and 2 wait for array 0";
    writer.add(0, file.arrays[0]);
    EXPECT_EQ(writer.bytesWaiting(), 0u);
    EXPECT_FALSE(std::filesystem::exists(dir / "streamed.surfels")) << "nothing under the name before finish";
    writer.finish();
  }
  EXPECT_EQ(test::readFile(dir / "streamed.surfels"), test::readFile(dir / "whole.surfels"));
}

// A shard's part: its shard table read back as written, the arrays it holds read back whole and the others
// empty; what readStored returns, copied with addStored, gives the whole file byte for byte.
TEST(SurfelFileWriter, ShardPartsRoundTripAndStoredArraysCopyExactly) {
  ScratchDir dir;
  const SurfelFile file = sampleFile();
  writeSurfelFile(dir / "whole.surfels", file);
  const SurfelShardTable table{.index = 1, .count = 2, .plan = 0xABCDull, .arrays = {0, 2}};
  {
    SurfelFileWriter part(dir / "part.surfels", file.sceneFingerprint, file.options, file.nodes, file.sceneTable, 3,
                          table);
    SurfelArray empty;
    empty.box = makeBox({0, 0, 0}, {0, 0, 0});
    for (std::uint32_t a : {0u, 1u, 2u}) part.add(a, a == 1 ? empty : file.arrays[a]);
    part.finish();
  }
  SurfelFileReader part(dir / "part.surfels");
  ASSERT_TRUE(part.shard());
  EXPECT_EQ(part.shard()->index, 1u);
  EXPECT_EQ(part.shard()->count, 2u);
  EXPECT_EQ(part.shard()->plan, 0xABCDull);
  EXPECT_EQ(part.shard()->arrays, table.arrays);
  EXPECT_EQ(part.arrays()[1].count, 0u);
  EXPECT_EQ(part.readPrefix(0, 4000).size(), 2500u);
  EXPECT_FALSE(SurfelFileReader(dir / "whole.surfels").shard()) << "a whole file has no shard table";

  SurfelFileReader whole(dir / "whole.surfels");
  {
    SurfelFileWriter copy(dir / "copy.surfels", file.sceneFingerprint, file.options, file.nodes, file.sceneTable, 3);
    for (std::uint32_t a : {2u, 0u, 1u}) copy.addStored(a, whole.arrays()[a], whole.readStored(a));
    EXPECT_THROW(copy.addStored(1, whole.arrays()[1], {1, 2, 3}), std::invalid_argument) << "added twice";
    copy.finish();
  }
  EXPECT_EQ(test::readFile(dir / "copy.surfels"), test::readFile(dir / "whole.surfels"));
  EXPECT_EQ(part.readStored(2), whole.readStored(2)) << "an array's stored bytes do not depend on where it is";

  SurfelFileWriter badSize(dir / "bad.surfels", file.sceneFingerprint, file.options, file.nodes, file.sceneTable, 3);
  EXPECT_THROW(badSize.addStored(0, whole.arrays()[0], {1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(SurfelFileWriter(dir / "bad2.surfels", 1, {}, {}, {}, 3,
                                SurfelShardTable{.index = 2, .count = 2, .plan = 0, .arrays = {}}),
               std::invalid_argument);
  EXPECT_THROW(SurfelFileWriter(dir / "bad3.surfels", 1, {}, {}, {}, 3, SurfelShardTable{.arrays = {2, 1}}),
               std::invalid_argument);
  EXPECT_THROW(SurfelFileWriter(dir / "bad4.surfels", 1, {}, {}, {}, 3,
                                SurfelShardTable{.index = 0, .count = kMaxSurfelShards + 1, .plan = 0, .arrays = {}}),
               std::invalid_argument)
      << "a shard count that would size tables by billions";
}

// A run that stops before finish (an exception, a missing array) leaves neither file nor temporary.
TEST(SurfelFileWriter, UnfinishedWritersLeaveNothing) {
  ScratchDir dir;
  const SurfelFile file = sampleFile();
  {
    SurfelFileWriter writer(dir / "f.surfels", file.sceneFingerprint, file.options, file.nodes, file.sceneTable, 3);
    writer.add(0, file.arrays[0]);
    EXPECT_THROW(writer.add(0, file.arrays[0]), std::invalid_argument) << "each array once";
    EXPECT_THROW(writer.add(3, file.arrays[1]), std::invalid_argument) << "out of range";
    SurfelArray bad = file.arrays[1];
    bad.coverage = std::nan("");
    EXPECT_THROW(writer.add(1, bad), std::invalid_argument);
    EXPECT_THROW(writer.finish(), std::logic_error) << "arrays 1 and 2 are missing";
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  EXPECT_THROW(SurfelFileWriter(dir / "g.surfels", 1, {}, {{"/0", 3}}, {}, 3), std::invalid_argument)
      << "a node naming a missing array";
  Bounds inverted = makeBox({0, 0, 0}, {1, 1, 1});
  std::swap(inverted.min.x, inverted.max.x);
  const SurfelSceneTable badTable{.structure = 0, .meshes = {}, .instanceBounds = {inverted}};
  EXPECT_THROW(SurfelFileWriter(dir / "g.surfels", 1, {}, {}, badTable, 3), std::invalid_argument)
      << "an instance box neither empty nor finite with min <= max";
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// ---- hashing -------------------------------------------------------------------------------------

TEST(Hash64, StreamingMatchesOneShotAndLengthsCount) {
  std::string data;
  for (int i = 0; i < 100; ++i) data.push_back(char(i * 7));
  const std::uint64_t whole = Hash64::of(data.data(), data.size());
  for (std::size_t split = 0; split <= data.size(); ++split) {
    Hash64 h;
    h.bytes(data.data(), split);
    h.bytes(data.data() + split, data.size() - split);
    ASSERT_EQ(h.digest(), whole);
  }
  const char zeros[3] = {};
  EXPECT_NE(Hash64::of(zeros, 1), Hash64::of(zeros, 2));
  EXPECT_NE(Hash64::of(zeros, 0), Hash64::of(zeros, 1));
  EXPECT_NE(Hash64::of(data.data(), 8, 0), Hash64::of(data.data(), 8, 1));
}

Scene fingerprintScene() {
  Scene scene;
  Mesh mesh;
  mesh.name = "tri";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {0, 1, 2};
  mesh.parts = {{.firstIndex = 0, .indexCount = 3, .material = 0}};
  scene.meshes.push_back(mesh);
  scene.materials.push_back({.name = "red", .baseColorFactor = {1, 0, 0, 1}, .baseColorTexture = 0});
  Texture texture;
  texture.name = "checker";
  texture.width = 2;
  texture.height = 1;
  texture.rgba8 = {1, 2, 3, 4, 5, 6, 7, 8};
  scene.textures.push_back(texture);
  Node root;
  root.name = "root";
  root.children = {1};
  Node child;
  child.name = "child";
  child.mesh = 0;
  child.local[3] = glm::dvec4(1e6, 2.0, 3.0, 1.0);
  scene.nodes = {root, child};
  scene.roots = {0};
  return scene;
}

TEST(SceneFingerprint, ChangesWithContentNotNames) {
  const Scene base = fingerprintScene();
  const std::uint64_t fp = sceneFingerprint(base);
  EXPECT_EQ(sceneFingerprint(fingerprintScene()), fp);

  auto differs = [&](auto edit) {
    Scene scene = fingerprintScene();
    edit(scene);
    return sceneFingerprint(scene) != fp;
  };
  EXPECT_TRUE(differs([](Scene& s) { s.meshes[0].positions[1].x = 1.0001f; }));
  EXPECT_TRUE(differs([](Scene& s) { s.meshes[0].normals[0].z = -1.0f; }));
  EXPECT_TRUE(differs([](Scene& s) { s.meshes[0].uvs[2].y = 0.5f; }));
  EXPECT_TRUE(differs([](Scene& s) { s.meshes[0].indices[2] = 0; }));
  EXPECT_TRUE(differs([](Scene& s) { s.meshes[0].parts[0].material = 1; }));
  EXPECT_TRUE(differs([](Scene& s) {
    s.nodes[1].local[3].x = std::nextafter(s.nodes[1].local[3].x, 2e6);  // one ulp of a double
  }));
  EXPECT_TRUE(differs([](Scene& s) { s.nodes[1].mesh = -1; }));
  EXPECT_TRUE(differs([](Scene& s) {
    s.nodes[0].children.clear();
    s.roots.push_back(1);
  }));
  EXPECT_TRUE(differs([](Scene& s) { s.materials[0].baseColorFactor.g = 0.5f; }));
  EXPECT_TRUE(differs([](Scene& s) { s.materials[0].baseColorTexture = -1; }));
  EXPECT_TRUE(differs([](Scene& s) { s.textures[0].rgba8[5] = 9; }));
  EXPECT_TRUE(differs([](Scene& s) { std::swap(s.textures[0].width, s.textures[0].height); }));
  // Moving a value from one list to the next is a change even though the concatenation is the same.
  EXPECT_TRUE(differs([](Scene& s) {
    s.meshes[0].uvs.clear();
    s.meshes[0].indices.insert(s.meshes[0].indices.begin(), 0);
  }));

  EXPECT_FALSE(differs([](Scene& s) {
    s.nodes[0].name = "renamed";
    s.meshes[0].name = "other";
    s.materials[0].name = "blue";
    s.textures[0].name = "t";
  }));
}

}  // namespace
}  // namespace pbs
