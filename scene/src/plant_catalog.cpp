// The default plant's textures, materials and unique meshes.
#include "plant_catalog.hpp"

#include "mesh_merge.hpp"
#include "procedural_parts.hpp"
#include "procedural_textures.hpp"
#include "transform_shorthand.hpp"

#include <cmath>
#include <utility>
#include <vector>

namespace pbs {
namespace {

struct PlantMaterials {
  std::uint32_t storagePaint, vesselPaint, checkerPlate, hazardStripes, concrete;  // textured
  std::uint32_t galvanised, safetyYellow, pipeGrey, pipeBlue, flangeDark, valveRed, machineGreen, gearSteel;
};

// Trilinear, as a glTF texture without a sampler is read.
std::uint32_t addTexture(Scene& scene, Texture texture) {
  texture.mipmap = TextureMipmap::Linear;
  buildMipLevels(texture);
  scene.textures.push_back(std::move(texture));
  return std::uint32_t(scene.textures.size() - 1);
}

std::uint32_t addMaterial(Scene& scene, const char* name, glm::vec3 linearColour, std::int32_t texture = -1) {
  scene.materials.push_back({name, glm::vec4(linearColour, 1.0f), texture});
  return std::uint32_t(scene.materials.size() - 1);
}

PlantMaterials addMaterials(Scene& scene) {
  const auto textured = [&](const char* name, Texture texture) {
    return addMaterial(scene, name, glm::vec3(1.0f), std::int32_t(addTexture(scene, std::move(texture))));
  };
  PlantMaterials m{};
  m.storagePaint = textured("storage paint",
                            makePaintedSteelTexture("storage paint", {0.9f, 0.9f, 0.86f}, {0.75f, 0.1f, 0.08f}, 11));
  m.vesselPaint =
      textured("vessel paint", makePaintedSteelTexture("vessel paint", {0.78f, 0.8f, 0.82f}, {0.1f, 0.3f, 0.65f}, 23));
  m.checkerPlate = textured("checker plate", makeCheckerPlateTexture("checker plate", 37));
  m.hazardStripes = textured("hazard stripes", makeHazardStripeTexture("hazard stripes", 41));
  m.concrete = textured("concrete", makeConcreteTexture("concrete", 53));
  m.galvanised = addMaterial(scene, "galvanised steel", {0.45f, 0.47f, 0.48f});
  m.safetyYellow = addMaterial(scene, "safety yellow", {0.8f, 0.55f, 0.02f});
  m.pipeGrey = addMaterial(scene, "pipe grey", {0.3f, 0.31f, 0.32f});
  m.pipeBlue = addMaterial(scene, "pipe blue", {0.05f, 0.15f, 0.45f});
  m.flangeDark = addMaterial(scene, "flange dark", {0.08f, 0.08f, 0.09f});
  m.valveRed = addMaterial(scene, "valve red", {0.7f, 0.04f, 0.03f});
  m.machineGreen = addMaterial(scene, "machine green", {0.12f, 0.3f, 0.15f});
  m.gearSteel = addMaterial(scene, "gear steel", {0.6f, 0.6f, 0.62f});
  return m;
}

std::int32_t addMesh(Scene& scene, Mesh mesh, const char* name, std::uint32_t material) {
  mesh.name = name;
  for (MeshPart& part : mesh.parts) part.material = material;
  scene.meshes.push_back(std::move(mesh));
  return std::int32_t(scene.meshes.size() - 1);
}

struct AssemblyPart {
  Mesh mesh;  // a finished single-part mesh
  glm::dmat4 place;
  std::uint32_t material;
};

// One mesh made of several parts, each placed and given its own material.
std::int32_t addAssembly(Scene& scene, const char* name, const std::vector<AssemblyPart>& parts) {
  std::vector<MeshPiece> pieces;
  for (const AssemblyPart& part : parts) pieces.push_back({&part.mesh, part.place, part.material});
  scene.meshes.push_back(mergeMeshes(pieces, name));
  return std::int32_t(scene.meshes.size() - 1);
}

std::int32_t addCoolingTower(Scene& scene, std::uint32_t material) {
  // A hyperboloid of one sheet: throat radius 24 m at 80 m, 38 m at the base, 110 m tall.
  constexpr double throat = 24.0, throatHeight = 80.0, height = 110.0;
  const double c = throatHeight / std::sqrt((38.0 / throat) * (38.0 / throat) - 1.0);
  std::vector<glm::vec2> outline;
  for (int i = 0; i <= 60; ++i) {
    const double y = height * i / 60.0;
    outline.emplace_back(float(throat * std::sqrt(1.0 + ((y - throatHeight) / c) * ((y - throatHeight) / c))),
                         float(y));
  }
  return addMesh(scene, makeRevolvedWall(outline, 0.6f, 384), "cooling tower", material);
}

std::int32_t addPylon(Scene& scene, std::uint32_t material) {
  std::vector<AssemblyPart> parts = {{makeLattice({8.0f, 1.5f, 45.0f, 18, 0.25f}), glm::dmat4(1.0), material}};
  const Mesh arm = makeLattice({1.6f, 0.4f, 11.0f, 6, 0.15f});
  for (double height : {34.0, 41.0})
    for (double side : {-1.0, 1.0})
      parts.push_back({arm, at(0.0, height, 0.0) * turnZ(-side * glm::half_pi<double>()), material});
  return addAssembly(scene, "pylon", parts);
}

}  // namespace

PlantCatalog addPlantCatalog(Scene& scene) {
  const PlantMaterials m = addMaterials(scene);
  PlantCatalog c{};
  c.storageTank = addMesh(scene, makeTank(11.0f, 12.0f, 0.2f, 384), "storage tank", m.storagePaint);
  c.sphere = addMesh(scene, makeTank(8.0f, 0.0f, 1.0f, 256), "sphere", m.vesselPaint);
  c.column = addMesh(scene, makeTank(1.6f, 22.0f, 1.0f, 128), "column", m.vesselPaint);
  c.columnSkirt = addMesh(scene, makeCylinder(1.45f, 1.6f, 96), "column skirt", m.concrete);
  c.tankRing = addMesh(scene, makeTorus(11.15f, 0.18f, 768, 16), "tank ring", m.galvanised);
  c.platformRing = addMesh(scene, makeTorus(2.2f, 0.1f, 192, 16), "platform ring", m.safetyYellow);
  c.flange = addMesh(scene, makeTorus(0.34f, 0.07f, 96, 24), "flange", m.flangeDark);
  c.pipeGrey = addMesh(scene, makeCylinder(0.3f, 1.0f, 64), "pipe grey", m.pipeGrey);
  c.pipeBlue = addMesh(scene, makeCylinder(0.3f, 1.0f, 64), "pipe blue", m.pipeBlue);
  const glm::vec3 elbow[] = {{0, 0, 0}, {0, 1.2f, 0}, {1.2f, 1.2f, 0}};
  c.elbow = addMesh(scene, makePipe(elbow, 0.3f, 0.9f, 64), "elbow", m.pipeGrey);
  const glm::vec3 loop[] = {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {6, 3, 0}, {6, 0, 0}, {8, 0, 0}};
  c.expansionLoop = addMesh(scene, makePipe(loop, 0.3f, 0.9f, 64), "expansion loop", m.pipeGrey);
  const glm::vec3 riser[] = {{0, 0.8f, 0}, {0, 0.8f, 4}, {0, 9, 4}, {0, 9, 7}};
  c.riser = addMesh(scene, makePipe(riser, 0.3f, 1.0f, 64), "riser", m.pipeBlue);
  c.gearLarge = addMesh(scene, makeGear({48, 0.92f, 1.0f, 0.12f, 0.18f}, 14), "large gear", m.gearSteel);
  c.gearSmall = addMesh(scene, makeGear({16, 0.29f, 0.34f, 0.08f, 0.2f}, 10), "small gear", m.gearSteel);
  c.shaft = addMesh(scene, makeCylinder(0.08f, 1.0f, 32), "shaft", m.gearSteel);
  c.concreteBlock = addMesh(scene, makeBox({1, 1, 1}), "concrete block", m.concrete);
  c.tankPad = addMesh(scene, makeBox({30, 0.6f, 30}), "tank pad", m.concrete);
  c.tankPlinth = addMesh(scene, makeCylinder(11.3f, 2.4f, 192), "tank plinth", m.concrete);
  c.processSkid = addMesh(scene, makeBox({44, 0.4f, 34}), "process skid", m.checkerPlate);
  c.housing = addMesh(scene, makeBox({1, 1, 1}), "housing", m.machineGreen);
  c.stairTower = addMesh(scene, makeLattice({3.0f, 3.0f, 14.0f, 7, 0.12f}), "stair tower", m.safetyYellow);
  c.rackTruss = addMesh(scene, makeLattice({2.5f, 2.5f, 8.0f, 4, 0.14f}), "rack truss", m.galvanised);
  c.pylon = addPylon(scene, m.galvanised);
  c.valve = addAssembly(scene, "valve",
                        {{makeCylinder(0.35f, 0.8f, 48), glm::dmat4(1.0), m.flangeDark},
                         {makeCylinder(0.04f, 0.6f, 12), at(0, 0.8, 0), m.gearSteel},
                         {makeTorus(0.3f, 0.035f, 64, 16), at(0, 1.4, 0), m.valveRed}});
  c.pump = addAssembly(scene, "pump",
                       {{makeBox({1.8f, 0.3f, 0.9f}), glm::dmat4(1.0), m.hazardStripes},
                        {makeCylinder(0.35f, 1.1f, 64), at(-0.85, 0.7, 0) * alongX(), m.machineGreen},
                        {makeTorus(0.3f, 0.17f, 64, 24), at(0.6, 0.7, 0) * alongX(), m.pipeBlue},
                        {makeCylinder(0.12f, 0.8f, 24), at(0.6, 1.0, 0), m.pipeBlue}});
  c.coolingTower = addCoolingTower(scene, m.concrete);
  const glm::vec2 stack[] = {{4.0f, 0.0f}, {3.2f, 40.0f}, {2.6f, 80.0f}};
  c.stack = addMesh(scene, makeRevolvedWall(stack, 0.4f, 96), "stack", m.concrete);
  c.turbine = addMesh(scene, makeTank(2.5f, 9.0f, 0.6f, 192), "turbine", m.machineGreen);
  return c;
}

}  // namespace pbs
