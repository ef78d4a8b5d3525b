// Mesa llvmpipe (OpenGL on the CPU through OSMesa) as a peer to time the rasterizer against.
// Loaded with dlopen at run time: pbs neither links nor needs Mesa unless a benchmark asks for it.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace pbs::bench {

class LlvmpipePeer {
 public:
  // Opens libOSMesa and makes a width×height RGBA8 + 24-bit depth context current on this thread,
  // with `threads` llvmpipe rasterizer threads. On failure, available() is false and missingReason()
  // says why (the benchmark then reports the peer as missing).
  LlvmpipePeer(std::uint32_t width, std::uint32_t height, int threads);
  ~LlvmpipePeer();
  LlvmpipePeer(const LlvmpipePeer&) = delete;
  LlvmpipePeer& operator=(const LlvmpipePeer&) = delete;

  bool available() const { return gl_ != nullptr; }
  const std::string& missingReason() const { return missing_; }

  // Draws into the lower-left width×height pixels (at most the context's size) from now on.
  void setViewport(std::uint32_t width, std::uint32_t height);
  void clear();
  // Indexed triangles with per-vertex colours under `clipFromObject`, depth test on.
  void drawTriangles(const glm::mat4& clipFromObject, std::span<const glm::vec3> positions,
                     std::span<const glm::u8vec4> colors, std::span<const std::uint32_t> indices);
  // GL_POINTS of `size` pixels with per-point colours, depth test on.
  void drawPoints(const glm::mat4& clipFromObject, std::span<const glm::vec3> positions,
                  std::span<const glm::u8vec4> colors, float size);
  // Waits until everything drawn is in the buffers (glFinish), so timings include the work.
  void finish();

  // Number of pixels whose depth is not the cleared value (a sanity check that it drew).
  std::uint64_t coveredPixels();

 private:
  struct Gl;
  void* library_ = nullptr;
  void* context_ = nullptr;
  std::unique_ptr<Gl> gl_;
  std::string missing_;
  std::uint32_t width_ = 0, height_ = 0;
  std::unique_ptr<std::uint8_t[]> colorBuffer_;
};

}  // namespace pbs::bench
