// Checks the numerical-stability suite shares: no NaN or Inf in an output, and the same bytes for
// 1, 2 and 4 worker threads.
#pragma once

#include <pbs/raster/framebuffer.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/surfels/surfel.hpp>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

namespace pbs::stability {

inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Depth is kClearDepth or in [0, 1]; every position and normal (covered or not) is finite.
inline void expectFiniteFramebuffer(const Framebuffer& framebuffer) {
  for (std::size_t p = 0; p < framebuffer.pixelCount(); ++p) {
    const float depth = framebuffer.depth[p];
    ASSERT_TRUE(!framebuffer.covered(p) || (depth >= 0.0f && depth <= 1.0f)) << "pixel " << p << ": " << depth;
    ASSERT_TRUE(!framebuffer.has(kChannelPosition) || finite(framebuffer.position[p])) << "pixel " << p;
    ASSERT_TRUE(!framebuffer.has(kChannelNormal) || finite(framebuffer.normal[p])) << "pixel " << p;
  }
}

// A measured error as a gtest property (seen with --gtest_output=xml), to 3 significant digits.
inline void recordMeasured(const char* name, double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  testing::Test::RecordProperty(name, text);
}

inline void expectFiniteSurfels(std::span<const Surfel> surfels) {
  for (std::size_t i = 0; i < surfels.size(); ++i)
    ASSERT_TRUE(finite(surfels[i].position) && finite(surfels[i].normal)) << "surfel " << i;
}

template <class T>
void appendBytes(std::string& out, const std::vector<T>& values) {
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// Every allocated channel, byte for byte.
inline std::string framebufferBytes(const Framebuffer& framebuffer) {
  std::string bytes;
  appendBytes(bytes, framebuffer.depth);
  appendBytes(bytes, framebuffer.color);
  appendBytes(bytes, framebuffer.position);
  appendBytes(bytes, framebuffer.normal);
  appendBytes(bytes, framebuffer.ids);
  return bytes;
}

// make() under 1, 2 and 4 threads; expects bytes(result) to be the same for each, returns the first.
template <class Make, class Bytes>
auto sameBytesForOneTwoAndFourThreads(Make make, Bytes bytes) {
  decltype(make()) first;
  runWithThreads(1, [&] { first = make(); });
  const std::string reference = bytes(first);
  for (const int threads : {2, 4}) {
    decltype(make()) other;
    runWithThreads(threads, [&] { other = make(); });
    EXPECT_TRUE(bytes(other) == reference) << "bytes differ with " << threads << " threads";
  }
  return first;
}

}  // namespace pbs::stability
