// Private to the glTF importer: decodes a glTF image (PNG, JPEG, … through tinygltf's stb_image) to RGBA8.
#pragma once

#include "gltf_document.hpp"
#include "pbs/scene/scene.hpp"

#include <tiny_gltf.h>

#include <string_view>

namespace pbs::gltf {

// Fills `texture`'s width, height and rgba8 from image `image` of a model from parseDocument (which
// left images encoded). Throws InputError naming the image when it is missing or cannot be decoded.
void decodeImage(const Document& model, int image, std::string_view file, Texture& texture);

}  // namespace pbs::gltf
