// Image output through OpenImageIO with the temporary-name-then-rename rule of every pbs output.
#include "image_files.hpp"

#include <OpenImageIO/imageio.h>

#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace pbs::cli {

void writeImage8(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height, int channels,
                 std::span<const std::uint8_t> pixels) {
  // Same folder (so the rename is atomic) and same extension (OpenImageIO picks the format by it).
  std::string name(1, '.');  // appended piece by piece: GCC 12 warns falsely on "." + string
  name.append(file.stem().string()).append(".partial-").append(std::to_string(getpid()));
  name.append(file.extension().string());
  const std::filesystem::path temporary = file.parent_path() / name;
  const auto fail = [&](const std::string& why) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(file.string() + ": cannot write image: " + why);
  };
  auto output = OIIO::ImageOutput::create(temporary.string());
  if (!output) fail(OIIO::geterror());
  const OIIO::ImageSpec spec(int(width), int(height), channels, OIIO::TypeDesc::UINT8);
  if (!output->open(temporary.string(), spec) || !output->write_image(OIIO::TypeDesc::UINT8, pixels.data()) ||
      !output->close())
    fail(output->geterror());
  std::error_code error;
  std::filesystem::rename(temporary, file, error);
  if (error) fail(error.message());
}

}  // namespace pbs::cli
