// Drawing indexed triangle meshes into a Framebuffer with the multithreaded tile rasterizer.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/raster/mesh_part.hpp"
#include "pbs/raster/texture.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>

namespace pbs {

struct SurfaceMaterial {
  glm::vec4 baseColor{1.0f};         // multiplies the texture; RGBA in [0, 1]
  const Texture* texture = nullptr;  // sampled (bilinear, its wrap modes) only when set
};

// A set of a mesh's faces by their side. Front faces turn counter-clockwise in the object frame (a mirroring
// worldFromObject, of negative determinant, is accounted for, so mirrored instances keep their front faces).
enum class FaceSides : std::uint8_t { none = 0, front = 1, back = 2, both = 3 };
inline bool hasSide(FaceSides set, FaceSides side) { return (std::uint8_t(set) & std::uint8_t(side)) != 0; }

// Pixels x0 … x1 × y0 … y1 of the window.
struct PixelRect {
  std::int32_t x0, y0, x1, y1;
};

// One mesh instance: a view on the caller's arrays, nothing is copied.
struct TriangleDraw {
  std::span<const glm::vec3> positions;  // object frame
  std::span<const glm::vec3> normals;    // needed only for the normal channel
  std::span<const glm::vec2> uvs;        // needed only for textured materials
  std::span<const std::uint32_t> indices;
  std::span<const MeshPart> parts;  // cover `indices`; materials index `materials`
  std::span<const SurfaceMaterial> materials;
  glm::dmat4 worldFromObject{1.0};
  std::uint32_t nodeId = 0;      // written to PixelIds::node
  std::uint32_t instanceId = 0;  // written to PixelIds::instance
  // The faces drawn. Front alone leaves the back faces out (as TriangleOptions::cullBackFaces does for every
  // draw): for a closed mesh seen from outside, which hides them behind its front faces; back alone, for a
  // closed mesh wound inside out (MeshFacing::closedInward), whose front faces are the hidden ones.
  FaceSides sides = FaceSides::both;
  // Of the faces `sides` leaves out, those whose pixel box meets one of these are drawn after all: the hidden
  // side of a mesh that is closed but for some holes shows through them (MeshClosure in the scene library).
  // TriangleOptions::cullBackFaces still leaves every back face out.
  std::span<const PixelRect> otherSidesWithin{};
};

struct TriangleOptions {
  // Every draw's back faces left out (FaceSides for which faces are front).
  bool cullBackFaces = false;
};

// Draws in submission order into the channels the framebuffer has (depth test: less). Runs on the
// current TBB arena; the result is bit-identical for any thread count.
//
// The exact pipeline, shared with the reference rasterizer in the tests:
// 1. clip = (projection · view · worldFromObject) · (p, 1), all in double;
// 2. clip against the near (z ≥ −w) and far (z ≤ w) planes in homogeneous space (Sutherland–Hodgman,
//    a new vertex is a + t·(b − a) with t = da / (da − db), d the signed plane distance);
// 3. window coordinates as in camera.hpp, snapped to 1/256 pixel: X = floor(x_w·256 + 0.5);
// 4. coverage of the pixel centres by exact integer edge functions with the top-left fill rule;
//    zero-area triangles cover nothing.
void drawTriangles(Framebuffer& framebuffer, const Camera& camera, std::span<const TriangleDraw> draws,
                   const TriangleOptions& options = {});

}  // namespace pbs
