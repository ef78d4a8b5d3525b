// Mesa llvmpipe (OpenGL on the CPU through OSMesa) as a peer to time the rasterizer against.
// Loaded with dlopen at run time: pbs neither links nor needs Mesa unless a benchmark asks for it.
#pragma once

#include <pbs/raster/texture.hpp>
#include <pbs/raster/triangles.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

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
  // Clears depth and every colour attachment.
  void clear();
  // Clears depth alone: the capture's clear, as pbs's (its other channels are read only where a
  // pixel is covered).
  void clearDepth();
  // GL_POINTS of `size` pixels with per-point colours, depth test on.
  void drawPoints(const glm::mat4& clipFromObject, std::span<const glm::vec3> positions,
                  std::span<const glm::u8vec4> colors, float size);
  // Switches triangle drawing to the capture G-buffer pbs fills: RGBA8 base colour plus world
  // position and unit normal in 32-bit float attachments, over a 32-bit float depth buffer, all of
  // the context's size, written by a shader program. False, with missingReason() set, where the
  // driver lacks something it needs.
  bool useCaptureGBuffer();
  // The texture as a GL texture with its wrap modes and filters (mip levels made by the driver where its
  // minFilter uses them): the name drawCaptureTriangles takes. Upload before timing.
  std::uint32_t uploadTexture(const Texture& texture);
  // Indexed triangles into the G-buffer: clip position from `clipFromObject`, the position channel
  // from `positionFromObject` (world minus the framebuffer's origin), the normal channel from
  // `normalFromObject` (normalised per pixel), and `baseColor` as the colour channel, times the texture
  // `texture` (uploadTexture's; 0: none) at `uvs` where the mesh has them. Of the faces, `sides` alone, as
  // pbs draws them (TriangleDraw::sides), `mirrored` where clipFromObject turns their winding over.
  void drawCaptureTriangles(const glm::mat4& clipFromObject, const glm::mat4& positionFromObject,
                            const glm::mat3& normalFromObject, const glm::vec4& baseColor,
                            std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                            std::span<const std::uint32_t> indices, std::span<const glm::vec2> uvs = {},
                            std::uint32_t texture = 0, FaceSides sides = FaceSides::both, bool mirrored = false);
  // Limits what is drawn next to a rectangle of the viewport (rows from the top, as pbs counts them), or not.
  void setScissor(const std::optional<PixelRect>& rect);
  // Waits until everything drawn is in the buffers (glFinish), so timings include the work.
  void finish();

  // Number of pixels whose depth is not the cleared value (a sanity check that it drew).
  std::uint64_t coveredPixels();
  // The G-buffer's position channel over the viewport, rows from the top as pbs stores them; NaN
  // where nothing was drawn.
  std::vector<glm::vec3> capturePositions();
  // The G-buffer's colour channel over the viewport, rows from the top.
  std::vector<glm::u8vec4> captureColors();

 private:
  struct Gl;
  void* library_ = nullptr;
  void* context_ = nullptr;
  std::unique_ptr<Gl> gl_;
  std::string missing_;
  std::uint32_t width_ = 0, height_ = 0;
  std::uint32_t viewportWidth_ = 0, viewportHeight_ = 0;
  int clipFromObjectAt_ = -1, positionFromObjectAt_ = -1, normalFromObjectAt_ = -1, baseColorAt_ = -1, texturedAt_ = -1;
  std::unique_ptr<std::uint8_t[]> colorBuffer_;
};

}  // namespace pbs::bench
