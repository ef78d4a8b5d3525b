// FrameCosts: predicting a frame's time from what it draws, and fitting the prediction to timed frames.
#include "pbs/surfels/frame_cost.hpp"

#include "lod_scale.hpp"
#include "pbs/raster/projected_box.hpp"
#include "pbs/scene/scene_draws.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pbs {
namespace {

// Solves the n × n system a x = b in place by Gaussian elimination with partial pivoting; false when a
// pivot vanishes (the chosen terms are not independent over the frames).
bool solve(std::vector<std::vector<double>>& a, std::vector<double>& b) {
  const std::size_t n = b.size();
  for (std::size_t col = 0; col < n; ++col) {
    std::size_t pivot = col;
    for (std::size_t row = col + 1; row < n; ++row)
      if (std::abs(a[row][col]) > std::abs(a[pivot][col])) pivot = row;
    if (!(std::abs(a[pivot][col]) > 1e-12)) return false;
    std::swap(a[pivot], a[col]);
    std::swap(b[pivot], b[col]);
    for (std::size_t row = col + 1; row < n; ++row) {
      const double f = a[row][col] / a[col][col];
      for (std::size_t k = col; k < n; ++k) a[row][k] -= f * a[col][k];
      b[row] -= f * b[col];
    }
  }
  for (std::size_t col = n; col-- > 0;) {
    for (std::size_t k = col + 1; k < n; ++k) b[col] -= a[col][k] * b[k];
    b[col] /= a[col][col];
  }
  return true;
}

// Non-negative coefficients x minimising Σ_f ((Σ_k x_k terms[f][k] − target[f]) / target[f])². Exact for a
// handful of terms: the optimum is the unconstrained fit on its own support, so it is the best of the
// subsets whose unconstrained fit is non-negative.
std::vector<double> fitNonNegative(const std::vector<std::vector<double>>& terms, const std::vector<double>& target) {
  const std::size_t n = terms.empty() ? 0 : terms[0].size();
  // Each row divided by its target (the residual is then relative), each column scaled to unit size so
  // that pixels (millions) and nodes (hundreds) condition alike.
  std::vector<std::vector<double>> rows(terms.size(), std::vector<double>(n));
  std::vector<double> scale(n, 0.0);
  for (std::size_t f = 0; f < terms.size(); ++f) {
    for (std::size_t k = 0; k < n; ++k) {
      rows[f][k] = terms[f][k] / target[f];
      scale[k] = std::max(scale[k], std::abs(rows[f][k]));
    }
  }
  for (std::vector<double>& row : rows)
    for (std::size_t k = 0; k < n; ++k) row[k] = scale[k] > 0.0 ? row[k] / scale[k] : 0.0;
  std::vector<double> best(n, 0.0);
  double bestResidual = std::numeric_limits<double>::infinity();
  for (unsigned subset = 1; subset < (1u << n); ++subset) {
    std::vector<std::size_t> used;
    bool usable = true;
    for (std::size_t k = 0; k < n; ++k) {
      if (!(subset & (1u << k))) continue;
      usable &= scale[k] > 0.0;
      used.push_back(k);
    }
    if (!usable) continue;
    std::vector<std::vector<double>> normal(used.size(), std::vector<double>(used.size(), 0.0));
    std::vector<double> x(used.size(), 0.0);
    for (const std::vector<double>& row : rows) {
      for (std::size_t i = 0; i < used.size(); ++i) {
        x[i] += row[used[i]];  // the scaled target is 1
        for (std::size_t j = 0; j < used.size(); ++j) normal[i][j] += row[used[i]] * row[used[j]];
      }
    }
    if (!solve(normal, x) || std::any_of(x.begin(), x.end(), [](double v) { return v < 0.0; })) continue;
    double residual = 0.0;
    for (const std::vector<double>& row : rows) {
      double predicted = 0.0;
      for (std::size_t i = 0; i < used.size(); ++i) predicted += row[used[i]] * x[i];
      residual += (predicted - 1.0) * (predicted - 1.0);
    }
    if (residual < bestResidual) {
      bestResidual = residual;
      std::fill(best.begin(), best.end(), 0.0);
      for (std::size_t i = 0; i < used.size(); ++i) best[used[i]] = x[i] / scale[used[i]];
    }
  }
  return best;
}

// One least-squares problem: per frame its terms and seconds, and the costs its solution sets.
struct CostProblem {
  explicit CostProblem(std::vector<double FrameCosts::*> costsSet) : costs(std::move(costsSet)) {}

  std::vector<double FrameCosts::*> costs;
  std::vector<std::vector<double>> terms;
  std::vector<double> seconds;

  void add(std::vector<double> frameTerms, double frameSeconds) {
    terms.push_back(std::move(frameTerms));
    seconds.push_back(frameSeconds);
  }
  // Sets the costs from the fit when there are at least `minimumFrames` frames; returns the frames.
  std::size_t solveInto(FrameCosts& into, std::size_t minimumFrames) const {
    if (terms.size() < minimumFrames) return terms.size();
    const std::vector<double> fitted = fitNonNegative(terms, seconds);
    for (std::size_t k = 0; k < costs.size(); ++k) into.*costs[k] = fitted[k];
    return terms.size();
  }
  void scale(FrameCosts& costsOf, double factor) const {
    for (double FrameCosts::*cost : costs) costsOf.*cost *= factor;
  }
};

// The value below which `quantile` of the values lie (nearest rank).
double quantileOf(std::vector<double> values, double quantile) {
  const auto rank = std::size_t(std::ceil(quantile * double(values.size())));
  const std::size_t index = std::clamp<std::size_t>(rank, 1, values.size()) - 1;
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(index), values.end());
  return values[index];
}

// The frames a drawer must have drawn for its terms to be fitted; with fewer they keep their defaults.
constexpr std::size_t kDrawerFrames = 3;

double coveredPixels(const FrameWork& work) { return std::min(work.geometryPixels, work.imagePixels); }

}  // namespace

FrameWork& FrameWork::operator+=(const FrameWork& other) {
  triangles += other.triangles;
  geometryPixels += other.geometryPixels;
  geometryRayPixels += other.geometryRayPixels;
  trianglesOnPixels += other.trianglesOnPixels;
  surfels += other.surfels;
  surfelPixels += other.surfelPixels;
  nodes += other.nodes;
  geometryNodes += other.geometryNodes;
  nodesWeighed += other.nodesWeighed;
  return *this;
}

FrameWork& FrameWork::operator-=(const FrameWork& other) {
  triangles -= other.triangles;
  geometryPixels -= other.geometryPixels;
  geometryRayPixels -= other.geometryRayPixels;
  trianglesOnPixels -= other.trianglesOnPixels;
  surfels -= other.surfels;
  surfelPixels -= other.surfelPixels;
  nodes -= other.nodes;
  geometryNodes -= other.geometryNodes;
  nodesWeighed -= other.nodesWeighed;
  return *this;
}

FrameWork frameWork(const LodStats& stats, std::uint64_t imagePixels) {
  return {.imagePixels = double(imagePixels),
          .triangles = double(stats.triangles),
          .geometryPixels = stats.geometryPixels,
          .geometryRayPixels = stats.geometryRayPixels,
          .trianglesOnPixels = stats.trianglesOnPixels,
          .surfels = double(stats.surfels),
          .surfelPixels = stats.surfelPixels,
          .nodes = double(stats.nodesGeometry + stats.nodesSurfels),
          .geometryNodes = double(stats.nodesGeometry),
          .nodesWeighed = double(stats.nodesWeighed)};
}

double predictGeometryCost(const FrameCosts& costs, const FrameWork& work, GeometryDrawer drawer) {
  const double covered = coveredPixels(work);
  const double raster = costs.rasterPerTriangle * work.triangles + costs.rasterPerPixel * covered +
                        costs.rasterPerBoxPixel * work.geometryPixels + costs.rasterPerNode * work.geometryNodes +
                        costs.rasterPerTriangleOnPixels * work.trianglesOnPixels;
  // No geometry, no rays: drawLodGeometry's chooser picks the rasterizer for an empty pass.
  const double rays = work.triangles > 0.0
                          ? costs.raysPerImagePixel * work.imagePixels + costs.raysPerPixel * covered +
                                costs.raysPerBoxPixel * work.geometryRayPixels + costs.raysPerNode * work.geometryNodes
                          : 0.0;
  switch (drawer) {
    case GeometryDrawer::Raster: return raster;
    case GeometryDrawer::Rays: return rays;
    case GeometryDrawer::Auto: return std::min(raster, rays);
  }
  return raster;
}

double predictNonGeometryCost(const FrameCosts& costs, const FrameWork& work) {
  return costs.perImagePixel * work.imagePixels + costs.perSurfel * work.surfels +
         costs.perSurfelPixel * work.surfelPixels + costs.perNode * work.nodes +
         costs.perNodeWeighed * work.nodesWeighed;
}

double predictFrameCost(const FrameCosts& costs, const FrameWork& work, GeometryDrawer drawer) {
  return predictNonGeometryCost(costs, work) + predictGeometryCost(costs, work, drawer);
}

double predictUpscaleCost(const FrameCosts& costs, double framePixels) { return costs.upscalePerPixel * framePixels; }

double splatPixels(const Camera& camera, const glm::dmat4& world, const SplatArray& splats,
                   const LodDraws::Surfels& draw) {
  constexpr int kSide = 4;
  if (splats.box.empty()) return 0.0;
  const double imagePixels = double(camera.width) * double(camera.height);
  const glm::dmat4 clipFromObject = camera.clipFromWorld() * world;
  const glm::dvec3 size = splats.box.size();
  const double radius = draw.radius * lod::frameScale(world);
  // Eye-space units per pixel at w = 1 (w is the depth for a perspective camera, 1 for an orthographic one).
  const double pixelsPerUnit = camera.projection[1][1] * camera.height / 2.0;
  // The lattice's points in clip space, stepped from its first by one column of the transform per axis (the
  // map is affine): a budget prices every node it weighs, thousands a frame on a large scene's far views.
  const glm::dvec4 first = clipFromObject * glm::dvec4(splats.box.min + size * (0.5 / kSide), 1.0);
  const glm::dvec4 step[3] = {clipFromObject[0] * (size.x / kSide), clipFromObject[1] * (size.y / kSide),
                              clipFromObject[2] * (size.z / kSide)};
  double sum = 0.0;
  for (int z = 0; z < kSide; ++z) {
    for (int y = 0; y < kSide; ++y) {
      glm::dvec4 clip = first + step[2] * double(z) + step[1] * double(y);
      for (int x = 0; x < kSide; ++x, clip += step[0]) {
        if (!(clip.w > 0.0)) continue;
        const double perW = 1.0 / clip.w;
        const double side = 2.0 * radius * pixelsPerUnit * perW + 1.0;
        // Off screen by more than the splat: culled.
        const double marginX = side / camera.width, marginY = side / camera.height;
        if (std::abs(clip.x * perW) > 1.0 + marginX || std::abs(clip.y * perW) > 1.0 + marginY) continue;
        sum += std::min(side * side, imagePixels);
      }
    }
  }
  return double(draw.count) * sum / double(kSide * kSide * kSide);
}

double rayLevels(double triangles) { return std::log2(2.0 + triangles); }

FrameWork geometryNodeWork(double triangles, double boxPixels) {
  return {.triangles = triangles,
          .geometryPixels = boxPixels,
          .geometryRayPixels = boxPixels * rayLevels(triangles),
          .trianglesOnPixels = std::min(triangles, boxPixels),
          .nodes = 1.0,
          .geometryNodes = 1.0};
}

double clippedBoxPixels(const BoxProjection& boxes, const Bounds& box) {
  if (boxes.outside(box)) return 0.0;
  // A box around or behind the eye projects to +infinity: it fills at most the image.
  return std::min(boxes.pixels(box), double(boxes.camera().width) * double(boxes.camera().height));
}

FrameCostFit fitFrameCosts(std::span<const TimedFrame> frames, double quantile) {
  if (frames.size() < 4)
    throw std::invalid_argument("fitFrameCosts: " + std::to_string(frames.size()) + " frames, at least 4 needed");
  if (!(quantile > 0.0 && quantile <= 1.0))
    throw std::invalid_argument("fitFrameCosts: quantile " + std::to_string(quantile) + " outside (0, 1]");
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const TimedFrame& frame = frames[f];
    if (!(frame.seconds > 0.0) || !std::isfinite(frame.seconds) || !(frame.geometrySeconds >= 0.0) ||
        !(frame.geometrySeconds < frame.seconds))
      throw std::invalid_argument("fitFrameCosts: frame " + std::to_string(f) + " took " +
                                  std::to_string(frame.seconds) + " s, its geometry " +
                                  std::to_string(frame.geometrySeconds) + " s");
  }
  FrameCostFit fit;
  fit.frames = frames.size();
  // Three problems: the rest of each frame over all frames, each drawer's geometry pass over the frames it
  // drew (at least 3, or its terms keep their defaults).
  CostProblem rest(
      {&FrameCosts::perImagePixel, &FrameCosts::perSurfel, &FrameCosts::perSurfelPixel, &FrameCosts::perNode});
  CostProblem raster({&FrameCosts::rasterPerTriangle, &FrameCosts::rasterPerPixel, &FrameCosts::rasterPerBoxPixel,
                      &FrameCosts::rasterPerNode, &FrameCosts::rasterPerTriangleOnPixels});
  CostProblem rays({&FrameCosts::raysPerImagePixel, &FrameCosts::raysPerPixel, &FrameCosts::raysPerBoxPixel,
                    &FrameCosts::raysPerNode});
  for (const TimedFrame& frame : frames) {
    const FrameWork& w = frame.work;
    rest.add({w.imagePixels, w.surfels, w.surfelPixels, w.nodes}, frame.seconds - frame.geometrySeconds);
    // A pass of a few microseconds is timer noise, not geometry.
    if (w.triangles == 0.0 || frame.geometrySeconds < 1e-5) continue;
    if (frame.drawer == GeometryDrawer::Rays)
      rays.add({w.imagePixels, coveredPixels(w), w.geometryRayPixels, w.geometryNodes}, frame.geometrySeconds);
    else
      raster.add({w.triangles, coveredPixels(w), w.geometryPixels, w.geometryNodes, w.trianglesOnPixels},
                 frame.geometrySeconds);
  }
  rest.solveInto(fit.costs, 1);
  fit.rasterFrames = raster.solveInto(fit.costs, kDrawerFrames);
  fit.rayFrames = rays.solveInto(fit.costs, kDrawerFrames);
  std::vector<double> ratios;
  for (const TimedFrame& frame : frames)
    ratios.push_back(frame.seconds / predictFrameCost(fit.costs, frame.work, frame.drawer));
  fit.quantile = quantile;
  fit.scale = quantileOf(std::move(ratios), quantile);
  // A prediction of nothing (no work at all) leaves the costs as fitted.
  if (!(fit.scale > 0.0) || !std::isfinite(fit.scale)) fit.scale = 1.0;
  rest.scale(fit.costs, fit.scale);
  if (fit.rasterFrames >= kDrawerFrames) raster.scale(fit.costs, fit.scale);
  if (fit.rayFrames >= kDrawerFrames) rays.scale(fit.costs, fit.scale);
  std::vector<double> errors;
  for (const TimedFrame& frame : frames)
    errors.push_back(std::abs(predictFrameCost(fit.costs, frame.work, frame.drawer) - frame.seconds) / frame.seconds);
  std::sort(errors.begin(), errors.end());
  fit.medianError = errors[errors.size() / 2];
  fit.p90Error = errors[std::min(errors.size() - 1, errors.size() * 9 / 10)];
  return fit;
}

double BudgetFeedback::limit() const {
  if (ratios_.empty()) return budget_;
  std::vector<double> sorted(ratios_.begin(), ratios_.end());
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  const double median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  return budget_ / std::max(1.0, median);
}

void BudgetFeedback::observe(double predictedSeconds, double measuredSeconds) {
  const double ratio = measuredSeconds / predictedSeconds;
  if (!(ratio > 0.0) || !std::isfinite(ratio)) return;
  ratios_.push_back(ratio);
  if (ratios_.size() > kFrames) ratios_.pop_front();
}

}  // namespace pbs
