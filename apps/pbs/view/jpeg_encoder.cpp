// libjpeg's compressor into its own memory buffer; its errors jump back here instead of exiting.
#include "jpeg_encoder.hpp"

#include <cstdio>  // jpeglib.h needs FILE
#include <jpeglib.h>

#include <csetjmp>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace pbs::cli {
namespace {

struct ErrorJump {
  jpeg_error_mgr manager;  // first: libjpeg sees a pointer to it
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void jumpOnError(j_common_ptr info) {
  auto* error = reinterpret_cast<ErrorJump*>(info->err);
  info->err->format_message(info, error->message);
  std::longjmp(error->jump, 1);
}

}  // namespace

std::vector<std::uint8_t> encodeJpeg(std::span<const std::uint8_t> rgb, std::uint32_t width, std::uint32_t height,
                                     int quality) {
  if (rgb.size() != std::size_t(width) * height * 3) throw std::invalid_argument("JPEG: pixels do not match the size");
  jpeg_compress_struct info{};
  ErrorJump error{};
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = jumpOnError;
  unsigned char* memory = nullptr;
  unsigned long size = 0;
  // Nothing with a destructor lives between here and the jump's target.
  if (setjmp(error.jump)) {
    jpeg_destroy_compress(&info);
    std::free(memory);
    throw std::runtime_error(std::string("JPEG: ") + error.message);
  }
  jpeg_create_compress(&info);
  jpeg_mem_dest(&info, &memory, &size);
  info.image_width = width;
  info.image_height = height;
  info.input_components = 3;
  info.in_color_space = JCS_RGB;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, quality, TRUE);
  info.dct_method = JDCT_IFAST;  // a moving frame: speed over the last bit of fidelity
  jpeg_start_compress(&info, TRUE);
  const std::size_t stride = std::size_t(width) * 3;
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(rgb.data() + info.next_scanline * stride);
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  std::vector<std::uint8_t> bytes(memory, memory + size);
  jpeg_destroy_compress(&info);
  std::free(memory);
  return bytes;
}

}  // namespace pbs::cli
