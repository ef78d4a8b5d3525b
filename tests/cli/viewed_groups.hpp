// `pbs view` of the groups test scene with its surfels, started for a test, with a client of it.
#pragma once

#include "cli_scenes.hpp"
#include "server_process.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

namespace pbs::test {

// A decimal text (17 significant digits) that reads back as the same double (for cameras given on command lines and
// in URLs, so that both sides compute the same camera).
inline std::string exactDecimal(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// The frame query (160×96) for an orbit around `center` (the scene description's), as `pbs render --orbit
// AZ,EL,DIST --size 160x96` sees it.
inline std::string orbitFrameQuery(const nlohmann::json& center, double az, double el, double dist,
                                   const std::string& more) {
  return "/api/frame?w=160&h=96&az=" + exactDecimal(az) + "&el=" + exactDecimal(el) + "&dist=" + exactDecimal(dist) +
         "&tx=" + exactDecimal(center[0]) + "&ty=" + exactDecimal(center[1]) + "&tz=" + exactDecimal(center[2]) + more;
}

struct ViewedGroups {
  ScratchDir scratch;
  std::pair<std::string, std::string> files = groupsWithSurfels(scratch);
  std::filesystem::path scene = scratch / "groups.glb";
  std::filesystem::path surfels = scratch / "groups.surfels";
  // The groups are small enough that rays draw every node cheaper than its surfels: the threshold alone decides
  // here, so that frames show surfels. The geometry's drawer is named: where the two are priced alike, Auto's
  // choice turns on the BVHs the viewer's earlier frames built, which a single `pbs render` has not (the
  // drawers agree only to a tolerance).
  ViewServer server{
      {"view", scene.string(), "--surfels", surfels.string(), "--rays-cheaper", "keep", "--geometry", "raster"}};
  httplib::Client client{"127.0.0.1", server.port};

  nlohmann::json description() {
    const auto response = client.Get("/api/scene");
    EXPECT_TRUE(response && response->status == 200);
    return response ? nlohmann::json::parse(response->body) : nlohmann::json{};
  }
  // The frame query for an orbit around the scene's centre (orbitFrameQuery).
  std::string orbitQuery(double az, double el, double dist, const std::string& more) {
    return orbitFrameQuery(description()["center"], az, el, dist, more);
  }
};

}  // namespace pbs::test
