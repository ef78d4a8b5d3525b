// `pbs prefixes`: the Figure 2 strip of surfel prefixes, its size, its coverage per panel, determinism, errors.
#include "gltf_test_files.hpp"
#include "test_support.hpp"

#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

namespace pbs::test {
namespace {

struct Picture {
  int width = 0, height = 0, channels = 0;
  std::vector<std::uint8_t> pixels;
};

Picture readPicture(const std::filesystem::path& file) {
  Picture picture;
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) return picture;
  const OIIO::ImageSpec& spec = in->spec();
  picture.width = spec.width;
  picture.height = spec.height;
  picture.channels = spec.nchannels;
  picture.pixels.resize(std::size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, picture.pixels.data())) picture.pixels.clear();
  return picture;
}

// A unit UV sphere (48 × 24 segments, ~2,300 triangles) as a .glb in `folder`: small and quick to load,
// with a surface whose silhouette and shading read in every panel.
std::filesystem::path writeSphereFile(const std::filesystem::path& folder) {
  constexpr int kAround = 48, kRings = 24;
  std::vector<float> positions;
  for (int r = 0; r <= kRings; ++r) {
    const double theta = std::numbers::pi * r / kRings;
    for (int a = 0; a <= kAround; ++a) {
      const double phi = 2.0 * std::numbers::pi * a / kAround;
      positions.push_back(float(std::sin(theta) * std::cos(phi)));
      positions.push_back(float(std::cos(theta)));
      positions.push_back(float(std::sin(theta) * std::sin(phi)));
    }
  }
  std::vector<std::uint16_t> indices;
  for (int r = 0; r < kRings; ++r) {
    for (int a = 0; a < kAround; ++a) {
      const auto v = [](int ring, int around) { return std::uint16_t(ring * (kAround + 1) + around); };
      for (std::uint16_t i : {v(r, a), v(r + 1, a), v(r + 1, a + 1), v(r, a), v(r + 1, a + 1), v(r, a + 1)})
        indices.push_back(i);
    }
  }
  GltfBuilder b;
  const int position = b.addAccessor(positions, kFloat, "VEC3");
  b.json["accessors"][position]["min"] = {-1, -1, -1};
  b.json["accessors"][position]["max"] = {1, 1, 1};
  const int index = b.addAccessor(indices, kUnsignedShort, "SCALAR");
  b.addMaterial({{"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.6, 0.3, 1.0}}}}});
  b.addMesh({{{"attributes", {{"POSITION", position}}}, {"indices", index}, {"material", 0}}});
  b.addNode({{"mesh", 0}, {"name", "ball"}});
  b.setScene({0});
  const auto file = folder / "sphere.glb";
  writeFile(file, b.glb());
  return file;
}

// Covered (opaque) pixels of each square panel, left to right.
std::vector<std::size_t> coveredPerPanel(const Picture& picture, int panelSize) {
  std::vector<std::size_t> covered(std::size_t(picture.width / panelSize), 0);
  for (int y = 0; y < picture.height; ++y) {
    for (int x = 0; x < picture.width; ++x) {
      const std::size_t pixel = std::size_t(y) * picture.width + x;
      if (picture.pixels[pixel * picture.channels + 3] != 0) ++covered[std::size_t(x / panelSize)];
    }
  }
  return covered;
}

TEST(Prefixes, PanelsCoverTheSurfaceAboutEqually) {
  ScratchDir scratch;
  const auto file = scratch / "prefixes.png";
  const CommandResult run = runPbs("prefixes '" + writeSphereFile(scratch.path()).string() +
                                   "' --resolution 128 --panel-size 96 --threads 2 -o '" + file.string() + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  // One line per panel with its count and point size; counts double from 100.
  for (int i = 0; i < 8; ++i) {
    EXPECT_NE(run.out.find("panel " + std::to_string(i) + ": "), std::string::npos) << run.out;
  }
  EXPECT_NE(run.out.find("panel 0: 100 surfels"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("panel 7: 12,800 surfels"), std::string::npos) << run.out;

  const Picture picture = readPicture(file);
  ASSERT_EQ(picture.width, 8 * 96);
  ASSERT_EQ(picture.height, 96);
  ASSERT_EQ(picture.channels, 4);
  ASSERT_FALSE(picture.pixels.empty());
  const std::vector<std::size_t> covered = coveredPerPanel(picture, 96);
  ASSERT_EQ(covered.size(), 8u);
  for (std::size_t panel = 0; panel < covered.size(); ++panel) {
    EXPECT_GT(covered[panel], 0u) << "panel " << panel;
    EXPECT_LT(covered[panel], std::size_t(96 * 96)) << "panel " << panel << " is all surface: the view is too close";
  }
  // Shrinking points keep the covered area roughly constant while the count grows 128-fold.
  EXPECT_GT(double(covered.back()), 0.5 * double(covered.front()));
  EXPECT_LT(double(covered.back()), 2.0 * double(covered.front()));
}

TEST(Prefixes, PanelCountAndOrderingOptions) {
  ScratchDir scratch;
  const std::string sphere = "prefixes '" + writeSphereFile(scratch.path()).string() + "' ";
  for (const char* ordering : {"farthest", "dart", "random"}) {
    const auto file = scratch / (std::string(ordering) + ".png");
    const CommandResult run = runPbs(sphere + "--node ball --resolution 64 --panel-size 40 --panels 3 --ordering " +
                                     std::string(ordering) + " -o '" + file.string() + "'");
    ASSERT_EQ(run.status, 0) << run.err;
    const Picture picture = readPicture(file);
    EXPECT_EQ(picture.width, 3 * 40);
    EXPECT_EQ(picture.height, 40);
    for (std::size_t covered : coveredPerPanel(picture, 40)) EXPECT_GT(covered, 0u) << ordering;
  }
}

TEST(Prefixes, SameBytesForOneAndTwoThreads) {
  ScratchDir scratch;
  const auto one = scratch / "one.png";
  const auto two = scratch / "two.png";
  const std::string common =
      "prefixes '" + writeSphereFile(scratch.path()).string() + "' --resolution 64 --panel-size 48 --panels 5 ";
  ASSERT_EQ(runPbs(common + "--threads 1 -o '" + one.string() + "'").status, 0);
  ASSERT_EQ(runPbs(common + "--threads 2 -o '" + two.string() + "'").status, 0);
  const std::string bytes = readFile(one);
  EXPECT_FALSE(bytes.empty());
  EXPECT_EQ(bytes, readFile(two));
}

TEST(Prefixes, BadInputsGiveOneErrorLine) {
  ScratchDir scratch;
  const auto file = scratch / "never.png";
  const CommandResult missing =
      runPbs("prefixes '" + (scratch / "missing.glb").string() + "' -o '" + file.string() + "'");
  EXPECT_EQ(missing.status, 1);
  EXPECT_EQ(missing.err.rfind("error: ", 0), 0u) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(file));
  const CommandResult node = runPbs("prefixes '" + writeSphereFile(scratch.path()).string() +
                                    "' --node no-such-node -o '" + file.string() + "'");
  EXPECT_EQ(node.status, 1);
  EXPECT_NE(node.err.find("error: "), std::string::npos) << node.err;
  EXPECT_NE(node.err.find("no-such-node"), std::string::npos) << node.err;
  EXPECT_FALSE(std::filesystem::exists(file));
}

}  // namespace
}  // namespace pbs::test
