// The projected area of a box: the capture coverage's denominator, and the size the LOD renderer
// compares with its threshold (paper, Sec. 2.1 and 3).
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/raster/camera.hpp"

namespace pbs {

// Area in pixels of the convex hull of the box's 8 corners in window space (its silhouette), unclipped:
// parts outside the viewport count. 0 for an empty box. With a perspective camera, +infinity when a
// corner lies on or behind the eye plane (the box surrounds or touches the eye: no finite size). An
// orthographic camera's projection is affine, so its corners are projected as offsets from the box
// centre and boxes far from the origin keep their digits.
double projectedBoxPixels(const Camera& camera, const Bounds& box);

// True when the box lies entirely outside one plane of the camera's clip volume. Conservative: a box that may
// show any pixel is never reported outside; an empty box always is.
bool outsideClipVolume(const Camera& camera, const Bounds& box);

// The two for many boxes seen by one camera (the LOD traversals weigh every visible node of a frame): its
// clip-from-world matrix made once instead of at every box, the same values. It refers to the camera, which
// must outlive it.
class BoxProjection {
 public:
  explicit BoxProjection(const Camera& camera) : camera_(camera), clipFromWorld_(camera.clipFromWorld()) {}
  double pixels(const Bounds& box) const;  // projectedBoxPixels
  bool outside(const Bounds& box) const;   // outsideClipVolume
  const Camera& camera() const { return camera_; }

 private:
  const Camera& camera_;
  glm::dmat4 clipFromWorld_;
};

}  // namespace pbs
