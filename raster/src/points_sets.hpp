// The point sets of one drawPoints call: checked, laid out as one range of ordinals (set order, then index),
// with per-set transforms, and what a point writes to the channels besides depth.
#pragma once

#include "pbs/raster/points.hpp"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace pbs::points {

// What a splat carries to the pixel it wins, so the cheap cases need no look-up afterwards.
enum class PayloadKind {
  none,     // depth-only framebuffer
  color,    // colour is the only other channel: the point's RGBA8
  ordinal,  // otherwise the point's ordinal in its batch, to look its values up once it has won
};

class PointSets {
 public:
  // Throws std::invalid_argument when the framebuffer does not match the camera or its channels, or when a
  // set lacks an array the framebuffer's channels need.
  PointSets(const Framebuffer& framebuffer, const Camera& camera, std::span<const PointSet> sets);

  std::uint64_t total() const { return first_.back(); }
  std::size_t size() const { return sets_.size(); }
  const PointSet& set(std::size_t s) const { return sets_[s]; }
  std::uint64_t first(std::size_t s) const { return first_[s]; }  // ordinal of the set's point 0
  const glm::dmat4& clipFromObject(std::size_t s) const { return clipFromObject_[s]; }
  PayloadKind payloadKind() const { return payloadKind_; }

  // The set holding `ordinal` (< total()).
  std::size_t setOf(std::uint64_t ordinal) const;

  // The payloads of points [index, index + count) of set s, in a batch starting at ordinal batchStart.
  void payloads(std::size_t s, std::size_t index, std::size_t count, std::uint64_t batchStart,
                std::uint32_t* out) const;

  // Writes the channels besides depth for the pixels [pixel, pixel + count) of one framebuffer row that splats
  // won, from their payloads: those whose new `depth` is below the framebuffer's (which is not yet updated).
  void writeChannels(Framebuffer& framebuffer, std::size_t pixel, std::size_t count, const float* depth,
                     const std::uint32_t* payloads, std::uint64_t batchStart) const;

 private:
  void writeLookedUp(Framebuffer& framebuffer, std::size_t pixel, std::uint64_t ordinal) const;

  std::span<const PointSet> sets_;
  std::vector<std::uint64_t> first_;  // one more than sets: the last is the total
  std::vector<glm::dmat4> clipFromObject_;
  std::vector<glm::dmat3> normalFromObject_;  // inverse transpose of worldFromObject's 3×3
  PayloadKind payloadKind_;
};

}  // namespace pbs::points
