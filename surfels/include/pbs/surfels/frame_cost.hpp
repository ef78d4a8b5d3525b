// A frame's time predicted from what it draws (FrameCosts), and the fit that makes the prediction for one
// machine from timed frames (`pbs calibrate`): what `--budget-ms` spends.
#pragma once

#include "pbs/raster/bounds.hpp"
#include "pbs/raster/camera.hpp"
#include "pbs/raster/projected_box.hpp"
#include "pbs/surfels/geometry_drawer.hpp"
#include "pbs/surfels/lod_render.hpp"
#include "pbs/surfels/scene_surfels.hpp"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>

namespace pbs {

// What a frame drew, in the units FrameCosts prices.
struct FrameWork {
  double imagePixels = 0.0;
  double triangles = 0.0;          // of the geometry nodes
  double geometryPixels = 0.0;     // Σ of their boxes' clipped pixels (the covered pixels: this, at most the image)
  double geometryRayPixels = 0.0;  // Σ of their boxes' clipped pixels × rayLevels of their meshes
  // Σ of min(triangles, box pixels) over them: at most the triangles that reach a pixel centre, which the
  // rasterizer sets up, bins and resolves in full (a sub-pixel one that reaches none is dropped early).
  double trianglesOnPixels = 0.0;
  double surfels = 0.0;
  double surfelPixels = 0.0;   // Σ of the prefixes' splatPixels
  double nodes = 0.0;          // geometry and surfel nodes drawn
  double geometryNodes = 0.0;  // of which geometry
  double nodesWeighed = 0.0;   // nodes a budget's traversal priced (each box projected, each prefix's splats)

  FrameWork& operator+=(const FrameWork& other);
  FrameWork& operator-=(const FrameWork& other);
};

FrameWork frameWork(const LodStats& stats, std::uint64_t imagePixels);

// The geometry's seconds by one drawer (Raster or Rays; Auto: the cheaper, as drawLodGeometry picks).
double predictGeometryCost(const FrameCosts& costs, const FrameWork& work, GeometryDrawer drawer);
// The rest: image pixels, surfels, nodes.
double predictNonGeometryCost(const FrameCosts& costs, const FrameWork& work);
// Both.
double predictFrameCost(const FrameCosts& costs, const FrameWork& work, GeometryDrawer drawer);
// Bringing a frame drawn at a lower resolution up to its `framePixels` (LodBudget::lowerResolution): every
// pixel of the frame written once more, at FrameCosts::upscalePerPixel.
double predictUpscaleCost(const FrameCosts& costs, double framePixels);

// The pixels the splats of `draw` (a prefix of `splats`, drawn by the node of world transform `world`)
// touch, however many overlap: each a square of its disc's diameter plus a pixel of filter, at most the
// image, and none behind the eye or off screen. The surfels are taken as spread over the node's box, which
// is sampled on a 4 × 4 × 4 lattice: their positions may not be loaded yet when a traversal asks, and a
// prefix whose box reaches the eye is priced for the huge discs near it, not for those at its centre.
double splatPixels(const Camera& camera, const glm::dmat4& world, const SplatArray& splats,
                   const LodDraws::Surfels& draw);

// How deep a ray goes into a mesh of `triangles` once it enters its box: log2(2 + triangles), the levels of
// a binary BVH over them.
double rayLevels(double triangles);

// The work of one geometry node of `triangles` whose box fills `boxPixels` (clipped to the image; 0 where
// pixels are not priced): its triangles, pixels, ray pixels and triangles on pixels, one node.
FrameWork geometryNodeWork(double triangles, double boxPixels);

// The pixels a box fills at most: its projected box, clipped to the image; 0 outside the clip volume.
double clippedBoxPixels(const BoxProjection& boxes, const Bounds& box);

// A timed frame: what it drew, its time, and of that its geometry pass and the drawer that drew it.
struct TimedFrame {
  FrameWork work;
  double seconds = 0.0;
  double geometrySeconds = 0.0;
  GeometryDrawer drawer = GeometryDrawer::Raster;
};

struct FrameCostFit {
  FrameCosts costs;
  std::size_t frames = 0;
  std::size_t rasterFrames = 0;  // frames whose geometry the rasterizer drew: fitted its terms if ≥ 3
  std::size_t rayFrames = 0;     // the same for rays
  double medianError = 0.0;      // |predicted − measured| / measured, each frame with its own drawer: median
  double p90Error = 0.0;         // and 90th percentile
  double quantile = 0.5;         // of the frames, the share predicted to take at least what they took
  double scale = 1.0;            // what the least-squares costs were multiplied by for it
};

// Non-negative least squares on the relative error, in three parts: the geometry pass per drawer (raster:
// triangles, covered and box pixels, nodes; rays: image, covered and box pixels, nodes) over the frames it drew, and
// the rest of each frame (image pixels, surfels, surfel pixels, nodes) over all. A drawer with fewer than 3 frames
// keeps the default terms. Least squares on the relative error predicts low (most frames take longer than
// predicted: 1.16× at the median over `pbs calibrate default`'s 216 frames), and a budget should hold, so the
// fitted terms are then multiplied by one factor, the least for which `quantile` of the frames take no longer
// than predicted (0.5: the median frame as predicted). Throws std::invalid_argument for fewer than 4 frames, a
// time not positive and finite, or a quantile outside (0, 1].
FrameCostFit fitFrameCosts(std::span<const TimedFrame> frames, double quantile = 0.5);

// `--budget-feedback`: a time budget corrected by how far the last frames' measured times were from their
// predicted ones, for machines (or scenes) the costs were not fitted on. The next frame's limit is the
// budget over the median ratio measured / predicted of the last few frames, when that ratio is above 1.
// Frames that ran under their predictions leave the limit at the budget: raised, it spent the margin
// that frames the model prices low need (docs/performance.md, "The feedback lowers the limit only").
// Frames then depend on measured times, so they are not reproducible bit for bit: an option, not the
// default.
class BudgetFeedback {
 public:
  explicit BudgetFeedback(double budgetSeconds) : budget_(budgetSeconds) {}
  double limit() const;  // seconds the cost model may predict for the next frame
  // Ignores a ratio that is not positive and finite (a frame that drew nothing).
  void observe(double predictedSeconds, double measuredSeconds);

 private:
  static constexpr std::size_t kFrames = 5;
  double budget_;
  std::deque<double> ratios_;
};

}  // namespace pbs
