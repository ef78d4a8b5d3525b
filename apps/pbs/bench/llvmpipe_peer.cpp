// The llvmpipe peer: OSMesa and legacy OpenGL entry points resolved at run time, fixed-function
// vertex arrays (the least driver overhead llvmpipe offers for plain coloured geometry).
#include "llvmpipe_peer.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace pbs::bench {
namespace {

using GLenum = unsigned int;
using GLint = int;
using GLsizei = int;
using GLbitfield = unsigned int;
using GLfloat = float;

constexpr GLenum kRgba = 0x1908, kUnsignedByte = 0x1401, kUnsignedInt = 0x1405, kFloat = 0x1406;
constexpr GLenum kDepthTest = 0x0B71, kVertexArray = 0x8074, kColorArray = 0x8076;
constexpr GLenum kProjection = 0x1701, kModelview = 0x1700, kTriangles = 0x0004, kPoints = 0x0000;
constexpr GLenum kLess = 0x0201, kDepthComponent = 0x1902;
constexpr GLbitfield kColorBit = 0x4000, kDepthBit = 0x0100;

template <typename F>
F resolve(void* (*getProc)(const char*), const char* name) {
  return reinterpret_cast<F>(getProc(name));
}

}  // namespace

struct LlvmpipePeer::Gl {
  void (*clear)(GLbitfield);
  void (*clearDepth)(double);
  void (*enable)(GLenum);
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
  gl_->viewport(0, 0, GLsizei(width), GLsizei(height));
}

void LlvmpipePeer::clear() { gl_->clear(kColorBit | kDepthBit); }

void LlvmpipePeer::finish() { gl_->finish(); }

void LlvmpipePeer::drawTriangles(const glm::mat4& clipFromObject, std::span<const glm::vec3> positions,
                                 std::span<const glm::u8vec4> colors, std::span<const std::uint32_t> indices) {
  gl_->matrixMode(kProjection);
  gl_->loadMatrixf(&clipFromObject[0][0]);
  gl_->vertexPointer(3, kFloat, 0, positions.data());
  gl_->colorPointer(4, kUnsignedByte, 0, colors.data());
  gl_->drawElements(kTriangles, GLsizei(indices.size()), kUnsignedInt, indices.data());
}

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

}  // namespace pbs::bench
