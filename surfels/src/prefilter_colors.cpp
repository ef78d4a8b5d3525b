// prefilteredColors: each ordered surfel's Gaussian-weighted mean colour over the candidates within its
// insertion distance, found through a dense uniform grid of the candidates and summed in vector lanes.
#include "pbs/surfels/prefilter_colors.hpp"

#include "order_nearest_grid.hpp"

#include "pbs/raster/simd_clones.hpp"
#include "pbs/raster/value_names.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace pbs {
namespace {

constexpr ValueNames<SurfelColors, 2> kColorNames{
    {{{SurfelColors::Pixel, "pixel"}, {SurfelColors::Prefiltered, "prefiltered"}}}};

// The grid holds at most this many cells per candidate (plus a few), so its memory stays a small
// multiple of the candidates' however they are spread; at most kMaxDims cells along an axis; and cell
// numbers fit 32 bits.
constexpr std::uint64_t kCellsPerCandidate = 2;
constexpr std::uint64_t kMinCells = 64;
constexpr std::uint64_t kMaxCells = std::numeric_limits<std::uint32_t>::max() - 1;
constexpr int kMaxDims = 1 << 20;

// Rows are kept or pruned with the search radius widened by this much, so that no candidate whose float
// squared distance passes the test is lost to the rounding of the row bounds.
constexpr double kReachMargin = 1e-4;

// Eight floats, one per lane, in GCC's vector extension (as raster's hot loops): one AVX2 register in
// the AVX2 clone, a pair of SSE registers in the baseline one, and each operation an IEEE
// single-precision one in both. Vectors are passed by reference: by value they would change the
// calling convention between SSE and AVX builds.
constexpr int kLanes = 8;
typedef float FloatLanes __attribute__((vector_size(kLanes * sizeof(float))));
typedef std::int32_t IntLanes __attribute__((vector_size(kLanes * sizeof(std::int32_t))));
constexpr IntLanes kLaneIndex = {0, 1, 2, 3, 4, 5, 6, 7};

// The candidates in grid order, one array per coordinate and colour channel, each followed by kLanes
// zeros: the sums read kLanes entries at a time, also where a range ends sooner.
struct CandidateColumns {
  std::vector<float> x, y, z;
  std::array<std::vector<float>, 4> rgba;

  void resize(std::size_t n) {
    for (std::vector<float>* column : {&x, &y, &z, &rgba[0], &rgba[1], &rgba[2], &rgba[3]}) column->resize(n + kLanes);
  }
};

// The candidates sorted into a dense uniform grid, x fastest, each cell's in candidate order: a run of
// cells along x is one contiguous range of entries, so a query walks rows of cells, not cells.
class CandidateGrid {
 public:
  // `cellTarget`: the cell size wanted (queries then walk about (2 · radius / cellTarget)² rows), made
  // larger where the cell cap needs it.
  // Candidate i at positions[i] with candidates[i]'s colour.
  CandidateGrid(std::span<const glm::vec3> positions, std::span<const Surfel> candidates, double cellTarget);

  const CandidateColumns& columns() const { return columns_; }

  // The number of the cell holding candidate position `p`: x fastest, then y, then z. The same cell as
  // cellAlong's on each axis, but p − lo ≥ 0 inside the candidates' box, so truncation is floor (one
  // instruction, where floor is a call in baseline x86-64) and only the upper clamp is needed.
  std::uint32_t cellOf(const glm::vec3& p) const {
    const glm::dvec3 offset = (glm::dvec3(p) - lo_) * perCell_;
    const auto along = [&](int axis) { return std::min(std::size_t(offset[axis]), std::size_t(dims_[axis] - 1)); };
    return std::uint32_t(along(0) + std::size_t(dims_.x) * (along(1) + std::size_t(dims_.y) * along(2)));
  }

  // Calls visit(begin, end) for ranges of entries holding every candidate within sqrt(radiusSquared)
  // of `query` (and some just outside), in a fixed order: rows by z, then y. +inf gives all entries.
  template <class Visit>
  PBS_CLONE_INLINE void forEachRangeNear(const glm::vec3& query, float radiusSquared, Visit&& visit) const {
    if (!(radiusSquared < std::numeric_limits<float>::infinity())) return visit(0u, cellStart_.back());
    const double reach = std::sqrt(double(radiusSquared)) * (1.0 + kReachMargin);
    const double reachSquared = reach * reach;
    const glm::dvec3 q(query);
    const int z0 = cellAlong(q.z - reach, 2), z1 = cellAlong(q.z + reach, 2);
    const int y0 = cellAlong(q.y - reach, 1), y1 = cellAlong(q.y + reach, 1);
    for (int z = z0; z <= z1; ++z) {
      const double gapZ = gap(q.z, z, 2);
      for (int y = y0; y <= y1; ++y) {
        const double gapY = gap(q.y, y, 1);
        const double rest = reachSquared - gapZ * gapZ - gapY * gapY;
        if (rest < 0.0) continue;
        // The row's cells the ball's cross-section reaches.
        const double half = std::sqrt(rest);
        const std::size_t row = std::size_t(dims_.x) * (std::size_t(y) + std::size_t(dims_.y) * std::size_t(z));
        const std::uint32_t begin = cellStart_[row + std::size_t(cellAlong(q.x - half, 0))];
        const std::uint32_t end = cellStart_[row + std::size_t(cellAlong(q.x + half, 0)) + 1];
        if (begin < end) visit(begin, end);
      }
    }
  }

 private:
  // The cell holding coordinate `v` along `axis`, clamped to the grid (also for ±inf).
  PBS_CLONE_INLINE int cellAlong(double v, int axis) const {
    return int(std::clamp(std::floor((v - lo_[axis]) * perCell_), 0.0, double(dims_[axis] - 1)));
  }
  // How far a coordinate lies outside cell `cell`'s slab along `axis` (0 inside).
  PBS_CLONE_INLINE double gap(double coordinate, int cell, int axis) const {
    const double lo = lo_[axis] + cell * cellSize_;
    return std::max({lo - coordinate, coordinate - (lo + cellSize_), 0.0});
  }

  glm::dvec3 lo_{0.0};
  double cellSize_ = 1.0;
  double perCell_ = 1.0;  // 1 / cellSize_
  glm::ivec3 dims_{1};
  std::vector<std::uint32_t> cellStart_;  // per cell its first entry, and the entry count at the end
  CandidateColumns columns_;
};

CandidateGrid::CandidateGrid(std::span<const glm::vec3> positions, std::span<const Surfel> candidates,
                             double cellTarget) {
  // The box first (its check is the orderings').
  std::vector<std::uint32_t> cells(candidates.size());
  {
    const OrderableBox box = orderableBox(positions, "prefilteredColors");
    lo_ = glm::dvec3(box.lo);
    const glm::dvec3 extent(box.extent);
    const double widest = std::max({extent.x, extent.y, extent.z});
    const std::uint64_t maxCells = std::min(kCellsPerCandidate * candidates.size() + kMinCells, kMaxCells);
    // Relative sizes only, so any scale gives the same grid shape; a zero-width box is one cell.
    cellSize_ = widest > 0.0 ? std::max(std::isfinite(cellTarget) ? cellTarget : widest, widest / (kMaxDims - 1)) : 1.0;
    const auto dimsFor = [&](double size) {
      return glm::min(glm::ivec3(glm::floor(extent / size)) + 1, glm::ivec3(kMaxDims));
    };
    const auto count = [](const glm::ivec3& d) { return std::uint64_t(d.x) * std::uint64_t(d.y) * std::uint64_t(d.z); };
    while (count(dimsFor(cellSize_)) > maxCells) cellSize_ *= 1.25;
    perCell_ = 1.0 / cellSize_;
    dims_ = dimsFor(cellSize_);
    for (std::size_t i = 0; i < positions.size(); ++i) cells[i] = cellOf(positions[i]);
    cellStart_.assign(count(dims_) + 1, 0);
  }

  // Counting sort by cell: counts summed into each cell's end, then candidates placed from the last
  // back, which leaves every cell's start behind and its candidates in index order.
  for (std::uint32_t cell : cells) ++cellStart_[cell];
  for (std::size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
  columns_.resize(candidates.size());
  for (std::size_t i = candidates.size(); i-- > 0;) {
    const std::uint32_t entry = --cellStart_[cells[i]];
    columns_.x[entry] = positions[i].x;
    columns_.y[entry] = positions[i].y;
    columns_.z[entry] = positions[i].z;
    for (int channel = 0; channel < 4; ++channel) columns_.rgba[channel][entry] = candidates[i].color[channel];
  }
}

// exp(−2t) for t in [0, 1], within 4e-6 relative: 1 + t·q(t), q the degree-6 Chebyshev interpolant of
// (exp(−2t) − 1) / t, so that t = 0 (d = +inf or a coincident candidate) weighs exactly 1. Evaluated
// in Estrin's scheme, whose short chains of dependent operations suit the vector units better than
// Horner's. Unlike std::exp it runs in vector lanes, and its fixed sequence of float operations gives
// the same bits on every CPU. Lanes outside [0, 1] give values that are not used.
PBS_CLONE_INLINE void gaussianWeight(const FloatLanes& t, FloatLanes& weight) {
  const FloatLanes t2 = t * t;
  const FloatLanes t4 = t2 * t2;
  const FloatLanes q01 = t * 1.999964f + -1.99999964f;
  const FloatLanes q23 = t * 0.663083732f + -1.3327508f;
  const FloatLanes q456 = t2 * -0.0109097455f + (t * 0.0719207004f + -0.255973339f);
  const FloatLanes q = (t2 * q23 + q01) + t4 * q456;
  weight = t * q + 1.0f;
}

PBS_CLONE_INLINE void load(const float* p, FloatLanes& lanes) { std::memcpy(&lanes, p, sizeof lanes); }

// A surfel's sums: float partial sums in vector lanes, added into double every kFlushBlocks blocks of
// kLanes entries so that a neighbourhood of any size keeps double precision. Which entry goes to which
// lane depends only on the ranges visited, so the bits do too.
class NeighbourhoodSums {
 public:
  NeighbourhoodSums(const glm::vec3& query, float radiusSquared)
      : query_(query),
        radiusSquared_(radiusSquared),
        perRadiusSquared_(radiusSquared >= std::numeric_limits<float>::min() ? 1.0f / radiusSquared : 0.0f) {}

  // Adds the candidates of entries [begin, end) that lie within the radius.
  PBS_CLONE_INLINE void add(const CandidateColumns& c, std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t e = begin; e < end; e += kLanes) addBlock(c, e, int(std::min<std::uint32_t>(kLanes, end - e)));
  }

  PBS_CLONE_INLINE glm::u8vec4 roundedMean() {
    flush();
    const glm::dvec4 mean = glm::clamp(glm::floor(color_ / weight_ + 0.5), 0.0, 255.0);
    return glm::u8vec4(mean);
  }

 private:
  static constexpr int kFlushBlocks = 32;

  // Entries [e, e + count), count ≤ kLanes (the lanes after them read the next entries or the
  // columns' padding, and count nothing).
  PBS_CLONE_INLINE void addBlock(const CandidateColumns& c, std::uint32_t e, int count) {
    FloatLanes x, y, z;
    load(&c.x[e], x);
    load(&c.y[e], y);
    load(&c.z[e], z);
    const FloatLanes dx = x - query_.x, dy = y - query_.y, dz = z - query_.z;
    const FloatLanes r2 = dx * dx + dy * dy + dz * dz;
    // σ = d / 2: exp(−r² / (2σ²)) = exp(−2 r² / d²), with t = r² / d² ≤ 1 (rounding can pass 1 by a
    // hair) where r ≤ d. For d = +inf, for d = 0 (where only r = 0 passes) and for d² below float's
    // normal range (spreads the orderings treat as coincident), t = 0: the weight is 1.
    FloatLanes t = r2 * perRadiusSquared_;
    t = t < 1.0f ? t : 1.0f;
    FloatLanes g;
    gaussianWeight(t, g);
    const IntLanes inside = (r2 <= radiusSquared_) & (kLaneIndex < count);
    const FloatLanes w = inside ? g : FloatLanes{};
    weights_ += w;
    for (int channel = 0; channel < 4; ++channel) {
      FloatLanes color;
      load(&c.rgba[channel][e], color);
      colors_[channel] += w * color;
    }
    if (++blocks_ == kFlushBlocks) flush();
  }

  PBS_CLONE_INLINE void flush() {
    for (int l = 0; l < kLanes; ++l) {
      weight_ += weights_[l];
      color_ += glm::dvec4(colors_[0][l], colors_[1][l], colors_[2][l], colors_[3][l]);
    }
    weights_ = FloatLanes{};
    colors_ = {};
    blocks_ = 0;
  }

  glm::vec3 query_;
  float radiusSquared_;
  float perRadiusSquared_;  // 1 / d², or 0 (see addBlock)
  FloatLanes weights_{};
  std::array<FloatLanes, 4> colors_{};
  int blocks_ = 0;
  double weight_ = 0.0;
  glm::dvec4 color_{0.0};
};

// The filtered colours of the surfels at chosen[byCell[first .. last)].
PBS_AVX2_CLONES void filterColors(const CandidateGrid& grid, std::span<const glm::vec3> chosen,
                                  std::span<const float> distances, std::span<const std::uint32_t> byCell,
                                  std::size_t first, std::size_t last, std::span<glm::u8vec4> colors) {
  for (std::size_t j = first; j < last; ++j) {
    const std::uint32_t i = byCell[j];
    const float radiusSquared = distances[i] * distances[i];
    NeighbourhoodSums sums(chosen[i], radiusSquared);
    grid.forEachRangeNear(chosen[i], radiusSquared,
                          [&](std::uint32_t begin, std::uint32_t end) { sums.add(grid.columns(), begin, end); });
    colors[i] = sums.roundedMean();
  }
}

// The median of the finite, positive distances, 0 when there is none. Most queries have about that
// radius (it shrinks as 1/sqrt(i) along the order); cells of about that size balance the rows a query
// walks against the entries outside its ball that it reads.
double medianRadius(std::span<const float> distances) {
  std::vector<float> finite;
  finite.reserve(distances.size());
  for (float d : distances)
    if (d > 0.0f && d < std::numeric_limits<float>::infinity()) finite.push_back(d);
  if (finite.empty()) return 0.0;
  const auto middle = finite.begin() + std::ptrdiff_t(finite.size() / 2);
  std::nth_element(finite.begin(), middle, finite.end());
  return *middle;
}

}  // namespace

std::string_view surfelColorsName(SurfelColors colors) { return kColorNames.name(colors); }

std::optional<SurfelColors> parseSurfelColors(std::string_view name) { return kColorNames.parse(name); }

std::vector<glm::u8vec4> prefilteredColors(std::span<const Surfel> candidates, std::span<const std::uint32_t> order) {
  std::vector<glm::vec3> positions(candidates.size());
  for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = candidates[i].position;
  return prefilteredColors(positions, candidates, order);
}

std::vector<glm::u8vec4> prefilteredColors(std::span<const glm::vec3> positions, std::span<const Surfel> candidates,
                                           std::span<const std::uint32_t> order) {
  if (positions.size() != candidates.size())
    throw std::invalid_argument("prefilteredColors: " + std::to_string(positions.size()) + " positions for " +
                                std::to_string(candidates.size()) + " candidates");
  // The distances among the chosen surfels alone: the same as over all candidates, for a k-sized grid.
  std::vector<glm::vec3> chosen(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (order[i] >= candidates.size()) {
      throw std::invalid_argument("prefilteredColors: order entry " + std::to_string(i) + " names candidate " +
                                  std::to_string(order[i]) + " of " + std::to_string(candidates.size()));
    }
    chosen[i] = positions[order[i]];
  }
  std::vector<std::uint32_t> sequence(order.size());
  for (std::uint32_t i = 0; i < sequence.size(); ++i) sequence[i] = i;
  const std::vector<float> distances = insertionDistances(chosen, sequence);
  std::vector<glm::u8vec4> colors(order.size());
  if (order.empty()) return colors;
  const double radius = medianRadius(distances);
  const CandidateGrid grid(positions, candidates, radius > 0.0 ? radius : std::numeric_limits<double>::infinity());

  // Surfels in the order of their cells, so that the next one reads mostly the rows the last one
  // brought into the cache (each one's sums do not depend on when they are made).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cellAndSurfel(order.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) cellAndSurfel[i] = {grid.cellOf(chosen[i]), i};
  std::sort(cellAndSurfel.begin(), cellAndSurfel.end());
  std::vector<std::uint32_t> byCell(order.size());
  for (std::size_t j = 0; j < byCell.size(); ++j) byCell[j] = cellAndSurfel[j].second;

  // The first surfels' neighbourhoods are the largest (the first is everything): small grains let the
  // workers share them.
  constexpr std::size_t kGrain = 8;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      filterColors(grid, chosen, distances, byCell, r.begin(), r.end(), colors);
                    });
  return colors;
}

}  // namespace pbs
