// The embedded default scene: an industrial plant laid out as plant → area → unit → assembly →
// part, every part an instance of one of the catalogue's meshes (plant_catalog.cpp).
#include "pbs/scene/generate.hpp"

#include "plant_catalog.hpp"
#include "pbs/raster/seeded_random.hpp"
#include "transform_shorthand.hpp"

#include <cmath>
#include <string>
#include <utility>

namespace pbs {
namespace {

using glm::dmat4;
using glm::dvec3;

constexpr double kQuarterTurn = glm::half_pi<double>();

// What every layout function needs: the scene being built, the meshes to place, and the one
// generator all variation comes from, so the plant is the same on every run.
struct Plant {
  Scene& scene;
  const PlantCatalog& parts;
  SeededRandom random;
};

std::uint32_t addNode(Plant& plant, std::int64_t parent, std::string name, const dmat4& local, std::int32_t mesh = -1) {
  Scene& scene = plant.scene;
  const auto index = std::uint32_t(scene.nodes.size());
  scene.nodes.push_back({std::move(name), local, {}, mesh});
  if (parent < 0)
    scene.roots.push_back(index);
  else
    scene.nodes[std::size_t(parent)].children.push_back(index);
  return index;
}

std::string numbered(const char* name, std::size_t number) { return std::string(name) + " " + std::to_string(number); }

// A straight pipe from `from` along +X for `length` metres, with a flange where it starts.
void addPipeRun(Plant& plant, std::uint32_t parent, std::string name, dvec3 from, double length, std::int32_t pipe) {
  const std::uint32_t run = addNode(plant, parent, std::move(name), at(from.x, from.y, from.z));
  addNode(plant, run, "pipe", alongX() * scaled(1.0, length, 1.0), pipe);
  addNode(plant, run, "flange", alongX(), plant.parts.flange);
}

void addTankUnit(Plant& plant, std::uint32_t parent, std::string name, const dmat4& local) {
  const PlantCatalog& p = plant.parts;
  const std::uint32_t unit = addNode(plant, parent, std::move(name), local);
  addNode(plant, unit, "pad", dmat4(1.0), p.tankPad);
  addNode(plant, unit, "plinth", at(0, 0.6, 0), p.tankPlinth);
  // The dished bottom sinks into the plinth, as a flat tank floor would sit on it.
  const std::uint32_t tank = addNode(plant, unit, "tank", at(0, 0.8, 0));
  addNode(plant, tank, "shell", dmat4(1.0), p.storageTank);
  const std::uint32_t rings = addNode(plant, tank, "stiffener rings", dmat4(1.0));
  for (int k = 0; k < 4; ++k) addNode(plant, rings, numbered("ring", k), at(0, 3.7 + 3.0 * k, 0), p.tankRing);
  const std::uint32_t stair = addNode(plant, tank, "stair", at(12.6, -0.2, 0));
  addNode(plant, stair, "tower", dmat4(1.0), p.stairTower);

  const std::uint32_t outlet = addNode(plant, unit, "outlet", at(0, 3.0, 10.9));
  addNode(plant, outlet, "riser", dmat4(1.0), p.riser);
  const std::uint32_t station = addNode(plant, outlet, "valve station", at(0, 0, 2.0));
  addNode(plant, station, "valve", at(0, 0.45, 0), p.valve);
  addNode(plant, station, "flange", at(0, 0.8, -0.6) * alongZ(), p.flange);
  addNode(plant, station, "flange", at(0, 0.8, 0.6) * alongZ(), p.flange);
}

void addTankFarm(Plant& plant, std::uint32_t parent) {
  const std::uint32_t area = addNode(plant, parent, "tank farm", at(-230, 0, 0));
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 6; ++col)
      addTankUnit(plant, area, "tank unit " + std::to_string(row) + "." + std::to_string(col),
                  at((col - 2.5) * 32.0, 0, (row - 1.5) * 36.0) * turnY(kQuarterTurn * plant.random.below(4)));
}

void addSphereYard(Plant& plant, std::uint32_t parent) {
  const PlantCatalog& p = plant.parts;
  const std::uint32_t area = addNode(plant, parent, "sphere yard", at(-230, 0, 100));
  for (int row = 0; row < 2; ++row) {
    for (int col = 0; col < 5; ++col) {
      const std::uint32_t unit = addNode(plant, area, numbered("sphere unit", std::size_t(row * 5 + col)),
                                         at((col - 2) * 22.0, 0, (row - 0.5) * 24.0));
      const std::uint32_t vessel = addNode(plant, unit, "vessel", dmat4(1.0));
      addNode(plant, vessel, "sphere", at(0, 6, 0), p.sphere);
      // The girder ring is the tank ring made smaller: instancing with a scale, not a new mesh.
      addNode(plant, vessel, "girder", at(0, 14, 0) * scaled(0.72, 0.72, 0.72), p.tankRing);
      const std::uint32_t legs = addNode(plant, vessel, "legs", dmat4(1.0));
      for (int leg = 0; leg < 8; ++leg) {
        const double angle = glm::two_pi<double>() * leg / 8.0;
        addNode(plant, legs, numbered("leg", std::size_t(leg)),
                at(8.0 * std::cos(angle), 0, 8.0 * std::sin(angle)) * scaled(2.5, 14.0, 2.5), p.shaft);
      }
      addNode(plant, unit, "stair", at(9.5, 0, 0), p.stairTower);
    }
  }
}

// Shafts in a zigzag, each carrying a small gear meshing with the previous shaft's large gear.
void addGearTrain(Plant& plant, std::uint32_t parent, std::string name, const dmat4& local) {
  const PlantCatalog& p = plant.parts;
  constexpr int kStages = 4;
  constexpr double kAxialStep = 0.25, kRise = 0.6;
  const double centreDistance = 0.96 + 0.315;
  const double step = std::sqrt(centreDistance * centreDistance - kRise * kRise);
  const std::uint32_t train = addNode(plant, parent, std::move(name), local);
  addNode(plant, train, "bed plate", at(step * 1.5, 0, 0.3) * scaled(step * 3 + 3.0, 0.8, 2.4), p.concreteBlock);
  addNode(plant, train, "motor", at(-1.6, 0.8, -0.4) * scaled(1.4, 1.6, 1.4), p.housing);
  for (int k = 0; k < kStages; ++k) {
    const std::uint32_t stage =
        addNode(plant, train, numbered("stage", std::size_t(k)), at(step * k, 1.9 + kRise * (k % 2), 0) * alongZ());
    addNode(plant, stage, "shaft", at(0, -0.5, 0) * scaled(1, 0.5 + kAxialStep * (kStages + 2), 1), p.shaft);
    addNode(plant, stage, "pinion", at(0, kAxialStep * k, 0) * turnY(plant.random.range(0, 1)), p.gearSmall);
    addNode(plant, stage, "wheel", at(0, kAxialStep * (k + 1), 0) * turnY(plant.random.range(0, 1)), p.gearLarge);
  }
}

void addProcessUnit(Plant& plant, std::uint32_t parent, std::string name, const dmat4& local) {
  const PlantCatalog& p = plant.parts;
  const std::uint32_t unit = addNode(plant, parent, std::move(name), local);
  addNode(plant, unit, "skid", dmat4(1.0), p.processSkid);

  const std::uint32_t columns = addNode(plant, unit, "columns", at(-14, 0.4, -9));
  for (int c = 0; c < 5; ++c) {
    const std::uint32_t column = addNode(plant, columns, numbered("column", std::size_t(c)), at(6.5 * c, 0, 0));
    addNode(plant, column, "skirt", dmat4(1.0), p.columnSkirt);
    addNode(plant, column, "vessel", at(0, 0.2, 0) * scaled(1, plant.random.range(0.8, 1.1), 1), p.column);
    for (int level = 0; level < 4; ++level)
      addNode(plant, column, numbered("platform", std::size_t(level)), at(0, 5.0 + 5.0 * level, 0), p.platformRing);
  }

  const std::uint32_t hall = addNode(plant, unit, "machines", at(-16, 0.4, 2));
  for (int t = 0; t < 4; ++t) addGearTrain(plant, hall, numbered("gear train", std::size_t(t)), at(10.0 * t, 0, 0));

  const std::uint32_t pumps = addNode(plant, unit, "pumps", at(-17, 0.4, 12));
  for (int k = 0; k < 8; ++k) {
    const std::uint32_t set = addNode(plant, pumps, numbered("pump set", std::size_t(k)), at(4.5 * k, 0, 0));
    addNode(plant, set, "pump", dmat4(1.0), p.pump);
    addNode(plant, set, "valve", at(0.6, 1.8, 0), p.valve);
    addNode(plant, set, "flange", at(0.6, 1.8, 0), p.flange);
    addNode(plant, set, "riser", at(0.6, 3.2, 0) * scaled(0.5, 2.3, 0.5), p.pipeBlue);
  }
  const std::uint32_t header = addNode(plant, unit, "header", dmat4(1.0));
  addPipeRun(plant, header, "discharge header", dvec3(-17.0, 5.8, 12.0), 33.0, p.pipeBlue);
  addNode(plant, header, "bend", at(16.0, 4.6, 12.0) * turnY(kQuarterTurn), p.elbow);
}

void addProcessArea(Plant& plant, std::uint32_t parent) {
  const std::uint32_t area = addNode(plant, parent, "process", at(-20, 0, -70));
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col)
      addProcessUnit(plant, area, "process unit " + std::to_string(row) + "." + std::to_string(col),
                     at((col - 1.5) * 52.0, 0, (row - 1) * 42.0));
}

void addPowerBlock(Plant& plant, std::uint32_t parent) {
  const PlantCatalog& p = plant.parts;
  const std::uint32_t area = addNode(plant, parent, "power block", at(190, 0, -40));
  const std::uint32_t cooling = addNode(plant, area, "cooling", at(0, 0, -130));
  for (int k = 0; k < 4; ++k)
    addNode(plant, cooling, numbered("cooling tower", std::size_t(k)), at(85.0 * k - 85.0, 0, 0), p.coolingTower);
  const std::uint32_t stacks = addNode(plant, area, "stacks", dmat4(1.0));
  for (int k = 0; k < 2; ++k)
    addNode(plant, stacks, numbered("stack", std::size_t(k)), at(k == 0 ? -60.0 : 60.0, 0, 60), p.stack);

  const std::uint32_t hall = addNode(plant, area, "turbine hall", at(-45, 0, 10));
  for (int k = 0; k < 6; ++k) {
    const std::uint32_t set = addNode(plant, hall, numbered("turbine set", std::size_t(k)), at(0, 0, 14.0 * k));
    addNode(plant, set, "foundation", at(6, 0, 0) * scaled(34, 1.5, 8), p.concreteBlock);
    const std::uint32_t turbine = addNode(plant, set, "turbine", at(-6, 4.0, 0));
    addNode(plant, turbine, "casing", alongX(), p.turbine);
    addNode(plant, turbine, "inlet", at(4, 2.0, 0) * scaled(1.5, 4.0, 1.5), p.pipeGrey);
    addGearTrain(plant, set, "gearbox", at(9, 1.5, -0.4) * scaled(1.5, 1.5, 1.5));
    addNode(plant, set, "generator", at(19, 1.5, -2.2) * scaled(7, 4.4, 4.4), p.housing);
  }
}

// A pipe rack: trestles with a truss every 8 m, three pipes on top and three below, expansion
// loops on the outer top lanes every sixth module.
void addRack(Plant& plant, std::uint32_t parent, std::string name, const dmat4& local, int modules) {
  const PlantCatalog& p = plant.parts;
  const std::uint32_t rack = addNode(plant, parent, std::move(name), local);
  constexpr double kLength = 8.0;
  for (int m = 0; m < modules; ++m) {
    const std::uint32_t module = addNode(plant, rack, numbered("module", std::size_t(m)), at(kLength * m, 0, 0));
    const std::uint32_t trestle = addNode(plant, module, "trestle", dmat4(1.0));
    for (double side : {-1.25, 1.25}) addNode(plant, trestle, "leg", at(0, 0, side) * scaled(2.5, 6.0, 2.5), p.shaft);
    addNode(plant, trestle, "truss", at(0, 7.25, 0) * alongX(), p.rackTruss);
    const bool loops = m % 6 == 3;
    for (int lane = 0; lane < 6; ++lane) {
      const bool top = lane < 3;
      const dvec3 from(0.0, top ? 8.85 : 6.4, 0.85 * (lane % 3 - 1));
      const std::int32_t pipe = lane % 2 == 0 ? p.pipeGrey : p.pipeBlue;
      if (loops && top && lane != 1) {
        const std::uint32_t run =
            addNode(plant, module, numbered("lane", std::size_t(lane)), at(from.x, from.y, from.z));
        addNode(plant, run, "loop", dmat4(1.0), p.expansionLoop);
        addNode(plant, run, "flange", alongX(), p.flange);
      } else {
        addPipeRun(plant, module, numbered("lane", std::size_t(lane)), from, kLength, pipe);
      }
    }
  }
}

void addPipeRacks(Plant& plant, std::uint32_t parent) {
  const std::uint32_t area = addNode(plant, parent, "pipe racks", dmat4(1.0));
  addRack(plant, area, "main rack", at(-125, 0, 55), 50);
  addRack(plant, area, "tank farm rack", at(-128, 0, -140) * turnY(-kQuarterTurn), 24);
  addRack(plant, area, "process rack", at(-125, 0, -5), 32);
  addRack(plant, area, "power rack", at(100, 0, -120) * turnY(-kQuarterTurn), 22);
}

void addTransmissionLine(Plant& plant, std::uint32_t parent) {
  const std::uint32_t area = addNode(plant, parent, "transmission line", at(310, 0, 100));
  for (int k = 0; k < 10; ++k) {
    // Separate statements: the order of two draws within one expression is unspecified.
    const double sway = plant.random.range(-3, 3);
    const double yaw = plant.random.range(-0.05, 0.05);
    addNode(plant, area, numbered("pylon", std::size_t(k)), at(35.0 * k, 0, sway) * turnY(kQuarterTurn + yaw),
            plant.parts.pylon);
  }
}

}  // namespace

Scene generateDefaultScene() {
  Scene scene;
  const PlantCatalog parts = addPlantCatalog(scene);
  Plant plant{scene, parts, SeededRandom(0x5EED)};
  const std::uint32_t root = addNode(plant, -1, "power plant", dmat4(1.0));
  addTankFarm(plant, root);
  addSphereYard(plant, root);
  addProcessArea(plant, root);
  addPowerBlock(plant, root);
  addPipeRacks(plant, root);
  addTransmissionLine(plant, root);
  dropUnreadUvs(scene);
  return scene;
}

}  // namespace pbs
