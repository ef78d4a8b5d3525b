// How the plug-in's functions hand a message back through their C interface.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>

namespace pbs::image_io {

// Copies as much of `message` as fits into error[0..errorSize), NUL-terminated.
inline void copyError(const std::string& message, char* error, std::size_t errorSize) {
  if (errorSize == 0) return;
  const std::size_t n = std::min(message.size(), errorSize - 1);
  std::memcpy(error, message.data(), n);
  error[n] = '\0';
}

}  // namespace pbs::image_io
