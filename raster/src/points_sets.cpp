// Checking and laying out the point sets of a draw, and the per-point channel values.
#include "points_sets.hpp"
#include "pbs/raster/simd_clones.hpp"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace pbs::points {

namespace {

void checkFramebuffer(const Framebuffer& framebuffer, const Camera& camera) {
  if (framebuffer.width != camera.width || framebuffer.height != camera.height)
    throw std::invalid_argument("drawPoints: framebuffer is " + std::to_string(framebuffer.width) + "x" +
                                std::to_string(framebuffer.height) + " but the camera's viewport is " +
                                std::to_string(camera.width) + "x" + std::to_string(camera.height));
  const std::size_t pixels = framebuffer.pixelCount();
  const auto check = [&](bool wanted, std::size_t size, const char* name) {
    if (size != (wanted ? pixels : 0))
      throw std::invalid_argument(std::string("drawPoints: the framebuffer's ") + name + " channel has " +
                                  std::to_string(size) + " pixels, expected " + std::to_string(wanted ? pixels : 0));
  };
  check(true, framebuffer.depth.size(), "depth");
  check(framebuffer.has(kChannelColor), framebuffer.color.size(), "colour");
  check(framebuffer.has(kChannelPosition), framebuffer.position.size(), "position");
  check(framebuffer.has(kChannelNormal), framebuffer.normal.size(), "normal");
  check(framebuffer.has(kChannelIds), framebuffer.ids.size(), "ids");
}

void checkSet(const Framebuffer& framebuffer, const PointSet& set, std::size_t index) {
  const std::size_t points = set.positions.size();
  const auto fail = [&](const char* what, std::size_t size) {
    throw std::invalid_argument("drawPoints: point set " + std::to_string(index) + " has " + std::to_string(size) +
                                " " + what + " for " + std::to_string(points) + " points");
  };
  // The primitive id 0xffffffff means "no point".
  if (points >= 0xffffffffu) fail("positions", points);
  if (framebuffer.has(kChannelColor) && set.colors.size() != points) fail("colours", set.colors.size());
  if (framebuffer.has(kChannelNormal) && set.normals.size() != points) fail("normals", set.normals.size());
  if (!set.sizeFactors.empty() && set.sizeFactors.size() != points) fail("size factors", set.sizeFactors.size());
}

// Unit length, or zero when the normal or the matrix is degenerate: never NaN.
glm::vec3 worldNormal(const glm::dmat3& normalFromObject, const glm::vec3& normal) {
  const glm::dvec3 n = normalFromObject * glm::dvec3(normal);
  const double length = glm::length(n);
  if (!(length > 0.0 && length <= std::numeric_limits<double>::max())) return glm::vec3(0.0f);
  return glm::vec3(n / length);
}

}  // namespace

PointSets::PointSets(const Framebuffer& framebuffer, const Camera& camera, std::span<const PointSet> sets)
    : sets_(sets),
      payloadKind_(framebuffer.channels == 0               ? PayloadKind::none
                   : framebuffer.channels == kChannelColor ? PayloadKind::color
                                                           : PayloadKind::ordinal) {
  checkFramebuffer(framebuffer, camera);
  first_.reserve(sets.size() + 1);
  first_.push_back(0);
  clipFromObject_.reserve(sets.size());
  normalFromObject_.reserve(sets.size());
  const glm::dmat4 clipFromWorld = camera.clipFromWorld();
  for (std::size_t s = 0; s < sets.size(); ++s) {
    checkSet(framebuffer, sets[s], s);
    first_.push_back(first_.back() + sets[s].positions.size());
    clipFromObject_.push_back(clipFromWorld * sets[s].worldFromObject);
    normalFromObject_.push_back(glm::inverseTranspose(glm::dmat3(sets[s].worldFromObject)));
  }
}

std::size_t PointSets::setOf(std::uint64_t ordinal) const {
  // The last set starting at or before the ordinal; empty sets before it share its start and are skipped.
  return static_cast<std::size_t>(std::upper_bound(first_.begin(), first_.end(), ordinal) - first_.begin()) - 1;
}

void PointSets::payloads(std::size_t s, std::size_t index, std::size_t count, std::uint64_t batchStart,
                         std::uint32_t* out) const {
  switch (payloadKind_) {
    case PayloadKind::none: return;
    case PayloadKind::color:
      // RGBA8 is the payload word, byte for byte: one block copy.
      std::memcpy(out, sets_[s].colors.data() + index, count * sizeof(std::uint32_t));
      return;
    case PayloadKind::ordinal:
      // Batches hold fewer than 2^32 points (points.cpp), so a batch ordinal fits.
      const auto first = static_cast<std::uint32_t>(first_[s] + index - batchStart);
      for (std::size_t i = 0; i < count; ++i) out[i] = first + static_cast<std::uint32_t>(i);
      return;
  }
}

namespace {

// Branch-free: about half the pixels of a row change hands in a dense draw, a branch would mispredict. The
// arrays are distinct (restrict) and colours are moved as 32-bit words, so the loop vectorises.
PBS_AVX2_CLONES
void writeColors(glm::u8vec4* __restrict color, std::size_t count, const float* __restrict depth,
                 const float* __restrict old, const std::uint32_t* __restrict payloads) {
  static_assert(sizeof(glm::u8vec4) == sizeof(std::uint32_t));
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t take = 0u - static_cast<std::uint32_t>(depth[i] < old[i]);
    std::uint32_t word;
    std::memcpy(&word, color + i, sizeof word);
    word = (payloads[i] & take) | (word & ~take);
    std::memcpy(color + i, &word, sizeof word);
  }
}

}  // namespace

void PointSets::writeChannels(Framebuffer& framebuffer, std::size_t pixel, std::size_t count, const float* depth,
                              const std::uint32_t* payloads, std::uint64_t batchStart) const {
  const float* old = framebuffer.depth.data() + pixel;
  if (payloadKind_ == PayloadKind::color) {
    writeColors(framebuffer.color.data() + pixel, count, depth, old, payloads);
    return;
  }
  for (std::size_t i = 0; i < count; ++i)
    if (depth[i] < old[i]) writeLookedUp(framebuffer, pixel + i, batchStart + payloads[i]);
}

void PointSets::writeLookedUp(Framebuffer& framebuffer, std::size_t pixel, std::uint64_t ordinal) const {
  const std::size_t s = setOf(ordinal);
  const PointSet& set = sets_[s];
  const std::size_t i = static_cast<std::size_t>(ordinal - first_[s]);
  if (framebuffer.has(kChannelColor)) framebuffer.color[pixel] = set.colors[i];
  if (framebuffer.has(kChannelPosition)) {
    const glm::dvec3 world(set.worldFromObject * glm::dvec4(glm::dvec3(set.positions[i]), 1.0));
    framebuffer.position[pixel] = glm::vec3(world - framebuffer.positionOrigin);
  }
  if (framebuffer.has(kChannelNormal)) framebuffer.normal[pixel] = worldNormal(normalFromObject_[s], set.normals[i]);
  if (framebuffer.has(kChannelIds))
    framebuffer.ids[pixel] = PixelIds{set.nodeId, set.instanceId, static_cast<std::uint32_t>(i)};
}

}  // namespace pbs::points
