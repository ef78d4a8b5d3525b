// Private to the glTF importer: file bytes to a tinygltf::Model, or an InputError naming the element.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pbs::gltf {

// Parses .gltf JSON or .glb (told apart by the "glTF" magic, not the name) with tinygltf, loading
// buffers from external files and data: URIs relative to `baseDir`. Images are left encoded: each
// keeps its file bytes in Image::image (as_is set) or its bufferView, so that only images a used
// texture needs are decoded, with our bounds checks (gltf_image.cpp). Rejects required extensions
// the importer cannot honour. Appends tinygltf's warnings, one line each.
tinygltf::Model parseDocument(std::span<const std::uint8_t> bytes, const std::string& file,
                              const std::filesystem::path& baseDir, std::vector<std::string>& warnings);

}  // namespace pbs::gltf
