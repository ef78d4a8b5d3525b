// contactSheet: alpha compositing of RGBA8 tiles into one RGB8 grid; differenceRgba8: what it shows of errors.
#include "pbs/evaluation/contact_sheet.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pbs {

std::vector<std::uint8_t> differenceRgba8(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b,
                                          float gain) {
  if (a.size() != b.size()) throw std::invalid_argument("differenceRgba8: images differ in size");
  std::vector<std::uint8_t> out(a.size() * 4);
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float d = std::clamp(std::abs(a[i][c] - b[i][c]) * gain, 0.0f, 1.0f);
      out[4 * i + std::size_t(c)] = std::uint8_t(std::lround(d * 255.0f));
    }
    out[4 * i + 3] = 255;
  }
  return out;
}

std::vector<std::uint8_t> contactSheet(std::uint32_t width, std::uint32_t height, std::uint32_t columns,
                                       const std::vector<std::span<const std::uint8_t>>& tiles,
                                       const std::uint8_t (&background)[3]) {
  if (columns == 0 || tiles.size() % columns != 0)
    throw std::invalid_argument("contactSheet: the tiles do not fill whole rows");
  const std::size_t tileBytes = std::size_t(width) * height * 4;
  const std::size_t rows = tiles.size() / columns;
  const std::size_t sheetWidth = std::size_t(width) * columns;
  std::vector<std::uint8_t> sheet(sheetWidth * height * rows * 3);
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    if (tiles[t].size() != tileBytes) throw std::invalid_argument("contactSheet: a tile of the wrong size");
    const std::size_t x0 = (t % columns) * width, y0 = (t / columns) * height;
    for (std::size_t y = 0; y < height; ++y) {
      for (std::size_t x = 0; x < width; ++x) {
        const std::uint8_t* in = &tiles[t][(y * width + x) * 4];
        std::uint8_t* out = &sheet[((y0 + y) * sheetWidth + x0 + x) * 3];
        for (int c = 0; c < 3; ++c) out[c] = std::uint8_t((in[c] * in[3] + background[c] * (255 - in[3]) + 127) / 255);
      }
    }
  }
  return sheet;
}

}  // namespace pbs
