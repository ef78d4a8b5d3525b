// Private to the glTF importer: the materials and textures that imported primitives use, each
// imported once on first use and renumbered in that order.
#pragma once

#include "gltf_document.hpp"
#include "pbs/scene/scene.hpp"

#include <tiny_gltf.h>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace pbs::gltf {

class MaterialImport {
 public:
  MaterialImport(const Document& model, std::string_view file, Scene& scene);

  // The scene material for glTF material `material`, -1 meaning the shared default white one.
  // `referrer` names the primitive, for a material that does not exist.
  std::uint32_t use(int material, std::string_view referrer);

  // use() as it stands now, for materials already used: what reading a mesh later needs, without this
  // object or the scene it imports into. A material not used yet is a std::logic_error.
  std::function<std::uint32_t(int material, std::string_view referrer)> used() const;

  // One line for all materials whose base colour reads a texCoord other than 0, if any.
  void appendWarnings(std::vector<std::string>& warnings) const;

 private:
  std::uint32_t importMaterial(int material);
  std::int32_t useTexture(int texture, int material);
  Texture importTexture(int texture);

  const Document& model_;
  std::string_view file_;
  Scene& scene_;
  std::vector<std::int64_t> materialIndex_;  // glTF material to scene material, -1 until used
  std::vector<std::int32_t> textureIndex_;   // glTF texture to scene texture, -1 until used
  std::int64_t defaultMaterial_ = -1;
  std::uint32_t otherTexCoordMaterials_ = 0;
};

}  // namespace pbs::gltf
