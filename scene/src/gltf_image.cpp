// Decodes the images that used textures need: finds their encoded bytes (a checked bufferView, or
// the uri's, read only now), decodes them with tinygltf's stb_image and converts to RGBA8.
#include "gltf_image.hpp"

#include "gltf_accessor.hpp"
#include "gltf_messages.hpp"
#include "pbs/scene/input_error.hpp"

#include <climits>
#include <cstring>
#include <stdexcept>

namespace pbs::gltf {
namespace {

constexpr std::size_t kMaxMessageLength = 300;

// stb's messages may span lines; InputError's are one short line.
std::string oneLine(std::string_view text) {
  std::string line;
  for (const char c : text) {
    if (c == '\n' || c == '\r') {
      if (!line.empty() && !line.ends_with("; ")) line += "; ";
    } else {
      line += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    }
  }
  while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
  if (line.size() > kMaxMessageLength) line = line.substr(0, kMaxMessageLength) + "...";
  return line;
}

// The image's encoded bytes: its bufferView's, or those its uri names, read (into `read`) now that a
// texture uses it.
std::span<const std::uint8_t> encodedBytes(const Document& model, int image, std::string_view file,
                                           const std::string& element, UriBytes& read) {
  const tinygltf::Image& source = model.images[static_cast<std::size_t>(image)];
  if (source.bufferView != -1) return bufferViewBytes(model, source.bufferView, file, element);
  if (source.uri.empty()) throw InputError(file, element, "has neither a uri nor a bufferView");
  try {
    read = readUri(source.uri, model.baseDir);
  } catch (const std::runtime_error& error) {
    throw InputError(file, element, error.what());
  }
  return read.bytes();
}

// tinygltf's decoder asks stb for RGBA today, but its Image contract is 1 to 4 channels (grey,
// grey+alpha, RGB, RGBA) of 8 or 16 bits; the scene keeps RGBA8.
void convertToRgba8(const tinygltf::Image& decoded, std::string_view file, const std::string& element,
                    Texture& texture) {
  const int channels = decoded.component;
  const std::size_t pixels = static_cast<std::size_t>(decoded.width) * static_cast<std::size_t>(decoded.height);
  const std::size_t channelBytes = static_cast<std::size_t>(decoded.bits / 8);
  if (channels < 1 || channels > 4 || (decoded.bits != 8 && decoded.bits != 16) ||
      decoded.image.size() != pixels * static_cast<std::size_t>(channels) * channelBytes) {
    throw InputError(file, element,
                     "decoded to an unsupported layout (" + std::to_string(channels) + " channels of " +
                         std::to_string(decoded.bits) + " bits)");
  }
  const std::uint8_t* src = decoded.image.data();
  const auto channel = [&](std::size_t index) -> std::uint8_t {
    if (channelBytes == 1) return src[index];
    std::uint16_t value;
    std::memcpy(&value, src + 2 * index, 2);
    return static_cast<std::uint8_t>((value * 255u + 32767u) / 65535u);
  };
  texture.width = static_cast<std::uint32_t>(decoded.width);
  texture.height = static_cast<std::uint32_t>(decoded.height);
  texture.rgba8.resize(pixels * 4);
  for (std::size_t p = 0; p < pixels; ++p) {
    const std::size_t first = p * static_cast<std::size_t>(channels);
    std::uint8_t* out = texture.rgba8.data() + 4 * p;
    if (channels <= 2) {
      out[0] = out[1] = out[2] = channel(first);
      out[3] = channels == 2 ? channel(first + 1) : 255;
    } else {
      out[0] = channel(first);
      out[1] = channel(first + 1);
      out[2] = channel(first + 2);
      out[3] = channels == 4 ? channel(first + 3) : 255;
    }
  }
}

}  // namespace

void decodeImage(const Document& model, int image, std::string_view file, Texture& texture) {
  const std::string element = elementName("image", image);
  UriBytes read;
  const std::span<const std::uint8_t> encoded = encodedBytes(model, image, file, element, read);
  if (encoded.size() > static_cast<std::size_t>(INT_MAX)) throw InputError(file, element, "is larger than 2 GiB");
  tinygltf::Image decoded;
  std::string error, warning;
  if (!tinygltf::LoadImageData(&decoded, image, &error, &warning, 0, 0, encoded.data(),
                               static_cast<int>(encoded.size()), nullptr)) {
    throw InputError(file, element, "cannot decode: " + oneLine(error));
  }
  convertToRgba8(decoded, file, element, texture);
}

}  // namespace pbs::gltf
