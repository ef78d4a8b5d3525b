// glTF materials (base colour factor and texture) and their textures and samplers, imported on first
// use so that the scene holds only what its primitives draw with.
#include "gltf_material.hpp"

#include "gltf_image.hpp"
#include "gltf_messages.hpp"
#include "pbs/scene/input_error.hpp"

#include <cmath>
#include <stdexcept>

namespace pbs::gltf {
namespace {

TextureWrap wrapMode(int value, const char* which, std::string_view file, const std::string& sampler) {
  switch (value) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return TextureWrap::Repeat;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::MirroredRepeat;
    default: throw InputError(file, sampler, std::string(which) + " " + std::to_string(value) + " is not a wrap mode");
  }
}

// A filter mode and, for minFilter, its use of the mip chain. Absent, the spec leaves both to the
// implementation: bilinear within a level, blended between levels (trilinear), as GPU viewers do.
struct FilterMode {
  TextureFilter filter;
  TextureMipmap mipmap;
};
FilterMode filterMode(int value, const char* which, std::string_view file, const std::string& sampler) {
  switch (value) {
    case -1:
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR: return {TextureFilter::Linear, TextureMipmap::Linear};
    case TINYGLTF_TEXTURE_FILTER_LINEAR: return {TextureFilter::Linear, TextureMipmap::None};
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST: return {TextureFilter::Linear, TextureMipmap::Nearest};
    case TINYGLTF_TEXTURE_FILTER_NEAREST: return {TextureFilter::Nearest, TextureMipmap::None};
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: return {TextureFilter::Nearest, TextureMipmap::Nearest};
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: return {TextureFilter::Nearest, TextureMipmap::Linear};
    default: throw InputError(file, sampler, std::string(which) + " " + std::to_string(value) + " is not a filter");
  }
}

}  // namespace

MaterialImport::MaterialImport(const Document& model, std::string_view file, Scene& scene)
    : model_(model),
      file_(file),
      scene_(scene),
      materialIndex_(model.materials.size(), -1),
      textureIndex_(model.textures.size(), -1) {}

std::uint32_t MaterialImport::use(int material, std::string_view referrer) {
  if (material == -1) {
    if (defaultMaterial_ < 0) {
      defaultMaterial_ = std::ssize(scene_.materials);
      scene_.materials.push_back(Material{"default", glm::vec4(1.0f), -1});
    }
    return static_cast<std::uint32_t>(defaultMaterial_);
  }
  if (!validIndex(material, model_.materials.size())) {
    throw InputError(file_, referrer, missingElement("material", material, model_.materials.size()));
  }
  std::int64_t& index = materialIndex_[static_cast<std::size_t>(material)];
  if (index < 0) index = importMaterial(material);
  return static_cast<std::uint32_t>(index);
}

std::function<std::uint32_t(int, std::string_view)> MaterialImport::used() const {
  return [index = materialIndex_, defaultMaterial = defaultMaterial_](int material, std::string_view) {
    const std::int64_t chosen = material == -1                       ? defaultMaterial
                                : validIndex(material, index.size()) ? index[static_cast<std::size_t>(material)]
                                                                     : -1;
    if (chosen < 0) throw std::logic_error("glTF material " + std::to_string(material) + " was not used at import");
    return static_cast<std::uint32_t>(chosen);
  };
}

void MaterialImport::appendWarnings(std::vector<std::string>& warnings) const {
  if (otherTexCoordMaterials_ == 0) return;
  warnings.push_back(std::to_string(otherTexCoordMaterials_) +
                     (otherTexCoordMaterials_ == 1 ? " material reads its" : " materials read their") +
                     " base colour texture through a texCoord other than 0; TEXCOORD_0 is used instead");
}

std::uint32_t MaterialImport::importMaterial(int material) {
  const tinygltf::Material& source = model_.materials[static_cast<std::size_t>(material)];
  const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
  const std::string element = elementName("material", material);
  if (pbr.baseColorFactor.size() != 4) {
    throw InputError(file_, element,
                     "baseColorFactor has " + std::to_string(pbr.baseColorFactor.size()) + " numbers, not 4");
  }
  Material result;
  result.name = source.name;
  for (int c = 0; c < 4; ++c) {
    result.baseColorFactor[c] = static_cast<float>(pbr.baseColorFactor[static_cast<std::size_t>(c)]);
    if (!std::isfinite(result.baseColorFactor[c])) throw InputError(file_, element, "baseColorFactor is not finite");
  }
  if (pbr.baseColorTexture.index != -1) {
    result.baseColorTexture = useTexture(pbr.baseColorTexture.index, material);
    if (pbr.baseColorTexture.texCoord != 0) ++otherTexCoordMaterials_;
  }
  scene_.materials.push_back(std::move(result));
  return static_cast<std::uint32_t>(scene_.materials.size() - 1);
}

std::int32_t MaterialImport::useTexture(int texture, int material) {
  if (!validIndex(texture, model_.textures.size())) {
    throw InputError(file_, elementName("material", material),
                     "baseColorTexture: " + missingElement("texture", texture, model_.textures.size()));
  }
  std::int32_t& index = textureIndex_[static_cast<std::size_t>(texture)];
  if (index < 0) {
    scene_.textures.push_back(importTexture(texture));
    index = static_cast<std::int32_t>(scene_.textures.size() - 1);
  }
  return index;
}

Texture MaterialImport::importTexture(int texture) {
  const tinygltf::Texture& source = model_.textures[static_cast<std::size_t>(texture)];
  const std::string element = elementName("texture", texture);
  if (source.source == -1) throw InputError(file_, element, "has no image source (extensions are not read)");
  if (!validIndex(source.source, model_.images.size())) {
    throw InputError(file_, element, missingElement("image", source.source, model_.images.size()));
  }
  const tinygltf::Image& image = model_.images[static_cast<std::size_t>(source.source)];
  Texture result;
  result.name = !source.name.empty() ? source.name : !image.name.empty() ? image.name : image.uri;
  result.mipmap = TextureMipmap::Linear;  // an absent sampler's minFilter, as an absent minFilter (filterMode)
  if (source.sampler != -1) {             // without one: repeat, linear and trilinear
    if (!validIndex(source.sampler, model_.samplers.size())) {
      throw InputError(file_, element, missingElement("sampler", source.sampler, model_.samplers.size()));
    }
    const tinygltf::Sampler& sampler = model_.samplers[static_cast<std::size_t>(source.sampler)];
    const std::string samplerElement = elementName("sampler", source.sampler);
    result.wrapS = wrapMode(sampler.wrapS, "wrapS", file_, samplerElement);
    result.wrapT = wrapMode(sampler.wrapT, "wrapT", file_, samplerElement);
    // A mipmap part in magFilter (which the spec does not allow) is ignored: magnification uses level 0.
    result.magFilter = filterMode(sampler.magFilter, "magFilter", file_, samplerElement).filter;
    const FilterMode minify = filterMode(sampler.minFilter, "minFilter", file_, samplerElement);
    result.minFilter = minify.filter;
    result.mipmap = minify.mipmap;
  }
  decodeImage(model_, source.source, file_, result);
  buildMipLevels(result);
  return result;
}

}  // namespace pbs::gltf
