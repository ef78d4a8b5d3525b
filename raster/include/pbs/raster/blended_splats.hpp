// Blended surfel splatting: each surfel is a disc in its own plane, projected to an elliptical footprint
// with a smooth kernel (EWA surface splatting, Zwicker et al. 2001), drawn in two passes per pixel as on
// GPUs (Botsch et al. 2005): a visibility pass finds the front surface, an accumulation pass averages every
// splat within a depth tolerance of it. Sub-pixel surfels add the fraction of a pixel they stand for, so a
// distant part covers what its geometry covers, not a whole pixel per point.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"

#include <glm/glm.hpp>

#include <cstdint>
#include <span>

namespace pbs {

struct SurfelSplatSet {
  std::span<const glm::vec3> positions{};  // object frame
  std::span<const glm::vec3> normals{};    // object frame, facing the side the surface was seen from
  std::span<const glm::u8vec4> colors{};
  glm::dmat4 worldFromObject{1.0};
  // Object-frame disc radius: neighbouring discs of the set overlap so that they close the surface.
  float radius = 0.0f;
  // Object-frame surface area each surfel stands for: the set's discs overlap, so this is less than a disc.
  float area = 0.0f;
  // A surfel is not drawn when the cosine between its normal and the direction to the eye is below this:
  // slightly negative, so that surfels at a silhouette (normals bent by curvature between samples) still
  // close it; −1 draws every surfel, facing the eye (an open sheet's, seen from either side).
  float backFaceCosine = -0.2f;
  std::uint32_t nodeId = 0;
  std::uint32_t instanceId = 0;  // PixelIds::primitive is the surfel's index in its set
};

struct BlendOptions {
  // Multiplies each splat's coverage. The kernels of a closed surface sum to 1 on average; ripples of a
  // few per cent between samples would show as speckled holes without a small excess.
  float coverageGain = 1.0f;
};

// Draws the sets over what `framebuffer` holds (geometry drawn before, tested by depth both ways).
//
// Each surfel's footprint is the projection of its disc (through the Jacobian at its centre) convolved
// with a pixel-sized filter: a Gaussian of covariance Σ = (a aᵀ + b bᵀ)/4 + I/12 (a, b the projected disc
// axes), cut off at Mahalanobis distance 2 (or farther, so that it reaches ¾ pixel). At a pixel centre it
// weighs w = exp(−q/2) and covers c = A · w / W, A the projected area the surfel stands for (times the
// gain) and W the sum of w over the footprint's pixels (its integral for footprints wider than 9 × 9
// pixels): summed over pixels, c gives A, so coverage is conserved at any size. Its depth at the pixel
// follows the disc's plane.
//
// Per pixel: the front depth is the least (splat depth + tolerance), the tolerance being one disc radius
// along the view ray; splats up to it form the front layer, the rest in front of the geometry a back
// layer. Each layer's colour and normal are the coverage-weighted means, its alpha S = Σ c raised toward 1
// where S > ½ (closing the ripples of a closed surface; see layerAlpha); front over
// back over geometry gives colour, normal and coverage (kChannelCoverage, required: every pixel of it is
// written, 1 where only geometry is). A splat deeper than the geometry by more than its tolerance is
// hidden; within it (a node fading out over its children's triangles) it is blended over them.
//
// Needs the colour, normal and coverage channels; ids (the nearest contributing surfel's) are written if
// present; the position channel is not supported. Throws std::invalid_argument otherwise, or when a set's
// arrays differ in length. Bit-identical for any thread count: tiles own their pixels and add their splats
// in set order, then index order.
void drawBlendedSplats(Framebuffer& framebuffer, const Camera& camera, std::span<const SurfelSplatSet> sets,
                       const BlendOptions& options = {});

}  // namespace pbs
