// A run of triangles of one indexed mesh drawn with one material (a glTF primitive).
#pragma once

#include <cstdint>

namespace pbs {

struct MeshPart {
  std::uint32_t firstIndex = 0;  // a multiple of 3
  std::uint32_t indexCount = 0;  // a multiple of 3
  std::uint32_t material = 0;    // index into the owner's material list
};

}  // namespace pbs
