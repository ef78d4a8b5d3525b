// Small scenes written to disk for the command-line tests, with their .surfels files.
#pragma once

#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_export.hpp>

#include <string>
#include <utility>

namespace pbs::test {

// twoIdenticalGroups() as `scratch`/groups.glb, its path quoted for the command line.
inline std::string groupsFile(const ScratchDir& scratch) {
  writeGlb(twoIdenticalGroups(), scratch / "groups.glb");
  // Appended, not "'" + string: GCC 12's -Wrestrict misfires on that operator+ where it is inlined.
  std::string quoted = "'";
  quoted += (scratch / "groups.glb").string();
  quoted += "'";
  return quoted;
}

// groupsFile() and `scratch`/groups.surfels made from it by `pbs surfelize --min-triangles 1000
// --max-surfels 4000` (small enough that every array is captured from triangles), both quoted.
inline std::pair<std::string, std::string> groupsWithSurfels(const ScratchDir& scratch) {
  const std::string scene = groupsFile(scratch);
  const std::string surfels = "'" + (scratch / "groups.surfels").string() + "'";
  const CommandResult made =
      runPbs("surfelize " + scene + " -o " + surfels + " --min-triangles 1000 --max-surfels 4000 --quiet");
  EXPECT_EQ(made.status, 0) << made.err;
  return {scene, surfels};
}

}  // namespace pbs::test
