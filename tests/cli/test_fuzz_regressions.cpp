// Replays the fuzzers' inputs through the entry points they drive (fuzz/fuzz_entries.hpp) in every
// build, sanitizers or not: the seed corpora (tests/fuzz/corpus/NAME, valid files that must load) and
// every input a fuzzer once failed on (tests/fuzz/regressions/NAME, which must load or throw
// pbs::InputError, never anything else).
#include "fuzz/fuzz_entries.hpp"
#include "gltf_test_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <exception>
#include <fstream>
#include <functional>
#include <iterator>

namespace {

const std::filesystem::path kFuzzDir = PBS_FUZZ_DIR;

std::vector<std::filesystem::path> filesIn(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  if (!std::filesystem::is_directory(dir)) return files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_regular_file() && !entry.path().filename().string().starts_with(".")) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::uint8_t> bytesOf(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

enum class Expect { Loads, LoadsOrInputError };

// Runs `entry` on the file's bytes; fails the test for any exception but InputError, and for
// InputError too when the file must load.
void replay(const std::filesystem::path& file, const std::function<void(std::span<const std::uint8_t>)>& entry,
            Expect expect) {
  SCOPED_TRACE(file.string());
  const std::vector<std::uint8_t> bytes = bytesOf(file);
  try {
    entry(bytes);
  } catch (const pbs::InputError& e) {
    if (expect == Expect::Loads) ADD_FAILURE() << "a seed must load, but: " << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "escaped an exception other than InputError: " << e.what();
  } catch (...) {
    ADD_FAILURE() << "escaped a non-standard exception";
  }
}

void replayAll(const std::string& name, const std::function<void(std::span<const std::uint8_t>)>& entry) {
  const std::vector<std::filesystem::path> seeds = filesIn(kFuzzDir / "corpus" / name);
  EXPECT_FALSE(seeds.empty()) << "no seeds in " << (kFuzzDir / "corpus" / name).string();
  for (const auto& file : seeds) replay(file, entry, Expect::Loads);
  for (const auto& file : filesIn(kFuzzDir / "regressions" / name)) replay(file, entry, Expect::LoadsOrInputError);
}

TEST(FuzzRegressions, GltfInputsLoadOrThrowInputError) { replayAll("gltf", pbs::fuzz::importGltfBytes); }

TEST(FuzzRegressions, SurfelInputsLoadOrThrowInputError) { replayAll("surfels", pbs::fuzz::readSurfelBytes); }

// The fuzzer's checksum repair repeats the file layout: on files writeSurfelFile wrote it must change
// nothing, else it has drifted from the format and the fuzzer stops getting past the checksums.
TEST(FuzzRegressions, SurfelChecksumRepairMatchesTheWriter) {
  for (const auto& file : filesIn(kFuzzDir / "corpus" / "surfels")) {
    SCOPED_TRACE(file.string());
    const std::vector<std::uint8_t> bytes = bytesOf(file);
    std::vector<std::uint8_t> repaired = bytes;
    pbs::fuzz::repairSurfelChecksums(repaired);
    EXPECT_TRUE(repaired == bytes);
  }
}

// And it does repair: a surfel changed after writing fails its chunk checksum as written, and reads
// once repaired.
TEST(FuzzRegressions, SurfelChecksumRepairFixesAChangedChunk) {
  const std::filesystem::path file = kFuzzDir / "corpus" / "surfels" / "small.surfels";
  std::vector<std::uint8_t> bytes = bytesOf(file);
  ASSERT_GT(bytes.size(), 200u);
  const pbs::SurfelFileReader reader(file);
  ASSERT_GT(reader.arrays().size(), 0u);
  ASSERT_GT(reader.arrays()[0].count, 0u);
  bytes[reader.arrays()[0].dataOffset + 3] ^= 0x5A;

  pbs::fuzz::MemoryFile memory;
  memory.assign(bytes);
  pbs::SurfelFileReader changed(memory.path());
  EXPECT_THROW(changed.readPrefix(0, 1), pbs::InputError);
  pbs::fuzz::repairSurfelChecksums(bytes);
  memory.assign(bytes);
  pbs::SurfelFileReader repaired(memory.path());
  EXPECT_NO_THROW(repaired.readPrefix(0, reader.arrays()[0].count));
}

// Found by probing the importer for the fuzzer's size caps: accessors without a bufferView (zeros) were
// capped at 2^24 elements each, but every use was read anew, so a file of a few hundred bytes could ask
// for gigabytes (8 primitives of 2^24 zero vertices: > 9 GB). Now one budget of 2^20 zero-filled
// elements covers the whole file, every use counted.
pbs::test::GltfBuilder zeroFilledMeshes(int meshes) {
  pbs::test::GltfBuilder b;
  const int zeros = b.append("accessors", {{"componentType", pbs::test::kFloat}, {"count", 600000}, {"type", "VEC3"}});
  std::vector<int> roots;
  for (int m = 0; m < meshes; ++m) {
    b.addMesh({{{"attributes", {{"POSITION", zeros}}}}});
    roots.push_back(b.addNode({{"mesh", m}}));
  }
  b.setScene(roots);
  return b;
}

TEST(FuzzRegressions, ZeroFilledAccessorsShareOneBudgetPerFile) {
  const pbs::ImportResult one = pbs::test::importText(zeroFilledMeshes(1).gltf());
  ASSERT_EQ(one.scene.meshes.size(), 1u);
  EXPECT_EQ(one.scene.meshes[0].positions.size(), 600000u);
  try {
    pbs::test::importText(zeroFilledMeshes(2).gltf());
    ADD_FAILURE() << "two meshes reading 600000 zero vertices each must exceed the budget";
  } catch (const pbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("accessor 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("every use counted"), std::string::npos) << e.what();
  }
}

}  // namespace
