// FootprintProjector: a surfel's disc through the camera's Jacobian at its centre, in double precision.
#include "blend_footprint.hpp"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace pbs::blend {
namespace {

// The pixels whose centre lies in [c − extent, c + extent]: [first, last], unclipped.
struct Span {
  double first, last;
};

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

// Hot: a frame projects every surfel of its prefixes. A batch is projected a step at a time, each step a loop
// without branches over the batch's surfels, one array element each (structure of arrays), which the compiler
// turns into vector instructions: every lane performs one surfel's operations in the order written here, IEEE
// rounded and never contracted (simd_clones.hpp), so a footprint's bits depend neither on its batch nor on the
// clone (the file's build options let its square roots and conditional divisions be vector instructions too:
// raster/CMakeLists.txt).
namespace {

constexpr std::size_t kBatch = FootprintProjector::kProjectBatch;
constexpr double kLargest = std::numeric_limits<double>::max();  // |x| ≤ kLargest: x is finite

// Surfels in the depth range facing the eye, in surfel order: the first step's results.
struct FacingLanes {
  std::uint32_t offset[kBatch];  // from the batch's first surfel
  alignas(64) double invW[kBatch];
  alignas(64) double cx[kBatch], cy[kBatch], cz[kBatch];  // the centre in window coordinates
  alignas(64) double ex[kBatch], ey[kBatch], ez[kBatch];  // toward the eye, object frame, unit
  alignas(64) double nx[kBatch], ny[kBatch], nz[kBatch];  // object frame, unit, turned toward the eye
};

// The second step's results: what the footprint's scalar tail (clipping, the pixel sums) needs.
struct FootprintLanes {
  alignas(64) double xFirst[kBatch], xLast[kBatch], yFirst[kBatch], yLast[kBatch];  // Span's, unclipped
  alignas(64) double planeArea[kBatch];  // |det| of the disc's map to the window
  alignas(64) double integral[kBatch];   // the kernel's integral over the footprint
  alignas(64) float cutoff[kBatch], tolerance[kBatch], conicA[kBatch], conicB[kBatch], conicC[kBatch];
  alignas(64) float depthDx[kBatch], depthDy[kBatch], depthReach[kBatch];
  alignas(64) float normalX[kBatch], normalY[kBatch], normalZ[kBatch];
  alignas(64) std::int64_t drawable[kBatch];  // 1 if its covariance is finite and positive definite
};

}  // namespace

PBS_CLONE_INLINE std::size_t FootprintProjector::projectBatch(std::size_t first, std::size_t count,
                                                              Footprint* out) const {
  const glm::dmat4& m = windowFromObject_;
  const glm::vec3* positions = set_.positions.data() + first;
  const glm::vec3* normals = set_.normals.data() + first;

  // Step 1: the centre through the window transform, the unit directions to the eye and of the normal, and
  // which surfels lie in the depth range facing the eye (the rest are left out before the dearer step 2).
  FacingLanes f;
  // The eye's direction first, in a loop of its own: chosen inside the main loop, it would keep that scalar.
  if (eyeIsPoint_)
    for (std::size_t k = 0; k < count; ++k)
      f.ex[k] = eye_.x - positions[k].x, f.ey[k] = eye_.y - positions[k].y, f.ez[k] = eye_.z - positions[k].z;
  else
    for (std::size_t k = 0; k < count; ++k) f.ex[k] = eye_.x, f.ey[k] = eye_.y, f.ez[k] = eye_.z;
  alignas(64) std::int64_t facing[kBatch];
  for (std::size_t k = 0; k < count; ++k) {
    const double px = positions[k].x, py = positions[k].y, pz = positions[k].z;
    // glm's matrix × vector order: (m0 x + m1 y) + (m2 z + m3 · 1).
    const double hx = (m[0][0] * px + m[1][0] * py) + (m[2][0] * pz + m[3][0]);
    const double hy = (m[0][1] * px + m[1][1] * py) + (m[2][1] * pz + m[3][1]);
    const double hz = (m[0][2] * px + m[1][2] * py) + (m[2][2] * pz + m[3][2]);
    const double hw = (m[0][3] * px + m[1][3] * py) + (m[2][3] * pz + m[3][3]);
    const double invW = 1.0 / hw;
    const double cx = hx * invW, cy = hy * invW, cz = hz * invW;
    double ex = f.ex[k], ey = f.ey[k], ez = f.ez[k];
    const double eyeDistance = std::sqrt((ex * ex + ey * ey) + ez * ez);
    const double toUnit = 1.0 / eyeDistance;
    ex *= toUnit, ey *= toUnit, ez *= toUnit;
    double nx = normals[k].x, ny = normals[k].y, nz = normals[k].z;
    const double length = std::sqrt((nx * nx + ny * ny) + nz * nz);
    // A surfel of no normal (a degenerate surface) is drawn facing the eye.
    const bool hasNormal = length > 0.0;
    const double toUnitNormal = 1.0 / length;
    nx = hasNormal ? nx * toUnitNormal : ex;
    ny = hasNormal ? ny * toUnitNormal : ey;
    nz = hasNormal ? nz * toUnitNormal : ez;
    const double cosine = (nx * ex + ny * ey) + nz * ez;
    const bool away = cosine < 0.0;
    // Every test made, and combined without a branch (as integers: a bitwise and of bools is taken for a typo).
    using Lane = std::int64_t;
    facing[k] = Lane(hw > 0.0) & Lane(cz >= 0.0) & Lane(cz <= 1.0) & Lane(std::abs(cx) <= kLargest) &
                Lane(std::abs(cy) <= kLargest) & Lane(eyeDistance > 0.0) & Lane(cosine >= backFaceCosine_);
    f.invW[k] = invW;
    f.cx[k] = cx, f.cy[k] = cy, f.cz[k] = cz;
    f.ex[k] = ex, f.ey[k] = ey, f.ez[k] = ez;
    f.nx[k] = away ? -nx : nx, f.ny[k] = away ? -ny : ny, f.nz[k] = away ? -nz : nz;
  }
  // Those facing the eye to the front, in order (each lane copied to the next free one, which advances only
  // past a surfel kept: no branch).
  std::size_t shown = 0;
  for (std::size_t k = 0; k < count; ++k) {
    f.offset[shown] = std::uint32_t(k);
    f.invW[shown] = f.invW[k];
    f.cx[shown] = f.cx[k], f.cy[shown] = f.cy[k], f.cz[shown] = f.cz[k];
    f.ex[shown] = f.ex[k], f.ey[shown] = f.ey[k], f.ez[shown] = f.ez[k];
    f.nx[shown] = f.nx[k], f.ny[shown] = f.ny[k], f.nz[shown] = f.nz[k];
    shown += std::size_t(facing[k]);
  }

  // Step 2: the disc through the Jacobian at its centre, d(window xyz)/d(object coordinate k), convolved with
  // the pixel filter: the footprint's covariance, extent, depth plane and normal.
  FootprintLanes g;
  const double radius = set_.radius;
  const glm::dmat3& toWorld = normalFromObject_;
  for (std::size_t k = 0; k < shown; ++k) {
    const double invW = f.invW[k];
    const double cx = f.cx[k], cy = f.cy[k], cz = f.cz[k];
    const double nx = f.nx[k], ny = f.ny[k], nz = f.nz[k];
    // Column j of the Jacobian: (m[j].xyz − c · m[j].w) / w.
    double jx[3], jy[3], jz[3];
    for (int j = 0; j < 3; ++j) {
      jx[j] = (m[j][0] - cx * m[j][3]) * invW;
      jy[j] = (m[j][1] - cy * m[j][3]) * invW;
      jz[j] = (m[j][2] - cz * m[j][3]) * invW;
    }
    // Two unit tangents completing n to an orthonormal basis, without a branch on its direction (Duff et al.
    // 2017), scaled by the radius: the disc's axes, then mapped to the window (a, b).
    const double sign = std::copysign(1.0, nz);
    const double inv = -1.0 / (sign + nz);
    const double cross = nx * ny * inv;
    const double t1x = (1.0 + sign * nx * nx * inv) * radius, t1y = (sign * cross) * radius,
                 t1z = (-sign * nx) * radius;
    const double t2x = cross * radius, t2y = (sign + ny * ny * inv) * radius, t2z = (-ny) * radius;
    const double ax = (jx[0] * t1x + jx[1] * t1y) + jx[2] * t1z, bx = (jx[0] * t2x + jx[1] * t2y) + jx[2] * t2z;
    const double ay = (jy[0] * t1x + jy[1] * t1y) + jy[2] * t1z, by = (jy[0] * t2x + jy[1] * t2y) + jy[2] * t2z;
    const double az = (jz[0] * t1x + jz[1] * t1y) + jz[2] * t1z, bz = (jz[0] * t2x + jz[1] * t2y) + jz[2] * t2z;

    const double sxx = (ax * ax + bx * bx) / 4.0 + 1.0 / 12.0;
    const double sxy = (ax * ay + bx * by) / 4.0;
    const double syy = (ay * ay + by * by) / 4.0 + 1.0 / 12.0;
    const double det = sxx * syy - sxy * sxy;
    g.drawable[k] = std::int64_t(det > 0.0) & std::int64_t(det <= kLargest);
    // The cut-off ellipse's half-extents are √(cutoff · Σxx) and √(cutoff · Σyy); std::max and std::min spelt out.
    const double narrowest = syy < sxx ? syy : sxx;
    const double reachCutoff = double(kMinReach * kMinReach) / narrowest;
    const double cutoff = double(kCutoff) < reachCutoff ? reachCutoff : double(kCutoff);
    const double extentX = std::sqrt(cutoff * sxx), extentY = std::sqrt(cutoff * syy);
    // The pixels whose centre lies in [c − extent, c + extent].
    g.xFirst[k] = std::ceil(cx - extentX - 0.5), g.xLast[k] = std::floor(cx + extentX - 0.5);
    g.yFirst[k] = std::ceil(cy - extentY - 0.5), g.yLast[k] = std::floor(cy + extentY - 0.5);
    g.cutoff[k] = float(cutoff);

    // The disc's plane: window depth as a function of the pixel offset, (s, t) = M⁻¹ (dx, dy) on the axes.
    const double planeDet = ax * by - bx * ay;
    const bool flat = std::abs(planeDet) > 1e-12;
    const double invPlane = 1.0 / planeDet;
    const double invDet = 1.0 / det;
    // One disc radius along the view ray, in window depth.
    const double along = (jz[0] * -f.ex[k] + jz[1] * -f.ey[k]) + jz[2] * -f.ez[k];
    g.tolerance[k] = float(std::abs(along) * radius);
    g.conicA[k] = float(syy * invDet);
    g.conicB[k] = float(-sxy * invDet);
    g.conicC[k] = float(sxx * invDet);
    g.depthDx[k] = flat ? float((az * by - bz * ay) * invPlane) : 0.0f;
    g.depthDy[k] = flat ? float((bz * ax - az * bx) * invPlane) : 0.0f;
    g.depthReach[k] = float(std::sqrt(az * az + bz * bz));
    g.planeArea[k] = std::abs(planeDet);
    g.integral[k] = 2.0 * std::numbers::pi * std::sqrt(det) * kKernelMass;
    // glm's matrix × vector order: m0 x + m1 y + m2 z, row by row.
    const double wx = toWorld[0][0] * nx + toWorld[1][0] * ny + toWorld[2][0] * nz;
    const double wy = toWorld[0][1] * nx + toWorld[1][1] * ny + toWorld[2][1] * nz;
    const double wz = toWorld[0][2] * nx + toWorld[1][2] * ny + toWorld[2][2] * nz;
    const double toUnit = 1.0 / std::sqrt((wx * wx + wy * wy) + wz * wz);
    g.normalX[k] = float(wx * toUnit), g.normalY[k] = float(wy * toUnit), g.normalZ[k] = float(wz * toUnit);
  }

  // Step 3, surfel by surfel: clipping to the viewport and the amplitude. The disc (area π r²) projects to area
  // π |det M|; the surface it stands for scales the same way. The amplitude makes the coverage summed over the
  // footprint's pixels that area: by the Gaussian's integral for wide footprints, by the sum over its pixel
  // centres for narrow ones, which sample it too coarsely.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < shown; ++k) {
    if (!g.drawable[k]) continue;
    Footprint& o = out[kept];
    const Span xs{g.xFirst[k], g.xLast[k]}, ys{g.yFirst[k], g.yLast[k]};
    if (!clip(xs, width_, o.x0, o.x1) || !clip(ys, height_, o.y0, o.y1)) continue;
    o.x = float(f.cx[k]);
    o.y = float(f.cy[k]);
    o.depth = float(f.cz[k]);
    o.cutoff = g.cutoff[k];
    o.tolerance = g.tolerance[k];
    o.conicA = g.conicA[k], o.conicB = g.conicB[k], o.conicC = g.conicC[k];
    o.depthDx = g.depthDx[k], o.depthDy = g.depthDy[k], o.depthReach = g.depthReach[k];
    const double pixels = (xs.last - xs.first + 1.0) * (ys.last - ys.first + 1.0);
    const double weights = pixels <= kSummedPixels ? pixelWeightSum(o, xs, ys) : g.integral[k];
    if (!(weights > 0.0)) continue;
    o.amplitude = float(areaGain_ * g.planeArea[k] / weights);
    o.normal = glm::vec3(g.normalX[k], g.normalY[k], g.normalZ[k]);
    const std::size_t index = first + f.offset[k];
    o.color = set_.colors[index];
    o.set = setIndex_;
    o.index = std::uint32_t(index);
    ++kept;
  }
  return kept;
}

namespace {

// The loop, compiled for AVX-512 and AVX2 beside the baseline. A free function: clang cannot clone a member
// function declared without the attribute.
PBS_AVX512_CLONES std::size_t projectEach(const FootprintProjector& projector, std::size_t first, std::size_t count,
                                          Footprint* out) {
  std::size_t kept = 0;
  for (std::size_t begin = first; begin < first + count; begin += kBatch)
    kept += projector.projectBatch(begin, std::min(first + count - begin, kBatch), out + kept);
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
