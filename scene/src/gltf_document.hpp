// Private to the glTF importer: file bytes to a Document (a tinygltf::Model and its buffers' bytes), or
// an InputError naming the element.
#pragma once

#include "gltf_uri.hpp"

#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pbs::gltf {

// A parsed glTF: what its JSON says, in tinygltf's types, and each buffer's bytes, exactly its
// byteLength. tinygltf::Buffer::data stays empty: a GLB's BIN chunk is viewed where it lies in the
// file's bytes (which must outlive the document) rather than copied, which for a 2 GB scene is 2 GB
// of memory; a uri buffer's file is mapped, a data: URI decoded, into `loadedBuffers`.
struct Document : tinygltf::Model {
  std::vector<std::span<const std::uint8_t>> bufferBytes;  // one per buffer
  std::vector<UriBytes> loadedBuffers;                     // what the uri buffers' spans view
  std::filesystem::path baseDir;                           // where relative uris (of images) are read from
};

// Parses .gltf JSON or .glb (told apart by the "glTF" magic, not the name), loading buffers from
// external files and data: URIs relative to `baseDir`. Images are not read here: gltf_image.cpp reads
// and decodes, with our bounds checks, only those a used texture needs. Rejects required extensions the
// importer cannot honour. Appends warnings, one line each.
Document parseDocument(std::span<const std::uint8_t> bytes, const std::string& file,
                       const std::filesystem::path& baseDir, std::vector<std::string>& warnings);

}  // namespace pbs::gltf
