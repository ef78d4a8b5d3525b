// A surfel: one point sample of a surface with its normal and base colour (paper, Sec. 2).
#pragma once

#include <glm/glm.hpp>

namespace pbs {

struct Surfel {
  glm::vec3 position;  // relative to an origin held beside the array (CaptureResult, SurfelArray), so
                       // far-from-origin nodes keep their digits in single precision
  glm::vec3 normal;    // unit normal of the surface, facing the capture view it was seen from
  glm::u8vec4 color;   // base colour: material factor × texture where the material has one
};

}  // namespace pbs
