// A city of instances for scaling tests: each prototype flattened into one unit-size mesh, then
// placed over a grid hierarchy of blocks with seeded turns, non-uniform and mirroring scales; or, with
// nothing shared, every placement baked into a mesh of its own.
#include "pbs/scene/generate.hpp"

#include "mesh_merge.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/input_error.hpp"
#include "pbs/raster/seeded_random.hpp"
#include "transform_shorthand.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

namespace pbs {
namespace {

constexpr double kLeafSpacing = 2.5;    // a unit prototype scaled up to 1.5 and turned still fits
constexpr double kStreetFactor = 1.15;  // room between neighbouring blocks
constexpr double kBlockTurn = 0.12;     // radians, either way

// Flattens `prototype` into one mesh (returned), with its materials and textures appended to the
// city's: centred over the origin, standing on y = 0, its largest extent 1.
Mesh flattenPrototype(Scene& city, const Scene& prototype, std::size_t index) {
  const std::string source = "city prototype " + std::to_string(index);
  validateScene(prototype, source);
  const Hierarchy hierarchy = analyzeHierarchy(prototype);
  Bounds bounds;
  for (std::uint32_t root : prototype.roots) bounds.extend(hierarchy.worldBounds[root]);
  if (bounds.empty()) throw InputError(source, "", "has no geometry to instance");
  const glm::dvec3 size = bounds.size();
  const double extent = std::max({size.x, size.y, size.z});
  const double scale = extent > 0.0 ? 1.0 / extent : 1.0;  // a prototype collapsed to a point stays one
  const glm::dmat4 normalise = scaled(scale, scale, scale) * at(-bounds.center().x, -bounds.min.y, -bounds.center().z);

  const auto materialOffset = std::uint32_t(city.materials.size());
  const auto textureOffset = std::int32_t(city.textures.size());
  city.textures.insert(city.textures.end(), prototype.textures.begin(), prototype.textures.end());
  for (Material material : prototype.materials) {
    if (material.baseColorTexture >= 0) material.baseColorTexture += textureOffset;
    city.materials.push_back(std::move(material));
  }

  std::vector<MeshPiece> pieces;
  for (std::uint32_t n : hierarchy.preorder) {
    const Node& node = prototype.nodes[n];
    if (node.mesh >= 0)
      pieces.push_back({&prototype.meshes[std::size_t(node.mesh)], normalise * hierarchy.world[n], materialOffset});
  }
  const std::string name = prototype.roots.size() == 1 && !prototype.nodes[prototype.roots[0]].name.empty()
                               ? prototype.nodes[prototype.roots[0]].name
                               : "prototype " + std::to_string(index);
  Mesh mesh = mergeMeshes(pieces, name);
  if (mesh.triangleCount() == 0) throw InputError(source, "", "has no triangles to instance");
  return mesh;
}

std::uint64_t countNodes(const CityOptions& options);

// Every prototype flattened into one mesh (its materials and textures appended to the city's), after
// checking the options.
std::vector<Mesh> flattenPrototypes(Scene& city, const std::vector<Scene>& prototypes, const CityOptions& options) {
  if (prototypes.empty()) throw std::invalid_argument("generateCity: no prototypes");
  if (options.fanout == 0) throw std::invalid_argument("generateCity: fanout must be at least 1");
  countNodes(options);  // throws before any work when the nodes would not fit 32-bit indices
  std::vector<Mesh> flattened;
  for (std::size_t p = 0; p < prototypes.size(); ++p) flattened.push_back(flattenPrototype(city, prototypes[p], p));
  return flattened;
}

// 1 + fanout + … + fanout^levels, or throws when the nodes would not fit 32-bit indices.
std::uint64_t countNodes(const CityOptions& options) {
  constexpr std::uint64_t kLimit = std::numeric_limits<std::int32_t>::max();
  std::uint64_t total = 1, level = 1;
  for (std::uint32_t l = 0; l < options.levels; ++l) {
    level *= options.fanout;
    total += level;
    if (level > kLimit || total > kLimit)
      throw std::invalid_argument("generateCity: fanout^levels is too many nodes for 32-bit indices");
  }
  return total;
}

// Where child `i` of a block sits on its grid, `spacing` apart, the grid centred on the block.
glm::dmat4 gridPlace(std::uint32_t i, std::uint32_t columns, std::uint32_t rows, double spacing) {
  const double x = (double(i % columns) - 0.5 * (columns - 1)) * spacing;
  const double z = (double(i / columns) - 0.5 * (rows - 1)) * spacing;
  return at(x, 0.0, z);
}

// A turned, stretched and one time in four mirrored placement of a random prototype.
Node makeInstance(SeededRandom& random, std::uint32_t prototypes, const glm::dmat4& place, std::string name) {
  // One draw per statement: the order of draws within an expression is unspecified.
  const auto mesh = std::int32_t(random.below(prototypes));
  const double yaw = random.range(0.0, glm::two_pi<double>());
  glm::dvec3 scale;
  for (int axis = 0; axis < 3; ++axis) scale[axis] = random.range(0.6, 1.5);
  if (random.chance(0.25)) scale.x = -scale.x;
  return Node{std::move(name), place * turnY(yaw) * scaled(scale.x, scale.y, scale.z), {}, mesh};
}

// What the unique city's meshes are baked from: the flattened prototypes and, per mesh (leaf i, in node
// order, gets mesh i), its prototype, the placement baked into it and its name.
struct LeafBakes {
  struct Leaf {
    std::uint32_t prototype;
    glm::dmat4 local;
    std::string name;
  };
  std::vector<Mesh> prototypes;
  std::vector<Leaf> leaves;

  Mesh bake(std::uint32_t mesh) const {
    const Leaf& leaf = leaves.at(mesh);
    const MeshPiece piece{&prototypes[leaf.prototype], leaf.local, 0};
    return mergeMeshes(std::span(&piece, 1), leaf.name);
  }
};

// The instanced city made unique without baking: leaf i gets mesh i, described by its name and parts
// (those of its prototype: baking one piece keeps a merged mesh's parts), and the identity transform.
// Returns what LeafBakes::bake turns into each mesh.
std::shared_ptr<const LeafBakes> describeLeaves(Scene& city, std::vector<Mesh> prototypes) {
  auto bakes = std::make_shared<LeafBakes>();
  for (std::uint32_t n = 0; n < city.nodes.size(); ++n) {
    Node& node = city.nodes[n];
    if (node.mesh < 0) continue;
    const Mesh& prototype = prototypes[std::size_t(node.mesh)];
    Mesh& described = city.meshes.emplace_back();
    described.name = prototype.name + ", " + node.name;
    described.parts = prototype.parts;
    described.describedVertices = prototype.positions.size();
    bakes->leaves.push_back({std::uint32_t(node.mesh), node.local, described.name});
    node.mesh = std::int32_t(city.meshes.size() - 1);
    node.local = glm::dmat4(1.0);
  }
  bakes->prototypes = std::move(prototypes);
  return bakes;
}

// The city's nodes: a root block, `levels` levels of `fanout` children each on a grid, instances of
// random prototypes (mesh indices below `prototypes`) at the leaves. Level by level, so the draws (and
// so the city) depend only on the seed and the options.
std::vector<Node> placeNodes(std::uint32_t prototypes, const CityOptions& options) {
  std::uint32_t columns = 1;
  while (columns * columns < options.fanout) ++columns;
  const std::uint32_t rows = (options.fanout + columns - 1) / columns;
  // spacing[d]: how far apart the children of a node at depth d sit, grown from the leaves up.
  std::vector<double> spacing(options.levels, kLeafSpacing);
  for (std::uint32_t d = options.levels; d-- > 1;) spacing[d - 1] = spacing[d] * columns * kStreetFactor;

  SeededRandom random(options.seed);
  std::vector<Node> nodes;
  nodes.reserve(countNodes(options));
  if (options.levels == 0) {
    nodes.push_back(makeInstance(random, prototypes, glm::dmat4(1.0), "instance 0"));
    return nodes;
  }
  nodes.push_back(Node{"city", glm::dmat4(1.0), {}, -1});
  std::vector<std::uint32_t> level = {0}, next;
  for (std::uint32_t depth = 1; depth <= options.levels; ++depth) {
    next.clear();
    for (std::uint32_t parent : level) {
      for (std::uint32_t i = 0; i < options.fanout; ++i) {
        const auto index = std::uint32_t(nodes.size());
        const glm::dmat4 place = gridPlace(i, columns, rows, spacing[depth - 1]);
        if (depth == options.levels) {
          nodes.push_back(makeInstance(random, prototypes, place, "instance " + std::to_string(index)));
        } else {
          const double turn = random.range(-kBlockTurn, kBlockTurn);
          nodes.push_back(Node{"block " + std::to_string(index), place * turnY(turn), {}, -1});
        }
        nodes[parent].children.push_back(index);
        next.push_back(index);
      }
    }
    std::swap(level, next);
  }
  return nodes;
}

// The unique city, described, and what bakes its meshes (generateUniqueCity; generateCity bakes them all).
std::pair<Scene, std::shared_ptr<const LeafBakes>> describeUniqueCity(const std::vector<Scene>& prototypes,
                                                                      const CityOptions& options) {
  Scene city;
  std::vector<Mesh> flattened = flattenPrototypes(city, prototypes, options);
  // placeNodes draws the same either way, so the unique city is the instanced one, baked.
  city.nodes = placeNodes(std::uint32_t(flattened.size()), options);
  city.roots = {0};
  std::shared_ptr<const LeafBakes> bakes = describeLeaves(city, std::move(flattened));
  return {std::move(city), std::move(bakes)};
}

}  // namespace

Scene generateCity(const std::vector<Scene>& prototypes, const CityOptions& options) {
  if (options.unique) {
    // Baked in parallel, each mesh into its own slot: the result does not depend on threads.
    // Not a structured binding: clang 14 cannot capture one in a lambda.
    std::pair<Scene, std::shared_ptr<const LeafBakes>> described = describeUniqueCity(prototypes, options);
    Scene& city = described.first;
    const LeafBakes& bakes = *described.second;
    tbb::parallel_for(std::size_t(0), city.meshes.size(),
                      [&](std::size_t m) { city.meshes[m] = bakes.bake(std::uint32_t(m)); });
    return std::move(city);
  }
  Scene city;
  std::vector<Mesh> flattened = flattenPrototypes(city, prototypes, options);
  city.nodes = placeNodes(std::uint32_t(flattened.size()), options);
  city.roots = {0};
  city.meshes = std::move(flattened);
  return city;
}

UnbakedCity generateUniqueCity(const std::vector<Scene>& prototypes, const CityOptions& options) {
  auto [city, bakes] = describeUniqueCity(prototypes, options);
  return {std::move(city),
          [bakes = bakes](std::uint32_t mesh) { return std::make_shared<const Mesh>(bakes->bake(mesh)); }};
}

}  // namespace pbs
