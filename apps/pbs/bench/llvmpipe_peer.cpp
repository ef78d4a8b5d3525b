// The llvmpipe peer: OSMesa and OpenGL entry points resolved at run time. Points use fixed-function
// vertex arrays (the least driver overhead llvmpipe offers for plain coloured geometry); capture
// triangles go through a small shader program into a G-buffer of the channels pbs fills, textured
// base colours included, so both do the same work.
#include "llvmpipe_peer.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace pbs::bench {
namespace {

using GLenum = unsigned int;
using GLint = int;
using GLsizei = int;
using GLbitfield = unsigned int;
using GLfloat = float;
using GLuint = unsigned int;
using GLchar = char;
using GLboolean = unsigned char;

constexpr GLenum kRgba = 0x1908, kUnsignedByte = 0x1401, kUnsignedInt = 0x1405, kFloat = 0x1406;
constexpr GLenum kDepthTest = 0x0B71, kVertexArray = 0x8074, kColorArray = 0x8076;
constexpr GLenum kScissorTest = 0x0C11;
constexpr GLenum kCullFace = 0x0B44, kFront = 0x0404, kBack = 0x0405, kClockwise = 0x0900, kCounterClockwise = 0x0901;
constexpr GLenum kProjection = 0x1701, kModelview = 0x1700, kTriangles = 0x0004, kPoints = 0x0000;
constexpr GLenum kLess = 0x0201, kDepthComponent = 0x1902;
constexpr GLbitfield kColorBit = 0x4000, kDepthBit = 0x0100;
constexpr GLenum kFramebuffer = 0x8D40, kRenderbuffer = 0x8D41, kColorAttachment0 = 0x8CE0, kDepthAttachment = 0x8D00;
constexpr GLenum kFramebufferComplete = 0x8CD5, kRgba8 = 0x8058, kRgb32f = 0x8815, kDepth32f = 0x8CAC, kRgb = 0x1907;
constexpr GLenum kVertexShader = 0x8B31, kFragmentShader = 0x8B30, kCompileStatus = 0x8B81, kLinkStatus = 0x8B82;
constexpr GLenum kTexture2d = 0x0DE1, kTextureMagFilter = 0x2800, kTextureMinFilter = 0x2801, kTextureWrapS = 0x2802,
                 kTextureWrapT = 0x2803;
constexpr GLenum kNearest = 0x2600, kLinear = 0x2601, kNearestMipmapNearest = 0x2700, kLinearMipmapNearest = 0x2701,
                 kNearestMipmapLinear = 0x2702, kLinearMipmapLinear = 0x2703;
constexpr GLenum kRepeat = 0x2901, kClampToEdge = 0x812F, kMirroredRepeat = 0x8370;

// World position and normal per vertex into the colour, position and normal attachments.
constexpr const char* kCaptureVertexShader = R"(#version 330 core
layout(location = 0) in vec3 objectPosition;
layout(location = 1) in vec3 objectNormal;
layout(location = 2) in vec2 objectUv;
uniform mat4 clipFromObject;
uniform mat4 positionFromObject;
uniform mat3 normalFromObject;
out vec3 position;
out vec3 normal;
out vec2 uv;
void main() {
  uv = objectUv;
  position = (positionFromObject * vec4(objectPosition, 1.0)).xyz;
  normal = normalFromObject * objectNormal;
  gl_Position = clipFromObject * vec4(objectPosition, 1.0);
}
)";
constexpr const char* kCaptureFragmentShader = R"(#version 330 core
uniform vec4 baseColor;
uniform bool textured;
uniform sampler2D baseTexture;
in vec3 position;
in vec3 normal;
in vec2 uv;
layout(location = 0) out vec4 outColor;
layout(location = 1) out vec3 outPosition;
layout(location = 2) out vec3 outNormal;
void main() {
  outColor = textured ? baseColor * texture(baseTexture, uv) : baseColor;
  outPosition = position;
  outNormal = normalize(normal);
}
)";

template <typename F>
F resolve(void* (*getProc)(const char*), const char* name) {
  return reinterpret_cast<F>(getProc(name));
}

}  // namespace

struct LlvmpipePeer::Gl {
  void (*clear)(GLbitfield);
  void (*clearDepth)(double);
  void (*enable)(GLenum);
  void (*disable)(GLenum);
  void (*cullFace)(GLenum);
  void (*frontFace)(GLenum);
  void (*scissor)(GLint, GLint, GLsizei, GLsizei);
  void (*depthFunc)(GLenum);
  void (*viewport)(GLint, GLint, GLsizei, GLsizei);
  void (*matrixMode)(GLenum);
  void (*loadMatrixf)(const GLfloat*);
  void (*loadIdentity)();
  void (*enableClientState)(GLenum);
  void (*vertexPointer)(GLint, GLenum, GLsizei, const void*);
  void (*colorPointer)(GLint, GLenum, GLsizei, const void*);
  void (*drawElements)(GLenum, GLsizei, GLenum, const void*);
  void (*drawArrays)(GLenum, GLint, GLsizei);
  void (*pointSize)(GLfloat);
  void (*finish)();
  void (*readPixels)(GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, void*);
  void (*disableClientState)(GLenum);
  void (*genFramebuffers)(GLsizei, GLuint*);
  void (*bindFramebuffer)(GLenum, GLuint);
  void (*genRenderbuffers)(GLsizei, GLuint*);
  void (*bindRenderbuffer)(GLenum, GLuint);
  void (*renderbufferStorage)(GLenum, GLenum, GLsizei, GLsizei);
  void (*framebufferRenderbuffer)(GLenum, GLenum, GLenum, GLuint);
  GLenum (*checkFramebufferStatus)(GLenum);
  void (*drawBuffers)(GLsizei, const GLenum*);
  void (*readBuffer)(GLenum);
  GLuint (*createShader)(GLenum);
  void (*shaderSource)(GLuint, GLsizei, const GLchar* const*, const GLint*);
  void (*compileShader)(GLuint);
  void (*getShaderiv)(GLuint, GLenum, GLint*);
  GLuint (*createProgram)();
  void (*attachShader)(GLuint, GLuint);
  void (*linkProgram)(GLuint);
  void (*getProgramiv)(GLuint, GLenum, GLint*);
  void (*useProgram)(GLuint);
  GLint (*getUniformLocation)(GLuint, const GLchar*);
  void (*uniformMatrix4fv)(GLint, GLsizei, GLboolean, const GLfloat*);
  void (*uniformMatrix3fv)(GLint, GLsizei, GLboolean, const GLfloat*);
  void (*uniform4fv)(GLint, GLsizei, const GLfloat*);
  void (*enableVertexAttribArray)(GLuint);
  void (*vertexAttribPointer)(GLuint, GLint, GLenum, GLboolean, GLsizei, const void*);
  void (*disableVertexAttribArray)(GLuint);
  void (*uniform1i)(GLint, GLint);
  void (*genTextures)(GLsizei, GLuint*);
  void (*bindTexture)(GLenum, GLuint);
  void (*texImage2D)(GLenum, GLint, GLint, GLsizei, GLsizei, GLint, GLenum, GLenum, const void*);
  void (*texParameteri)(GLenum, GLenum, GLint);
  void (*generateMipmap)(GLenum);
  void (*destroyContext)(void*);
};

LlvmpipePeer::LlvmpipePeer(std::uint32_t width, std::uint32_t height, int threads) : width_(width), height_(height) {
  // llvmpipe reads its thread count from the environment when the first context is created.
  setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
  library_ = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
  if (!library_) {
    missing_ = "libOSMesa.so.8 not found (Debian package libosmesa6)";
    return;
  }
  using CreateContext = void* (*)(GLenum, GLint, GLint, GLint, void*);
  using MakeCurrent = unsigned char (*)(void*, void*, GLenum, GLsizei, GLsizei);
  using GetProc = void* (*)(const char*);
  auto create = reinterpret_cast<CreateContext>(dlsym(library_, "OSMesaCreateContextExt"));
  auto makeCurrent = reinterpret_cast<MakeCurrent>(dlsym(library_, "OSMesaMakeCurrent"));
  auto getProc = reinterpret_cast<GetProc>(dlsym(library_, "OSMesaGetProcAddress"));
  auto destroy = reinterpret_cast<void (*)(void*)>(dlsym(library_, "OSMesaDestroyContext"));
  if (!create || !makeCurrent || !getProc || !destroy) {
    missing_ = "libOSMesa lacks the OSMesa entry points";
    return;
  }
  context_ = create(kRgba, 24, 0, 0, nullptr);
  colorBuffer_ = std::make_unique<std::uint8_t[]>(std::size_t(width) * height * 4);
  if (!context_ || !makeCurrent(context_, colorBuffer_.get(), kUnsignedByte, GLsizei(width), GLsizei(height))) {
    missing_ = "OSMesa could not create a context";
    return;
  }
  auto gl = std::make_unique<Gl>(Gl{
      resolve<decltype(Gl::clear)>(getProc, "glClear"),
      resolve<decltype(Gl::clearDepth)>(getProc, "glClearDepth"),
      resolve<decltype(Gl::enable)>(getProc, "glEnable"),
      resolve<decltype(Gl::disable)>(getProc, "glDisable"),
      resolve<decltype(Gl::cullFace)>(getProc, "glCullFace"),
      resolve<decltype(Gl::frontFace)>(getProc, "glFrontFace"),
      resolve<decltype(Gl::scissor)>(getProc, "glScissor"),
      resolve<decltype(Gl::depthFunc)>(getProc, "glDepthFunc"),
      resolve<decltype(Gl::viewport)>(getProc, "glViewport"),
      resolve<decltype(Gl::matrixMode)>(getProc, "glMatrixMode"),
      resolve<decltype(Gl::loadMatrixf)>(getProc, "glLoadMatrixf"),
      resolve<decltype(Gl::loadIdentity)>(getProc, "glLoadIdentity"),
      resolve<decltype(Gl::enableClientState)>(getProc, "glEnableClientState"),
      resolve<decltype(Gl::vertexPointer)>(getProc, "glVertexPointer"),
      resolve<decltype(Gl::colorPointer)>(getProc, "glColorPointer"),
      resolve<decltype(Gl::drawElements)>(getProc, "glDrawElements"),
      resolve<decltype(Gl::drawArrays)>(getProc, "glDrawArrays"),
      resolve<decltype(Gl::pointSize)>(getProc, "glPointSize"),
      resolve<decltype(Gl::finish)>(getProc, "glFinish"),
      resolve<decltype(Gl::readPixels)>(getProc, "glReadPixels"),
      resolve<decltype(Gl::disableClientState)>(getProc, "glDisableClientState"),
      resolve<decltype(Gl::genFramebuffers)>(getProc, "glGenFramebuffers"),
      resolve<decltype(Gl::bindFramebuffer)>(getProc, "glBindFramebuffer"),
      resolve<decltype(Gl::genRenderbuffers)>(getProc, "glGenRenderbuffers"),
      resolve<decltype(Gl::bindRenderbuffer)>(getProc, "glBindRenderbuffer"),
      resolve<decltype(Gl::renderbufferStorage)>(getProc, "glRenderbufferStorage"),
      resolve<decltype(Gl::framebufferRenderbuffer)>(getProc, "glFramebufferRenderbuffer"),
      resolve<decltype(Gl::checkFramebufferStatus)>(getProc, "glCheckFramebufferStatus"),
      resolve<decltype(Gl::drawBuffers)>(getProc, "glDrawBuffers"),
      resolve<decltype(Gl::readBuffer)>(getProc, "glReadBuffer"),
      resolve<decltype(Gl::createShader)>(getProc, "glCreateShader"),
      resolve<decltype(Gl::shaderSource)>(getProc, "glShaderSource"),
      resolve<decltype(Gl::compileShader)>(getProc, "glCompileShader"),
      resolve<decltype(Gl::getShaderiv)>(getProc, "glGetShaderiv"),
      resolve<decltype(Gl::createProgram)>(getProc, "glCreateProgram"),
      resolve<decltype(Gl::attachShader)>(getProc, "glAttachShader"),
      resolve<decltype(Gl::linkProgram)>(getProc, "glLinkProgram"),
      resolve<decltype(Gl::getProgramiv)>(getProc, "glGetProgramiv"),
      resolve<decltype(Gl::useProgram)>(getProc, "glUseProgram"),
      resolve<decltype(Gl::getUniformLocation)>(getProc, "glGetUniformLocation"),
      resolve<decltype(Gl::uniformMatrix4fv)>(getProc, "glUniformMatrix4fv"),
      resolve<decltype(Gl::uniformMatrix3fv)>(getProc, "glUniformMatrix3fv"),
      resolve<decltype(Gl::uniform4fv)>(getProc, "glUniform4fv"),
      resolve<decltype(Gl::enableVertexAttribArray)>(getProc, "glEnableVertexAttribArray"),
      resolve<decltype(Gl::vertexAttribPointer)>(getProc, "glVertexAttribPointer"),
      resolve<decltype(Gl::disableVertexAttribArray)>(getProc, "glDisableVertexAttribArray"),
      resolve<decltype(Gl::uniform1i)>(getProc, "glUniform1i"),
      resolve<decltype(Gl::genTextures)>(getProc, "glGenTextures"),
      resolve<decltype(Gl::bindTexture)>(getProc, "glBindTexture"),
      resolve<decltype(Gl::texImage2D)>(getProc, "glTexImage2D"),
      resolve<decltype(Gl::texParameteri)>(getProc, "glTexParameteri"),
      resolve<decltype(Gl::generateMipmap)>(getProc, "glGenerateMipmap"),
      destroy,
  });
  gl->viewport(0, 0, GLsizei(width), GLsizei(height));
  gl->enable(kDepthTest);
  gl->depthFunc(kLess);
  gl->clearDepth(1.0);
  gl->matrixMode(kModelview);
  gl->loadIdentity();
  gl->enableClientState(kVertexArray);
  gl->enableClientState(kColorArray);
  gl_ = std::move(gl);
}

LlvmpipePeer::~LlvmpipePeer() {
  if (gl_ && context_) gl_->destroyContext(context_);
  // The library stays loaded: Mesa and its LLVM are not safe to unload within a process.
}

void LlvmpipePeer::setViewport(std::uint32_t width, std::uint32_t height) {
  viewportWidth_ = width;
  viewportHeight_ = height;
  gl_->viewport(0, 0, GLsizei(width), GLsizei(height));
}

bool LlvmpipePeer::useCaptureGBuffer() {
  const Gl& gl = *gl_;
  const auto fail = [&](const char* why) {
    missing_ = why;
    return false;
  };
  const bool hasEntryPoints =
      gl.disableClientState && gl.genFramebuffers && gl.bindFramebuffer && gl.genRenderbuffers && gl.bindRenderbuffer &&
      gl.renderbufferStorage && gl.framebufferRenderbuffer && gl.checkFramebufferStatus && gl.drawBuffers &&
      gl.readBuffer && gl.createShader && gl.shaderSource && gl.compileShader && gl.getShaderiv && gl.createProgram &&
      gl.attachShader && gl.linkProgram && gl.getProgramiv && gl.useProgram && gl.getUniformLocation &&
      gl.uniformMatrix4fv && gl.uniformMatrix3fv && gl.uniform4fv && gl.enableVertexAttribArray &&
      gl.vertexAttribPointer && gl.disableVertexAttribArray && gl.uniform1i && gl.genTextures && gl.bindTexture &&
      gl.texImage2D && gl.texParameteri && gl.generateMipmap;
  if (!hasEntryPoints) return fail("libOSMesa lacks the OpenGL 3.3 entry points the G-buffer needs");
  GLuint framebuffer = 0;
  gl.genFramebuffers(1, &framebuffer);
  gl.bindFramebuffer(kFramebuffer, framebuffer);
  const GLenum formats[3] = {kRgba8, kRgb32f, kRgb32f};  // colour, position, normal
  GLenum drawBuffers[3];
  for (int i = 0; i < 3; ++i) {
    GLuint renderbuffer = 0;
    gl.genRenderbuffers(1, &renderbuffer);
    gl.bindRenderbuffer(kRenderbuffer, renderbuffer);
    gl.renderbufferStorage(kRenderbuffer, formats[i], GLsizei(width_), GLsizei(height_));
    drawBuffers[i] = kColorAttachment0 + GLenum(i);
    gl.framebufferRenderbuffer(kFramebuffer, drawBuffers[i], kRenderbuffer, renderbuffer);
  }
  GLuint depth = 0;
  gl.genRenderbuffers(1, &depth);
  gl.bindRenderbuffer(kRenderbuffer, depth);
  gl.renderbufferStorage(kRenderbuffer, kDepth32f, GLsizei(width_), GLsizei(height_));
  gl.framebufferRenderbuffer(kFramebuffer, kDepthAttachment, kRenderbuffer, depth);
  gl.drawBuffers(3, drawBuffers);
  if (gl.checkFramebufferStatus(kFramebuffer) != kFramebufferComplete)
    return fail("llvmpipe cannot render to an RGBA8 + RGB32F + RGB32F + DEPTH32F framebuffer");

  const auto compile = [&](GLenum kind, const char* source) {
    const GLuint shader = gl.createShader(kind);
    gl.shaderSource(shader, 1, &source, nullptr);
    gl.compileShader(shader);
    GLint compiled = 0;
    gl.getShaderiv(shader, kCompileStatus, &compiled);
    return compiled ? shader : 0u;
  };
  const GLuint vertex = compile(kVertexShader, kCaptureVertexShader);
  const GLuint fragment = compile(kFragmentShader, kCaptureFragmentShader);
  if (!vertex || !fragment) return fail("llvmpipe could not compile the G-buffer shaders");
  const GLuint program = gl.createProgram();
  gl.attachShader(program, vertex);
  gl.attachShader(program, fragment);
  gl.linkProgram(program);
  GLint linked = 0;
  gl.getProgramiv(program, kLinkStatus, &linked);
  if (!linked) return fail("llvmpipe could not link the G-buffer shaders");
  gl.useProgram(program);
  clipFromObjectAt_ = gl.getUniformLocation(program, "clipFromObject");
  positionFromObjectAt_ = gl.getUniformLocation(program, "positionFromObject");
  normalFromObjectAt_ = gl.getUniformLocation(program, "normalFromObject");
  baseColorAt_ = gl.getUniformLocation(program, "baseColor");
  texturedAt_ = gl.getUniformLocation(program, "textured");
  gl.uniform1i(gl.getUniformLocation(program, "baseTexture"), 0);  // texture unit 0
  // The program reads generic attributes 0 and 1; the fixed-function arrays stay off.
  gl.disableClientState(kVertexArray);
  gl.disableClientState(kColorArray);
  gl.enableVertexAttribArray(0);
  gl.enableVertexAttribArray(1);
  return true;
}

std::uint32_t LlvmpipePeer::uploadTexture(const Texture& texture) {
  const Gl& gl = *gl_;
  GLuint name = 0;
  gl.genTextures(1, &name);
  gl.bindTexture(kTexture2d, name);
  // Rows top first, as glTF's v runs: uploaded as they are, texture(uv) reads what pbs's sampler reads at uv.
  gl.texImage2D(kTexture2d, 0, GLint(kRgba8), GLsizei(texture.width), GLsizei(texture.height), 0, kRgba, kUnsignedByte,
                texture.rgba8.data());
  const auto wrap = [](TextureWrap w) {
    return GLint(w == TextureWrap::ClampToEdge      ? kClampToEdge
                 : w == TextureWrap::MirroredRepeat ? kMirroredRepeat
                                                    : kRepeat);
  };
  const bool linear = texture.minFilter == TextureFilter::Linear;
  GLenum minFilter = linear ? kLinear : kNearest;
  if (texture.mipmap == TextureMipmap::Nearest) minFilter = linear ? kLinearMipmapNearest : kNearestMipmapNearest;
  if (texture.mipmap == TextureMipmap::Linear) minFilter = linear ? kLinearMipmapLinear : kNearestMipmapLinear;
  gl.texParameteri(kTexture2d, kTextureMinFilter, GLint(minFilter));
  gl.texParameteri(kTexture2d, kTextureMagFilter,
                   GLint(texture.magFilter == TextureFilter::Linear ? kLinear : kNearest));
  gl.texParameteri(kTexture2d, kTextureWrapS, wrap(texture.wrapS));
  gl.texParameteri(kTexture2d, kTextureWrapT, wrap(texture.wrapT));
  if (texture.mipmap != TextureMipmap::None) gl.generateMipmap(kTexture2d);
  return name;
}

void LlvmpipePeer::drawCaptureTriangles(const glm::mat4& clipFromObject, const glm::mat4& positionFromObject,
                                        const glm::mat3& normalFromObject, const glm::vec4& baseColor,
                                        std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                        std::span<const std::uint32_t> indices, std::span<const glm::vec2> uvs,
                                        std::uint32_t texture, FaceSides sides, bool mirrored) {
  const Gl& gl = *gl_;
  // Counter-clockwise in clip space is counter-clockwise in GL's window too (its y runs up, as clip space's).
  if (sides == FaceSides::both) {
    gl.disable(kCullFace);
  } else {
    gl.enable(kCullFace);
    gl.frontFace(mirrored ? kClockwise : kCounterClockwise);
    gl.cullFace(sides == FaceSides::front ? kBack : kFront);
  }
  gl.uniformMatrix4fv(clipFromObjectAt_, 1, 0, &clipFromObject[0][0]);
  gl.uniformMatrix4fv(positionFromObjectAt_, 1, 0, &positionFromObject[0][0]);
  gl.uniformMatrix3fv(normalFromObjectAt_, 1, 0, &normalFromObject[0][0]);
  gl.uniform4fv(baseColorAt_, 1, &baseColor[0]);
  const bool textured = texture != 0 && uvs.size() == positions.size();
  gl.uniform1i(texturedAt_, textured);
  if (textured) {
    gl.bindTexture(kTexture2d, texture);
    gl.enableVertexAttribArray(2);
    gl.vertexAttribPointer(2, 2, kFloat, 0, 0, uvs.data());
  } else {
    gl.disableVertexAttribArray(2);
  }
  gl.vertexAttribPointer(0, 3, kFloat, 0, 0, positions.data());
  gl.vertexAttribPointer(1, 3, kFloat, 0, 0, normals.data());
  gl.drawElements(kTriangles, GLsizei(indices.size()), kUnsignedInt, indices.data());
}

void LlvmpipePeer::setScissor(const std::optional<PixelRect>& rect) {
  if (!rect) {
    gl_->disable(kScissorTest);
    return;
  }
  // GL's rows run up from the bottom.
  const GLint x0 = std::max(0, rect->x0), y0 = std::max(0, rect->y0);
  const GLint x1 = std::min(GLint(viewportWidth_) - 1, rect->x1), y1 = std::min(GLint(viewportHeight_) - 1, rect->y1);
  gl_->enable(kScissorTest);
  gl_->scissor(x0, GLint(viewportHeight_) - 1 - y1, std::max(0, x1 - x0 + 1), std::max(0, y1 - y0 + 1));
}

void LlvmpipePeer::clear() { gl_->clear(kColorBit | kDepthBit); }

void LlvmpipePeer::clearDepth() { gl_->clear(kDepthBit); }

void LlvmpipePeer::finish() { gl_->finish(); }

void LlvmpipePeer::drawPoints(const glm::mat4& clipFromObject, std::span<const glm::vec3> positions,
                              std::span<const glm::u8vec4> colors, float size) {
  gl_->matrixMode(kProjection);
  gl_->loadMatrixf(&clipFromObject[0][0]);
  gl_->pointSize(size);
  gl_->vertexPointer(3, kFloat, 0, positions.data());
  gl_->colorPointer(4, kUnsignedByte, 0, colors.data());
  gl_->drawArrays(kPoints, 0, GLsizei(positions.size()));
}

std::uint64_t LlvmpipePeer::coveredPixels() {
  std::vector<float> depth(std::size_t(width_) * height_);
  gl_->readPixels(0, 0, GLsizei(width_), GLsizei(height_), kDepthComponent, kFloat, depth.data());
  std::uint64_t covered = 0;
  for (float d : depth) covered += d < 1.0f;
  return covered;
}

std::vector<glm::u8vec4> LlvmpipePeer::captureColors() {
  const std::size_t width = viewportWidth_, height = viewportHeight_;
  std::vector<glm::u8vec4> color(width * height);
  gl_->readBuffer(kColorAttachment0);
  gl_->readPixels(0, 0, GLsizei(width), GLsizei(height), kRgba, kUnsignedByte, color.data());
  std::vector<glm::u8vec4> topDown(width * height);
  for (std::size_t row = 0; row < height; ++row)
    std::copy_n(color.begin() + std::ptrdiff_t((height - 1 - row) * width), width,
                topDown.begin() + std::ptrdiff_t(row * width));
  return topDown;
}

std::vector<glm::vec3> LlvmpipePeer::capturePositions() {
  const std::size_t width = viewportWidth_, height = viewportHeight_;
  std::vector<float> depth(width * height);
  std::vector<glm::vec3> position(width * height);
  gl_->readPixels(0, 0, GLsizei(width), GLsizei(height), kDepthComponent, kFloat, depth.data());
  gl_->readBuffer(kColorAttachment0 + 1);
  gl_->readPixels(0, 0, GLsizei(width), GLsizei(height), kRgb, kFloat, position.data());
  gl_->readBuffer(kColorAttachment0);
  std::vector<glm::vec3> topDown(width * height, glm::vec3(std::numeric_limits<float>::quiet_NaN()));
  for (std::size_t row = 0; row < height; ++row)
    for (std::size_t column = 0; column < width; ++column) {
      const std::size_t from = (height - 1 - row) * width + column;
      if (depth[from] < 1.0f) topDown[row * width + column] = position[from];
    }
  return topDown;
}

}  // namespace pbs::bench
