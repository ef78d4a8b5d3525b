// FootprintProjector: a surfel's disc through the camera's Jacobian at its centre, in double precision.
#include "blend_footprint.hpp"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace pbs::blend {
namespace {

// The pixels whose centre lies in [c − extent, c + extent]: [first, last], unclipped.
struct Span {
  double first, last;
};
PBS_CLONE_INLINE Span pixelSpan(double c, double extent) {
  return {std::ceil(c - extent - 0.5), std::floor(c + extent - 0.5)};
}

// The span clipped to [0, n) as [lo, hi); false if nothing is left.
PBS_CLONE_INLINE bool clip(Span span, int n, std::uint16_t& lo, std::uint16_t& hi) {
  if (!(span.first < n) || !(span.last >= 0.0) || span.first > span.last) return false;
  lo = std::uint16_t(std::max(span.first, 0.0));
  hi = std::uint16_t(std::min(span.last + 1.0, double(n)));
  return true;
}

// The kernel's mass inside the cut-off: 1 − e^(−kCutoff / 2).
const double kKernelMass = 1.0 - std::exp(-double(kCutoff) / 2.0);

// Footprints of at most this many pixels are normalised by their pixels' weights (a 2σ disc of σ ≈ 2 px).
constexpr double kSummedPixels = 81.0;

// The kernel summed over the footprint's pixel centres within its cut-off, whether on screen or not (the
// span is at most kSummedPixels, so its ends are small integers). Every weight is a float in [e^−4, 1]
// (kernelWeight clamps q to kMaxCutoff), so a multiple of 2^−29, and there are at most 81 of them: their sum in
// double is exact in any order, so the sum is the same bits however the loop adds them.
static_assert(kMaxCutoff <= 8.0f && kSummedPixels <= 81.0, "the partial sums of pixelWeightSum must stay exact");
PBS_CLONE_INLINE double pixelWeightSum(const Footprint& f, Span xs, Span ys) {
  double sum = 0.0;
  for (int y = int(ys.first); y <= int(ys.last); ++y)
    for (int x = int(xs.first); x <= int(xs.last); ++x) {
      const float q = f.distance(x, y);
      sum += q <= f.cutoff ? double(f.weight(q)) : 0.0;
    }
  return sum;
}

// Two unit tangents completing the unit normal n to an orthonormal basis, without a branch on its
// direction (Duff et al. 2017).
PBS_CLONE_INLINE void tangents(const glm::dvec3& n, glm::dvec3& t1, glm::dvec3& t2) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  t1 = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  t2 = glm::dvec3(b, sign + n.y * n.y * a, -n.y);
}

}  // namespace

const KernelTable kKernel;

KernelTable::KernelTable() {
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(std::exp(-0.5 * double(i) / kKernelSteps));
}

FootprintProjector::FootprintProjector(const Camera& camera, const SurfelSplatSet& set, std::uint32_t setIndex,
                                       const BlendOptions& options)
    : set_(set),
      setIndex_(setIndex),
      windowFromObject_(windowFromClipMatrix(camera) * camera.clipFromWorld() * set.worldFromObject),
      normalFromObject_(glm::inverseTranspose(glm::dmat3(set.worldFromObject))),
      backFaceCosine_(set.backFaceCosine),
      areaGain_(double(options.coverageGain) * double(set.area) / (double(set.radius) * double(set.radius))),
      width_(int(camera.width)),
      height_(int(camera.height)) {
  const glm::dmat4 objectFromEye = glm::inverse(camera.view * set.worldFromObject);
  // Eye space looks down −Z: the eye is its origin, and +Z points back toward it.
  eyeIsPoint_ = !camera.isOrthographic();
  eye_ = eyeIsPoint_ ? glm::dvec3(objectFromEye * glm::dvec4(0.0, 0.0, 0.0, 1.0))
                     : glm::dvec3(objectFromEye * glm::dvec4(0.0, 0.0, 1.0, 0.0));
}

// Hot: a frame projects every surfel of its prefixes, in two loops per batch (projectEach) so that each loop's
// chain of dependent operations is short and several surfels are in flight at once. Divisions are few (each a
// reciprocal used several times), and the AVX2 clone rounds the spans in one instruction.
PBS_CLONE_INLINE bool FootprintProjector::facing(std::size_t i, FacingSurfel& out) const {
  const glm::dvec3 p(set_.positions[i]);
  const glm::dmat4& m = windowFromObject_;
  const glm::dvec4 h = m * glm::dvec4(p, 1.0);
  if (!(h.w > 0.0)) return false;
  const double invW = 1.0 / h.w;
  const glm::dvec3 c = glm::dvec3(h) * invW;
  if (!(c.z >= 0.0 && c.z <= 1.0) || !std::isfinite(c.x) || !std::isfinite(c.y)) return false;

  glm::dvec3 toEye = eyeIsPoint_ ? eye_ - p : eye_;
  const double eyeDistance = std::sqrt(glm::dot(toEye, toEye));
  if (!(eyeDistance > 0.0)) return false;
  toEye *= 1.0 / eyeDistance;
  glm::dvec3 n(set_.normals[i]);
  const double length = std::sqrt(glm::dot(n, n));
  // A surfel of no normal (a degenerate surface) is drawn facing the eye.
  n = length > 0.0 ? n * (1.0 / length) : toEye;
  const double cosine = glm::dot(n, toEye);
  if (!(cosine >= backFaceCosine_)) return false;
  out = {i, invW, c, toEye, cosine < 0.0 ? -n : n};
  return true;
}

PBS_CLONE_INLINE bool FootprintProjector::footprint(const FacingSurfel& surfel, Footprint& out) const {
  const glm::dmat4& m = windowFromObject_;
  const double invW = surfel.invW;
  const glm::dvec3& c = surfel.window;
  const glm::dvec3& toEye = surfel.toEye;
  const glm::dvec3& n = surfel.normal;
  const std::size_t i = surfel.index;
  // d(window xyz)/d(object coordinate k) at p: the Jacobian that maps the disc.
  glm::dvec3 jacobian[3];
  for (int k = 0; k < 3; ++k) jacobian[k] = (glm::dvec3(m[k]) - c * m[k][3]) * invW;
  const auto map = [&](const glm::dvec3& v) { return jacobian[0] * v.x + jacobian[1] * v.y + jacobian[2] * v.z; };
  glm::dvec3 t1, t2;
  tangents(n, t1, t2);
  const double radius = set_.radius;
  const glm::dvec3 a = map(t1 * radius), b = map(t2 * radius);

  const double sxx = (a.x * a.x + b.x * b.x) / 4.0 + 1.0 / 12.0;
  const double sxy = (a.x * a.y + b.x * b.y) / 4.0;
  const double syy = (a.y * a.y + b.y * b.y) / 4.0 + 1.0 / 12.0;
  const double det = sxx * syy - sxy * sxy;
  if (!(det > 0.0) || !std::isfinite(det)) return false;
  // The cut-off ellipse's half-extents are √(cutoff · Σxx) and √(cutoff · Σyy).
  const double cutoff = std::max(double(kCutoff), kMinReach * kMinReach / std::min(sxx, syy));
  const Span xs = pixelSpan(c.x, std::sqrt(cutoff * sxx)), ys = pixelSpan(c.y, std::sqrt(cutoff * syy));
  if (!clip(xs, width_, out.x0, out.x1) || !clip(ys, height_, out.y0, out.y1)) return false;
  out.cutoff = float(cutoff);

  // The disc's plane: window depth as a function of the pixel offset, (s, t) = M⁻¹ (dx, dy) on the axes.
  const double planeDet = a.x * b.y - b.x * a.y;
  const bool flat = std::abs(planeDet) > 1e-12;
  const double invPlane = 1.0 / planeDet;
  const double invDet = 1.0 / det;
  out.x = float(c.x);
  out.y = float(c.y);
  out.depth = float(c.z);
  out.tolerance = float(std::abs(map(-toEye).z) * radius);
  out.conicA = float(syy * invDet);
  out.conicB = float(-sxy * invDet);
  out.conicC = float(sxx * invDet);
  out.depthDx = flat ? float((a.z * b.y - b.z * a.y) * invPlane) : 0.0f;
  out.depthDy = flat ? float((b.z * a.x - a.z * b.x) * invPlane) : 0.0f;
  out.depthReach = float(std::sqrt(a.z * a.z + b.z * b.z));
  // The disc (area π r²) projects to area π |det M|; the surface it stands for scales the same way. The
  // amplitude makes the coverage summed over the footprint's pixels that area: by the Gaussian's integral
  // for wide footprints, by the sum over its pixel centres for narrow ones, which sample it too coarsely.
  const double pixels = (xs.last - xs.first + 1.0) * (ys.last - ys.first + 1.0);
  const double weights =
      pixels <= kSummedPixels ? pixelWeightSum(out, xs, ys) : 2.0 * std::numbers::pi * std::sqrt(det) * kKernelMass;
  if (!(weights > 0.0)) return false;
  out.amplitude = float(areaGain_ * std::abs(planeDet) / weights);
  const glm::dvec3 normal = normalFromObject_ * n;
  out.normal = glm::vec3(normal * (1.0 / std::sqrt(glm::dot(normal, normal))));
  out.color = set_.colors[i];
  out.set = setIndex_;
  out.index = std::uint32_t(i);
  return true;
}

namespace {

// The loop, compiled for AVX2 beside the baseline. A free function: clang cannot clone a member function
// declared without the attribute.
PBS_AVX2_CLONES std::size_t projectEach(const FootprintProjector& projector, std::size_t first, std::size_t count,
                                        Footprint* out) {
  constexpr std::size_t kBatch = 64;
  FacingSurfel facing[kBatch];
  std::size_t kept = 0;
  for (std::size_t begin = first; begin < first + count; begin += kBatch) {
    const std::size_t end = std::min(first + count, begin + kBatch);
    std::size_t shown = 0;
    for (std::size_t i = begin; i < end; ++i) shown += projector.facing(i, facing[shown]);
    for (std::size_t k = 0; k < shown; ++k) kept += projector.footprint(facing[k], out[kept]);
  }
  return kept;
}

}  // namespace

std::size_t FootprintProjector::projectRange(std::size_t first, std::size_t count, Footprint* out) const {
  // A set of no finite, positive radius has no discs to draw.
  const double radius = set_.radius;
  const bool drawable = radius > 0.0 && std::isfinite(radius) && std::isfinite(areaGain_);
  return drawable ? projectEach(*this, first, count, out) : 0;
}

}  // namespace pbs::blend
