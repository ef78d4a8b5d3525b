// Pictures side by side in one image: the contact sheet of `pbs eval` (exact | surfels | difference
// per row).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace pbs::cli {

// `rows` × `columns` tiles of width×height RGBA8 each, rows top first, every tile composited over
// `background` (RGB8) by its alpha: one RGB8 image of columns·width × rows·height. `tiles` lists the
// tiles row by row; each must hold width·height·4 bytes (else std::invalid_argument).
std::vector<std::uint8_t> contactSheet(std::uint32_t width, std::uint32_t height, std::uint32_t columns,
                                       const std::vector<std::span<const std::uint8_t>>& tiles,
                                       const std::uint8_t (&background)[3]);

}  // namespace pbs::cli
