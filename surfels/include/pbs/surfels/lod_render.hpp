// Rendering with surfels (paper, Sec. 3): walk the scene graph from the roots; a node small on screen
// that has surfels draws a prefix of them, anything else is descended into and its meshes drawn as
// triangles. In a band around the threshold both are drawn, one growing while the other shrinks, so
// nothing pops.
#pragma once

#include "pbs/raster/camera.hpp"
#include "pbs/raster/framebuffer.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/scene.hpp"
#include "pbs/surfels/geometry_drawer.hpp"
#include "pbs/surfels/scene_surfels.hpp"

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace pbs {

enum class PrefixRule : std::uint32_t {
  // The paper's: projected size² × coverage × overdraw, for points of kReferencePointSize pixels (the
  // authors' default); a point of p pixels covers (p / kReferencePointSize)² as much, so the count is
  // divided by that: larger points, fewer surfels.
  Coverage = 0,
  // The authors' later one: packing / r² with r = point size × (world size of a pixel at the node) / 2,
  // so neighbouring points overlap by half their size.
  Packing = 1,
};

inline constexpr float kReferencePointSize = 2.0f;

// How prefixes are drawn. Nearest: each surfel a square of the point size, the nearest point wins each
// pixel (the paper's GL points). Blend: each surfel a disc in its plane, projected and blended with its
// neighbours on the front surface, sub-pixel ones adding fractional coverage (blended_splats.hpp).
enum class SplatMode : std::uint32_t { Nearest = 0, Blend = 1 };

// "nearest", "blend"; nullopt for any other name.
std::optional<SplatMode> splatModeFromName(std::string_view name);
const char* splatModeName(SplatMode mode);

// Seconds a frame spends per unit of what it draws: what `--budget-ms` spends (LodBudget), and what the
// geometry's drawer is chosen by (lod_geometry.hpp). The geometry terms default to the model fitted for
// that choice (lod_geometry.cpp), the others to `pbs calibrate default` at 1920×1080 on the 2-core machine
// the project is measured on (docs/performance.md, "A frame by budget"); a calibration file replaces all of
// them. A node's projected box, clipped to the image, stands for the pixels it fills.
struct FrameCosts {
  double perImagePixel = 5.9e-9;       // every frame: clear, shading, resolve
  double rasterPerTriangle = 12.1e-9;  // geometry by the rasterizer: each triangle in view
  double rasterPerPixel = 41.6e-9;     // each pixel the geometry covers (its boxes' pixels, at most the image)
  double rasterPerBoxPixel = 0.0;      // each pixel of each geometry box, however many overlap (depth complexity)
  double rasterPerNode = 0.0;          // each geometry node
  // Each triangle that may reach a pixel centre (FrameWork::trianglesOnPixels): its full setup, binning and
  // resolve. `pbs calibrate` fitted 67–234 ns on the 2-core machine (the cities and the default scene, fitted
  // with the other terms). 90 ns is the middle of the values (85–95 ns) that choose the measured-faster drawer
  // on the most of 38 frames timed with each drawer forced; left at 0, the chooser priced near frames of large
  // textured triangles at half what the rasterizer takes and drew them so, slower than rays (docs/evaluation.md,
  // "The rasterizer's price of triangles on pixels").
  double rasterPerTriangleOnPixels = 90e-9;
  double raysPerImagePixel = 2.9e-9;  // geometry by rays: each pixel of the image (a ray)
  double raysPerPixel = 55.2e-9;      // each pixel the geometry covers
  double raysPerBoxPixel = 0.0;       // each pixel of each geometry box, times its mesh's BVH levels
  // Each geometry node (an instance of the frame's top-level BVH): `pbs calibrate default` fitted 9.4 µs (the
  // city 5-10 µs). It is what keeps a subtree of many nodes drawn as surfels where rays could draw it
  // (lod::raysCheaperAbove).
  double raysPerNode = 9.4e-6;
  double perSurfel = 64e-9;        // each surfel drawn
  double perSurfelPixel = 2.0e-9;  // each pixel a splat touches (splatPixels)
  double perNode = 0.0;            // each node drawn, as geometry or as a prefix
  // Each node a budget's traversal prices (FrameWork::nodesWeighed): `pbs calibrate` timed 407 ns on the default
  // scene and 651 ns on the billion-triangle city, on the 2-core machine (docs/performance.md).
  double perNodeWeighed = 0.65e-6;
  // Each pixel of a frame drawn at a lower resolution and brought up to its size (LodBudget::lowerResolution):
  // 3.4–3.9 ms at 1920×1080 from a half, a third or two thirds of it a side on 2 cores (medians of 40, 8-bit
  // output; docs/performance.md). `pbs calibrate` times it.
  double upscalePerPixel = 1.75e-9;

  // Every triangle and surfel 1, the rest free: a budget of primitives (with the rasterizer's terms).
  static FrameCosts primitives() {
    return {.perImagePixel = 0.0,
            .rasterPerTriangle = 1.0,
            .rasterPerPixel = 0.0,
            .rasterPerBoxPixel = 0.0,
            .rasterPerNode = 0.0,
            .rasterPerTriangleOnPixels = 0.0,
            .raysPerImagePixel = 0.0,
            .raysPerPixel = 0.0,
            .raysPerBoxPixel = 0.0,
            .raysPerNode = 0.0,
            .perSurfel = 1.0,
            .perSurfelPixel = 0.0,
            .perNode = 0.0,
            .perNodeWeighed = 0.0,
            .upscalePerPixel = 0.0};
  }
  bool operator==(const FrameCosts&) const = default;
};

enum class BudgetUnit : std::uint32_t { Primitives, Seconds };

// A frame's cost, estimated from what it draws: a greedy refinement spends it (LodOptions::budget).
struct LodBudget {
  double limit = 0.0;  // 0: no budget, the thresholds decide
  BudgetUnit unit = BudgetUnit::Primitives;
  // A budget in seconds: when even the coarsest cut the refinement starts from is predicted over the limit
  // at full resolution (near the eye the cheapest cut is geometry, whose rays or pixels cost what they cost),
  // the frame is drawn at the least of a ladder of lower resolutions at which it fits and upscaled
  // (FrameRenderer; budgetResolution). false: always full resolution, over the limit if need be.
  bool lowerResolution = true;

  // Triangles plus surfels drawn, at most `limit` (`--budget-primitives`): the same cut on every machine.
  static LodBudget primitives(double limit) { return {limit, BudgetUnit::Primitives}; }
  // A frame LodOptions::frameCosts predicts to take at most `seconds` (`--budget-ms`).
  static LodBudget seconds(double seconds) { return {seconds, BudgetUnit::Seconds}; }
  bool operator==(const LodBudget&) const = default;
};

struct LodOptions {
  // Projected size (square root of the box's projected area, pixels) above which a node is descended.
  double threshold = 128.0;
  // Transition band: between threshold and threshold × (1 + band) a node draws its surfels and its
  // children at once. 0 switches abruptly (popping, for comparison).
  double band = 0.5;
  // Surfels per covered pixel of a node's prefix. The paper's 4 was for 2-pixel points; with discs sized
  // from the prefix and arrays descended into when they run out, 16 measured best (docs/evaluation.md:
  // FLIP 0.175 -> 0.126 on the default scene's orbit, 0.138 -> 0.087 on the city's approach, in about
  // one ray per pixel's time).
  double overdraw = 16.0;
  SplatMode splat = SplatMode::Blend;
  // Pixels; 0: from the prefix (the default). A prefix of k surfels closes the node's surface with discs
  // of radius r = √(packing / k) in the node's frame (the authors' later rule), so a prefix cut short by
  // its array draws larger points and a dense one smaller; nearest mode draws squares of side 2r at the
  // node's distance, sub-pixel when below 1, and blend mode discs of radius r.
  // A fixed size (nearest mode only) sizes the prefix by prefixRule instead. Below 1 the points are
  // sub-pixel (PointOptions::subPixel): each covers a pixel only where the pixel's centre falls inside it.
  float pointSize = 0.0f;
  PrefixRule prefixRule = PrefixRule::Coverage;
  // What draws the geometry nodes when renderLod is given a ray caster (lod_geometry.hpp).
  GeometryDrawer geometry = GeometryDrawer::Auto;
  // The frames a mesh BVH built for rays is expected to serve: Auto charges each frame that draws by rays a
  // mesh its caster has not drawn before (EmbreeNodeCaster::drawnBefore) 1/this of the mesh's build. 1 (a single view)
  // charges it whole; a camera path sets its number of frames, since the BVHs are kept. Charged whole, a build the
  // first frame declines is declined by every frame after it, and a path stays with the rasterizer where rays would
  // have repaid the build within a frame or two.
  double bvhBuildFrames = 1.0;
  // A surfel seen at angle θ between its normal and the view direction is drawn max(|cos θ|, this)
  // times the point size, so silhouettes stay sharp (paper, Sec. 3). 1 disables the shrinking.
  float minSizeFactor = 0.25f;
  // Surfels whose normal (facing the capture view that saw them) makes a cosine below this with the
  // direction to the eye are not drawn; slightly negative so that silhouettes stay closed. −1 draws all.
  float backFaceCosine = -0.2f;
  // Blend mode: multiplies each splat's coverage (BlendOptions::coverageGain).
  float coverageGain = 1.0f;
  // A node whose whole array is shorter than the prefix its size asks for at the top of the band is
  // descended into sooner: its threshold drops to the size at which the array just suffices there. An
  // array spread thinner than that blends neighbouring surfaces' colours into each other (red bands on
  // a white tank turn pink) and opens holes. false keeps the one threshold for every node and draws an
  // exhausted array whole with larger points (the paper's cap).
  bool descendExhausted = true;
  // A node whose subtree drawn by rays is predicted (frameCosts) to cost less than its prefix is descended into,
  // below the threshold too: per pixel a prefix of overdraw 16 costs about twenty rays, and only the rays' price
  // per node keeps a subtree of many nodes drawn as surfels (lod::raysCheaperAbove). Exact where that is
  // cheaper; the transition band lies above the lowered threshold as above any. It holds where rays draw the
  // cut's geometry (traverseLodForDrawer, which renderLod and FrameRenderer traverse with), so the commands turn
  // it on (`--rays-cheaper descend`, their default); false here, for a traversal with no ray caster behind it:
  // the threshold alone (the paper's rule).
  bool descendWhereRaysCheaper = false;
  // With descendWhereRaysCheaper: rays are chosen while they are predicted to cost up to this many times the
  // prefix. 2 was measured (docs/evaluation.md, "Rays at up to twice a prefix's price") faster than 1 on six of nine
  // paths of the default scene and two cities and no worse in median FLIP on any: the prefixes it gives up were
  // mostly the slower and the less exact picture.
  double raysPreference = 2.0;
  // With descendWhereRaysCheaper, where rays draw the cut: a frame whose geometry fills more than this share of
  // what its cut draws (nearFrameShare) has every node's descent threshold shrunk, linearly down to 0 at this
  // plus kNearFrameRamp, so that a frame rays draw nearly whole is drawn by them whole. The prefixes left in such a
  // frame save little (its rays are cast over most of the image anyway) and cost accuracy: the default scene's
  // near frames drew 0.2-18 % of their pixels as splats and scored up to 4 % above one ray's FLIP, in about the
  // time of the frame drawn all by rays (docs/evaluation.md, "Near frames drawn by rays whole"). The shares
  // measured lie at 0.15-0.30 on mid and far frames and at 0.5-1 on near ones. 1 turns the rule off.
  double raysNearShare = 0.35;
  // Multiplies every node's descent threshold: set by traverseLodForDrawer from raysNearShare; 1 elsewhere.
  double descentScale = 1.0;
  // With a limit: the cut is chosen by cost instead of by the threshold. From the coarsest cut (every
  // visible node with an array drawn as surfels, the rest descended), the node largest on screen is
  // refined (drawn as its own mesh and its children) while the cost stays within the limit; nodes whose
  // refinement does not fit are passed over for smaller ones. A limit below the coarsest cut's cost draws
  // the coarsest cut. No transition bands. Deterministic.
  LodBudget budget;
  // What a budget in seconds prices a frame's work with (`--calibration`).
  FrameCosts frameCosts;

  // The costs `budget` spends: its unit's.
  FrameCosts budgetCosts() const { return budget.unit == BudgetUnit::Seconds ? frameCosts : FrameCosts::primitives(); }
  bool operator==(const LodOptions&) const = default;
};

// What one traversal decided: geometry to draw and surfel prefixes to draw.
struct LodDraws {
  struct Surfels {
    std::uint32_t node = 0;
    std::uint32_t array = 0;
    std::uint32_t count = 0;  // prefix length, ≤ the array's size
    // Disc radius in the node's frame that closes the surface with the whole prefix the node's size asks
    // for (before a transition thins it): √(packing / k).
    double radius = 0.0;
    double pointSize = 0.0;  // 2 × radius in pixels at the node's centre
    // The prefix the node's size asks for before a transition thins it: above `count` inside a band.
    std::uint32_t full = 0;
  };
  std::vector<std::uint32_t> geometryNodes;  // nodes whose own mesh is drawn as triangles, in traversal order
  std::vector<Surfels> surfels;              // in traversal order
  std::uint64_t triangles = 0;
  std::uint64_t surfelCount = 0;
  std::uint64_t nodesWeighed = 0;  // by a budget's traversal (FrameWork::nodesWeighed); 0 for the threshold's
};

// The traversal alone: frustum culling of node boxes, the threshold and band decisions, prefix sizes.
// `surfels` may have no arrays (then everything visible is geometry). Deterministic.
LodDraws traverseLod(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                     const LodOptions& options);

// The draw traverseLod would make of `node`'s own array at full weight whatever the node's size: the
// prefix its projected size asks for, clamped to the array, with the disc that closes the surface. For
// a caller that must draw surfels where the traversal chose geometry (a stream whose mesh has not
// arrived). nullopt when the node has no array or the prefix is empty.
std::optional<LodDraws::Surfels> wholeArrayDraw(const Scene& scene, const Hierarchy& hierarchy,
                                                const SceneSurfels& surfels, const Camera& camera,
                                                const LodOptions& options, std::uint32_t node);

// The number of surfels a node of projected size `projectedSize` (pixels) whose array is `array` asks
// for, seen at `worldPixel` (world size of one pixel at the node) with node-to-world scale `scale`: by
// options.prefixRule, not clamped to the array. It grows with projectedSize², under either rule.
double prefixDemand(const SplatArray& array, double projectedSize, double worldPixel, double scale,
                    const LodOptions& options);

// prefixDemand clamped to the array and rounded to nearest.
std::uint32_t prefixLength(const SplatArray& array, double projectedSize, double worldPixel, double scale,
                           const LodOptions& options);

struct LodStats {
  double traverseSeconds = 0.0;  // traversal, prefix sizes and per-surfel size factors
  double rasterSeconds = 0.0;    // triangles and points
  std::uint64_t triangles = 0;
  std::uint64_t surfels = 0;
  std::uint64_t nodesGeometry = 0;
  std::uint64_t nodesSurfels = 0;
  // The pixels a frame's cost model reads (FrameCosts): the geometry nodes' projected boxes (each its own
  // mesh's) clipped to the image, summed; the pixels the prefixes' splats touch (splatPixels), summed.
  double geometryPixels = 0.0;
  double geometryRayPixels = 0.0;  // each geometry box's pixels times its mesh's BVH levels (rayLevels)
  double trianglesOnPixels = 0.0;  // Σ min(triangles, box pixels) over the geometry nodes (FrameWork's)
  std::uint64_t nodesWeighed = 0;  // LodDraws'
  double surfelPixels = 0.0;
  // The geometry nodes' pass: its drawer (Raster or Rays), its time (part of rasterSeconds) and, of
  // that, the ray caster's BVH builds of meshes no earlier frame needed.
  GeometryDrawer geometryDrawer = GeometryDrawer::Raster;
  double geometrySeconds = 0.0;
  double bvhBuildSeconds = 0.0;
};
// renderLod's `rays`, kept across frames so that each mesh's BVH is built once, lets options.geometry draw
// the geometry nodes by rays, which overwrite every pixel before the surfels are drawn; without it the
// rasterizer draws them (lod_geometry.hpp).
class EmbreeNodeCaster;

// Traverses and draws into `framebuffer` (its channels decide what is written; it is not cleared). Blend
// mode needs the coverage channel (kChannelCoverage) and writes all of it; into a framebuffer without it,
// prefixes are drawn nearest-wins.
// The image does not depend on the thread count.
LodStats renderLod(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                   Framebuffer& framebuffer, const LodOptions& options, EmbreeNodeCaster* rays = nullptr);

// The traversal renderLod makes: traverseLod, where options.descendWhereRaysCheaper holds only for a cut whose
// geometry rays will draw (options.geometry Rays, or Auto choosing them for that cut, their BVH builds priced as
// drawLodGeometry prices them). Otherwise, and without `rays`, the threshold's cut: a single view whose BVHs
// are yet to build is drawn by the rasterizer, whose price is per triangle.
// Where rays draw the cut and its geometry fills more than options.raysNearShare of it, the cut made again with
// the descent scale nearFrameDescentScale gives.
LodDraws traverseLodForDrawer(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                              const Camera& camera, const LodOptions& options, const EmbreeNodeCaster* rays);

// The width of the share over which LodOptions::raysNearShare shrinks the thresholds to 0.
inline constexpr double kNearFrameRamp = 0.1;

// The share of a cut's pixels its geometry fills: the geometry nodes' projected boxes (each clipped to the image,
// `geometryBoxPixels`) over those plus the prefixes' splat pixels (splatPixels). Both overcount where things
// overlap, so it is an estimate, not the share of pixels the frame's geometry covers (frame_kind.hpp); 0 for an
// empty cut.
double nearFrameShare(const Hierarchy& hierarchy, const SceneSurfels& surfels, const Camera& camera,
                      const LodDraws& draws, double geometryBoxPixels);

// 1 up to raysNearShare (and for NaN), 0 from raysNearShare + kNearFrameRamp, linear between.
double nearFrameDescentScale(double share, double raysNearShare);

// renderLod's drawing half, for `draws` that traverseLod made with the same arguments (a caller that
// loads the drawn prefixes first traverses once). Every drawn prefix must be loaded (std::logic_error).
// The stats' traverseSeconds is 0.
LodStats drawLod(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels, const LodDraws& draws,
                 const Camera& camera, Framebuffer& framebuffer, const LodOptions& options,
                 EmbreeNodeCaster* rays = nullptr);

}  // namespace pbs
