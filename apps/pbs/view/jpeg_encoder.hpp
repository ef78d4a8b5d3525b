// JPEG in memory with libjpeg-turbo: the frames `pbs view` sends while the camera moves, about a tenth of
// a PNG's bytes and encoded in a few milliseconds.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace pbs::cli {

// width × height RGB pixels (3 bytes each, rows top first), quality 1–100. Throws std::runtime_error with
// libjpeg's message.
std::vector<std::uint8_t> encodeJpeg(std::span<const std::uint8_t> rgb, std::uint32_t width, std::uint32_t height,
                                     int quality);

}  // namespace pbs::cli
