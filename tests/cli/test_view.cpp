// `pbs view` as a client sees it: the page and the scene served, frames equal to `pbs render`'s for the
// same camera, bad requests answered 400 with the reason, superseded frames dropped, several clients at
// once, and Ctrl-C ending it cleanly. The server listens on 127.0.0.1 and is stopped by its process id.
#include "viewed_groups.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

namespace pbs::test {
namespace {

TEST(View, ServesThePageAndDescribesTheScene) {
  ViewedGroups view;
  ASSERT_GT(view.server.port, 0);
  const auto page = view.client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("<title>pbs view</title>"), std::string::npos);
  EXPECT_NE(page->get_header_value("Content-Type").find("text/html"), std::string::npos);
  for (const char* file : {"/view.js", "/view.css"}) {
    const auto served = view.client.Get(file);
    ASSERT_TRUE(served);
    EXPECT_EQ(served->status, 200) << file;
    EXPECT_GT(served->body.size(), 500u) << file;
  }
  const nlohmann::json scene = view.description();
  EXPECT_TRUE(scene["name"].get<std::string>().ends_with("groups.glb"));
  EXPECT_TRUE(scene["surfels"].get<bool>());
  EXPECT_GT(scene["radius"].get<double>(), 0.0);
  for (const char* path : {"orbit", "approach", "flythrough"}) EXPECT_EQ(scene["paths"][path].size(), 24u) << path;
  // Nothing but the page, the description and frames.
  for (const char* other : {"/etc/passwd", "/../CMakeLists.txt", "/api/other", "/index.html"}) {
    const auto response = view.client.Get(other);
    ASSERT_TRUE(response);
    EXPECT_EQ(response->status, 404) << other;
  }
}

TEST(View, FramesAreTheBytesPbsRenderWritesForTheSameCamera) {
  ViewedGroups view;
  ASSERT_GT(view.server.port, 0);
  for (const std::string mode : {"surfels", "exact", "embree"}) {
    const auto frame = view.client.Get(view.orbitQuery(75, 35, 2.2, "&show=" + mode));
    ASSERT_TRUE(frame);
    ASSERT_EQ(frame->status, 200) << frame->body;
    EXPECT_EQ(frame->get_header_value("Content-Type"), "image/png");
    const nlohmann::json stats = nlohmann::json::parse(frame->get_header_value("X-Pbs-Stats"));
    EXPECT_EQ(stats["drawn_by"], mode);
    const std::filesystem::path rendered = view.scratch / (mode + ".png");
    const CommandResult render =
        runPbs("render " + quoted(view.scene) + " --surfels " + quoted(view.surfels) + " --mode " + mode +
               " --rays-cheaper keep --geometry raster --orbit 75,35,2.2 --size 160x96 -o " + quoted(rendered));
    ASSERT_EQ(render.status, 0) << render.err;
    EXPECT_TRUE(frame->body == readFile(rendered)) << mode << ": the served PNG differs from pbs render's";
  }
  // Supersampled and moving (JPEG) frames too.
  const auto sampled = view.client.Get(view.orbitQuery(75, 35, 2.2, "&show=embree&samples=4"));
  ASSERT_TRUE(sampled && sampled->status == 200);
  const CommandResult render4 =
      runPbs("render " + quoted(view.scene) + " --mode embree --samples 4 --orbit 75,35,2.2 --size 160x96 -o " +
             quoted(view.scratch / "embree4.png"));
  ASSERT_EQ(render4.status, 0) << render4.err;
  EXPECT_TRUE(sampled->body == readFile(view.scratch / "embree4.png"));
  const auto moving = view.client.Get(view.orbitQuery(75, 35, 2.2, "&format=jpeg"));
  ASSERT_TRUE(moving && moving->status == 200);
  EXPECT_EQ(moving->get_header_value("Content-Type"), "image/jpeg");
  EXPECT_EQ(moving->body.substr(0, 3), std::string("\xFF\xD8\xFF"));
}

TEST(View, ComparisonsAndSettingsChangeTheFrame) {
  ViewedGroups view;
  ASSERT_GT(view.server.port, 0);
  const auto surfels = view.client.Get(view.orbitQuery(10, 20, 2.5, ""));
  const auto fewer = view.client.Get(view.orbitQuery(10, 20, 2.5, "&overdraw=0.25"));
  const auto nearest = view.client.Get(view.orbitQuery(10, 20, 2.5, "&splat=nearest&point=3"));
  const auto flip = view.client.Get(view.orbitQuery(10, 20, 2.5, "&show=flip"));
  const auto difference = view.client.Get(view.orbitQuery(10, 20, 2.5, "&show=difference"));
  for (const auto* response : {&surfels, &fewer, &nearest, &flip, &difference}) {
    ASSERT_TRUE(*response);
    ASSERT_EQ((*response)->status, 200) << (*response)->body;
  }
  EXPECT_NE(surfels->body, fewer->body);
  EXPECT_NE(surfels->body, nearest->body);
  const nlohmann::json fewerStats = nlohmann::json::parse(fewer->get_header_value("X-Pbs-Stats"));
  const nlohmann::json allStats = nlohmann::json::parse(surfels->get_header_value("X-Pbs-Stats"));
  EXPECT_LT(fewerStats["surfels"].get<double>(), allStats["surfels"].get<double>());
  const nlohmann::json flipStats = nlohmann::json::parse(flip->get_header_value("X-Pbs-Stats"));
  EXPECT_GT(flipStats["flip"].get<double>(), 0.0);
  EXPECT_LT(flipStats["flip"].get<double>(), 1.0);
  EXPECT_NE(flip->body, difference->body);
}

TEST(View, NodesAreListedPickedAndInspected) {
  ViewedGroups view;
  ASSERT_GT(view.server.port, 0);
  const std::string camera = view.orbitQuery(10, 20, 2.5, "").substr(std::string("/api/frame?").size());
  const auto draws = view.client.Get("/api/draws?" + camera);
  ASSERT_TRUE(draws && draws->status == 200);
  const nlohmann::json nodes = nlohmann::json::parse(draws->body);
  ASSERT_FALSE(nodes.empty());
  double largest = 1e300;
  for (const nlohmann::json& node : nodes) {
    EXPECT_LE(node["size"].get<double>(), largest) << "listed largest first";
    largest = node["size"].get<double>();
    const nlohmann::json& rect = node["rect"];
    EXPECT_LE(rect[0].get<double>(), rect[2].get<double>());
    EXPECT_GE(rect[0].get<double>(), 0.0);
    EXPECT_LE(rect[2].get<double>(), 160.0);
    const std::string kind = node["kind"];
    EXPECT_TRUE(kind == "geometry" || kind == "surfels" || kind == "band") << kind;
    if (kind != "geometry") {
      EXPECT_GT(node["surfels"].get<int>(), 0);
    }
  }
  // The centre pixel of the largest surfel node's rectangle is drawn by a node the list names.
  std::optional<nlohmann::json> drawn;
  for (const nlohmann::json& node : nodes)
    if (node["kind"] == "surfels" && !drawn) drawn = node;
  ASSERT_TRUE(drawn);
  const int x = int(((*drawn)["rect"][0].get<double>() + (*drawn)["rect"][2].get<double>()) / 2);
  const int y = int(((*drawn)["rect"][1].get<double>() + (*drawn)["rect"][3].get<double>()) / 2);
  const auto picked = view.client.Get("/api/pick?" + camera + "&x=" + std::to_string(x) + "&y=" + std::to_string(y));
  ASSERT_TRUE(picked && picked->status == 200) << (picked ? picked->body : "");
  const nlohmann::json node = nlohmann::json::parse(picked->body);
  if (!node.is_null()) {
    bool listed = false;
    for (const nlohmann::json& entry : nodes) listed |= entry["node"] == node["node"];
    EXPECT_TRUE(listed) << node.dump();
  }
  const std::string id = std::to_string((*drawn)["node"].get<int>());
  const auto described = view.client.Get("/api/node?node=" + id);
  ASSERT_TRUE(described && described->status == 200);
  const nlohmann::json facts = nlohmann::json::parse(described->body);
  ASSERT_TRUE(facts.contains("array"));
  const int length = facts["array"]["surfels"].get<int>();
  const auto rho = view.client.Get("/api/node/rho?node=" + id);
  ASSERT_TRUE(rho && rho->status == 200);
  const nlohmann::json curve = nlohmann::json::parse(rho->body);
  ASSERT_GT(curve["k"].size(), 10u);
  EXPECT_EQ(curve["k"].back().get<int>(), length);
  for (const nlohmann::json& value : curve["rho"]) EXPECT_GT(value.get<double>(), 0.0);
  const auto views = view.client.Get("/api/node/views?node=" + id);
  ASSERT_TRUE(views && views->status == 200);
  EXPECT_EQ(views->body.substr(1, 3), "PNG");
  // A prefix alone draws exactly its surfels; the overlay of sources tints the surfel frame.
  for (const int k : {1, 50, length}) {
    const auto prefix =
        view.client.Get(view.orbitQuery(10, 20, 2.5, "&show=prefix&node=" + id + "&prefix=" + std::to_string(k)));
    ASSERT_TRUE(prefix && prefix->status == 200) << (prefix ? prefix->body : "");
    EXPECT_EQ(nlohmann::json::parse(prefix->get_header_value("X-Pbs-Stats"))["surfels"].get<int>(), k);
  }
  const auto source = view.client.Get(view.orbitQuery(10, 20, 2.5, "&show=source"));
  const auto plain = view.client.Get(view.orbitQuery(10, 20, 2.5, ""));
  ASSERT_TRUE(source && source->status == 200 && plain && plain->status == 200);
  EXPECT_NE(source->body, plain->body);
  // Refusals name what is wrong.
  for (const auto& [query, reason] : std::vector<std::pair<std::string, std::string>>{
           {"/api/node?node=100000", "node: the scene has"},
           {"/api/node", "node: missing"},
           {"/api/frame?show=prefix", "show=prefix: needs node and prefix"},
           {"/api/pick?w=64&h=64&x=64&y=0", "x, y: outside the 64x64 frame"}}) {
    const auto refused = view.client.Get(query);
    ASSERT_TRUE(refused) << query;
    EXPECT_EQ(refused->status, 400) << query;
    EXPECT_NE(refused->body.find(reason), std::string::npos) << query << ": " << refused->body;
  }
}

TEST(View, BadRequestsAreRefusedWithTheReasonAndTheServerGoesOn) {
  ViewedGroups view;
  ASSERT_GT(view.server.port, 0);
  const std::pair<const char*, const char*> bad[] = {
      {"/api/frame?w=abc", "w: expected a whole number"},
      {"/api/frame?w=100000", "w: expected a whole number in [16, 3840]"},
      {"/api/frame?az=nan", "az: expected a number"},
      {"/api/frame?dist=0", "dist: expected a number"},
      {"/api/frame?el=1e400", "el: expected a number"},
      {"/api/frame?show=wireframe", "show: expected surfels, exact, embree"},
      {"/api/frame?samples=3", "samples: expected 1, 4, 16 or 64"},
      {"/api/frame?format=gif", "format: expected jpeg or png"},
      {"/api/frame?client=a%20b", "client: expected 1 to 64 letters"},
      {"/api/frame?w=64&w=65", "w: given more than once"},
      {"/api/frame?hack=1", "unknown parameter 'hack'"},
      {"/api/frame?point=2", "point: a fixed point size is for splat=nearest"},
      {"/api/frame?budget=10&budget_ms=5", "budget and budget_ms: give one"},
  };
  for (const auto& [query, reason] : bad) {
    const auto response = view.client.Get(query);
    ASSERT_TRUE(response) << query;
    EXPECT_EQ(response->status, 400) << query;
    EXPECT_EQ(response->body.rfind(std::string("error: ") + reason, 0), 0u) << query << ": " << response->body;
  }
  // A body is refused, a long URL too; then a good frame still comes.
  const auto posted = view.client.Post("/api/frame", std::string(1 << 16, 'x'), "text/plain");
  ASSERT_TRUE(posted);
  EXPECT_GE(posted->status, 400);
  const auto longUrl = view.client.Get("/api/frame?client=" + std::string(20000, 'a'));
  EXPECT_TRUE(!longUrl || longUrl->status >= 400);
  const auto good = view.client.Get("/api/frame?w=64&h=64");
  ASSERT_TRUE(good);
  EXPECT_EQ(good->status, 200);
}

TEST(View, AFrameSupersededByTheSameClientIsDropped) {
  ViewedGroups view;
  ASSERT_GT(view.server.port, 0);
  const auto newer = view.client.Get("/api/frame?w=64&h=64&client=tab1&seq=5");
  ASSERT_TRUE(newer && newer->status == 200);
  const auto older = view.client.Get("/api/frame?w=64&h=64&client=tab1&seq=3");
  ASSERT_TRUE(older);
  EXPECT_EQ(older->status, 204);
  EXPECT_EQ(older->get_header_value("X-Pbs-Dropped"), "superseded");
  // Another client's older number is its own.
  const auto other = view.client.Get("/api/frame?w=64&h=64&client=tab2&seq=3");
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 200);
}

// The server's resident memory, from /proc (Linux), in bytes.
std::uint64_t residentBytes(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
  return 0;
}

// A bounded load test: several clients orbiting at once, each with its own sequence. Every answer is a
// frame or a drop, never an error; a second round leaves the server's memory where the first did (no
// leak grows with frames); the frames' times are reported.
TEST(View, SeveralClientsMovingAtOnce) {
  ViewedGroups view;
  ASSERT_GT(view.server.port, 0);
  constexpr int kClients = 4, kFrames = 12;
  std::atomic<int> frames{0}, dropped{0}, failed{0};
  std::mutex timesMutex;
  std::vector<double> renderMs, deliveredMs;
  const auto round = [&](int first) {
    std::vector<std::thread> clients;
    for (int c = 0; c < kClients; ++c)
      clients.emplace_back([&, c] {
        httplib::Client client("127.0.0.1", view.server.port);
        for (int f = first; f < first + kFrames; ++f) {
          const std::string query = "/api/frame?w=320&h=180&format=jpeg&client=load" + std::to_string(c) +
                                    "&seq=" + std::to_string(f) + "&az=" + std::to_string(30 * c + 15 * f);
          const auto start = std::chrono::steady_clock::now();
          const auto response = client.Get(query);
          const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
          if (response && response->status == 200) {
            ++frames;
            const std::lock_guard lock(timesMutex);
            renderMs.push_back(nlohmann::json::parse(response->get_header_value("X-Pbs-Stats"))["render_ms"]);
            deliveredMs.push_back(ms);
          } else if (response && response->status == 204) {
            ++dropped;
          } else {
            ++failed;
          }
        }
      });
    for (std::thread& client : clients) client.join();
  };
  round(0);
  const std::uint64_t afterFirst = residentBytes(view.server.process.pid());
  round(kFrames);
  const std::uint64_t afterSecond = residentBytes(view.server.process.pid());
  EXPECT_EQ(failed.load(), 0);
  EXPECT_EQ(frames.load() + dropped.load(), 2 * kClients * kFrames);
  EXPECT_GT(frames.load(), 0);
  EXPECT_LE(afterSecond, afterFirst + afterFirst / 4 + (16u << 20)) << "resident memory grew with frames";
  const auto median = [](std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values.empty() ? 0.0 : values[values.size() / 2];
  };
  std::printf(
      "load: %d clients, %d frames, %d dropped; render %.1f ms, delivered %.1f ms (medians); resident "
      "%.1f then %.1f MB\n",
      kClients, frames.load(), dropped.load(), median(renderMs), median(deliveredMs), afterFirst / 1e6,
      afterSecond / 1e6);
  const auto after = view.client.Get("/api/frame?w=64&h=64");
  ASSERT_TRUE(after);
  EXPECT_EQ(after->status, 200);
  EXPECT_TRUE(view.server.process.running());
}

TEST(View, CtrlCStopsItCleanly) {
  ViewedGroups view;
  ASSERT_GT(view.server.port, 0);
  ASSERT_TRUE(view.client.Get("/api/frame?w=64&h=64"));
  const std::optional<int> status = view.server.process.stop(SIGINT, 30.0);
  ASSERT_TRUE(status) << "pbs view did not stop on SIGINT";
  EXPECT_EQ(*status, 0) << view.server.process.err();
  EXPECT_NE(view.server.process.out().find("pbs view: stopped"), std::string::npos);
}

TEST(View, WithoutSurfelsItShowsTheSceneExactly) {
  ScratchDir scratch;
  const std::string scene = (scratch / "groups.glb").string();
  groupsFile(scratch);
  ViewServer server({"view", scene});
  ASSERT_GT(server.port, 0);
  httplib::Client client("127.0.0.1", server.port);
  const auto description = client.Get("/api/scene");
  ASSERT_TRUE(description);
  EXPECT_FALSE(nlohmann::json::parse(description->body)["surfels"].get<bool>());
  const auto surfels = client.Get("/api/frame?w=64&h=64&show=surfels");
  ASSERT_TRUE(surfels);
  EXPECT_EQ(surfels->status, 400);
  EXPECT_NE(surfels->body.find("no .surfels file"), std::string::npos) << surfels->body;
  const auto rho = client.Get("/api/node/rho?node=0");
  ASSERT_TRUE(rho);
  EXPECT_EQ(rho->status, 400);
  EXPECT_NE(rho->body.find("no surfel array"), std::string::npos) << rho->body;
  const auto exact = client.Get("/api/frame?w=64&h=64&show=embree");
  ASSERT_TRUE(exact);
  EXPECT_EQ(exact->status, 200);
}

// `--texture-filter` filters the frames a viewer shows as `pbs render`'s: the embedded default scene's textured
// frames through rays, each the bytes `pbs render --texture-filter` writes for the same camera.
TEST(View, FramesFilterTexturesAsTheCommandLineSays) {
  ScratchDir scratch;
  std::map<std::string, std::string> shown;
  for (const std::string filter : {"anisotropic", "none"}) {
    ViewServer server({"view", "default", "--texture-filter", filter});
    ASSERT_GT(server.port, 0);
    httplib::Client client("127.0.0.1", server.port);
    const auto description = client.Get("/api/scene");
    ASSERT_TRUE(description);
    const nlohmann::json scene = nlohmann::json::parse(description->body);
    EXPECT_EQ(scene["texture_filter"], filter);
    const auto frame = client.Get(orbitFrameQuery(scene["center"], 75, 35, 2.2, "&show=embree"));
    ASSERT_TRUE(frame);
    ASSERT_EQ(frame->status, 200) << frame->body;
    const std::filesystem::path rendered = scratch / (filter + ".png");
    const CommandResult render = runPbs("render default --mode embree --texture-filter " + filter +
                                        " --orbit 75,35,2.2 --size 160x96 -o " + quoted(rendered));
    ASSERT_EQ(render.status, 0) << render.err;
    EXPECT_TRUE(frame->body == readFile(rendered)) << filter;
    shown[filter] = frame->body;
  }
  EXPECT_NE(shown["anisotropic"], shown["none"]);
  EXPECT_EQ(runPbs("view default --texture-filter trilinear").status, 2) << "an unknown filter is bad usage";
}

TEST(View, SurfelsMadeInTheBackgroundAreSurfelizesAndAreDrawn) {
  ScratchDir scratch;
  groupsFile(scratch);
  const std::filesystem::path scene = scratch / "groups.glb", made = scratch / "made.surfels";
  ViewServer server({"view", scene.string(), "--make-surfels", made.string()});
  ASSERT_GT(server.port, 0);
  httplib::Client client("127.0.0.1", server.port);
  const auto idle = client.Get("/api/surfelize");
  ASSERT_TRUE(idle && idle->status == 200);
  EXPECT_EQ(nlohmann::json::parse(idle->body)["state"], "idle");
  const auto started = client.Post("/api/surfelize", "", "text/plain");
  ASSERT_TRUE(started && started->status == 200);
  nlohmann::json status = nlohmann::json::parse(started->body);
  for (int poll = 0; poll < 600 && status["state"] == "running"; ++poll) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    status = nlohmann::json::parse(client.Get("/api/surfelize")->body);
  }
  ASSERT_EQ(status["state"], "done") << status.dump();
  EXPECT_EQ(status["fraction"].get<double>(), 1.0);
  EXPECT_TRUE(nlohmann::json::parse(client.Get("/api/scene")->body)["surfels"].get<bool>());
  // The file is `pbs surfelize`'s at its defaults, and frames draw it.
  const std::filesystem::path reference = scratch / "reference.surfels";
  const CommandResult surfelize = runPbs("surfelize " + quoted(scene) + " -o " + quoted(reference) + " --quiet");
  ASSERT_EQ(surfelize.status, 0) << surfelize.err;
  EXPECT_TRUE(readFile(made) == readFile(reference)) << "the background's file differs from pbs surfelize's";
  const auto frame = client.Get("/api/frame?w=64&h=64&show=surfels");
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->status, 200) << frame->body;
}

TEST(View, BadCommandLinesAreOneErrorLine) {
  ScratchDir scratch;
  const CommandResult missing = runPbs("view " + quoted(scratch / "none.glb") + " --port 0");
  EXPECT_EQ(missing.status, 1);
  EXPECT_EQ(missing.err.rfind("error: ", 0), 0u) << missing.err;
  const CommandResult port = runPbs("view default --port 70000");
  EXPECT_EQ(port.status, 2);
  // A port another server holds: one error line naming the address.
  groupsFile(scratch);
  ViewServer first({"view", (scratch / "groups.glb").string()});
  ASSERT_GT(first.port, 0);
  const CommandResult taken =
      runPbs("view " + quoted(scratch / "groups.glb") + " --port " + std::to_string(first.port));
  EXPECT_EQ(taken.status, 1);
  EXPECT_EQ(taken.err, "error: cannot listen on 127.0.0.1:" + std::to_string(first.port) + "\n");
}

}  // namespace
}  // namespace pbs::test
