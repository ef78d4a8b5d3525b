// Pictures side by side in one image: the contact sheets of `pbs eval` and `pbs figure views` (exact |
// surfels | difference per row), and the difference picture they show.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pbs {

inline constexpr float kDifferenceGain = 4.0f;

// |a − b| × gain per RGB channel, clamped, alpha 1: what the contact sheet shows of the error. Both
// images must have the same size (else std::invalid_argument).
std::vector<std::uint8_t> differenceRgba8(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b, float gain);

// `rows` × `columns` tiles of width×height RGBA8 each, rows top first, every tile composited over
// `background` (RGB8) by its alpha: one RGB8 image of columns·width × rows·height. `tiles` lists the
// tiles row by row; each must hold width·height·4 bytes (else std::invalid_argument).
std::vector<std::uint8_t> contactSheet(std::uint32_t width, std::uint32_t height, std::uint32_t columns,
                                       const std::vector<std::span<const std::uint8_t>>& tiles,
                                       const std::uint8_t (&background)[3]);

}  // namespace pbs
