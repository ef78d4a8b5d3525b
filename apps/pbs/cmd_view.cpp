// `pbs view SCENE [--surfels F] [--port 8080] [--bind 127.0.0.1]`: the scene live in a browser, each frame
// rendered on this machine's CPU for the camera the page sends (apps/pbs/view).
#include "commands.hpp"
#include "frame_scene.hpp"
#include "memory_limit.hpp"
#include "orbit_views.hpp"
#include "view/view_server.hpp"

#include <pbs/raster/thread_arena.hpp>

#include <stdlib.h>  // mkdtemp

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <pthread.h>
#include <filesystem>
#include <optional>
#include <thread>

namespace pbs::cli {
namespace {

struct ViewOptions {
  std::string scene;
  std::string surfels;
  std::string makeSurfels;  // where surfels made from the page go; empty: a temporary folder
  int port = 8080;
  std::string bind = "127.0.0.1";
  LodOptions lod;
  TextureFiltering textures = TextureFiltering::Anisotropic;
  std::uint64_t cacheMb = 1024;
  std::uint64_t maxMemory = 0;
  int threads = 0;
};

constexpr std::uint32_t kPathFrames = 24;  // the page's "go to" stops along each named path

// A fresh folder under the system's temporary one, removed with everything in it when this goes away.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "pbs-view-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot make a temporary folder under " + pattern);
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

bool isLoopback(const std::string& host) { return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0; }

// A path camera as the page's camera: an orbit around a target in front of the eye, at the distance of
// the scene's centre along the view (at least a twentieth of its radius).
nlohmann::json pageCamera(const PathView& view, const glm::dvec3& center, double radius) {
  const double along = std::max(glm::dot(center - view.eye, view.forward), 0.05 * radius);
  const glm::dvec3 target = view.eye + view.forward * along;
  const glm::dvec3 back = -view.forward;
  return {{"tx", target.x},
          {"ty", target.y},
          {"tz", target.z},
          {"az", glm::degrees(std::atan2(back.z, back.x))},
          {"el", glm::degrees(std::asin(std::clamp(back.y, -1.0, 1.0)))},
          {"dist", along / radius}};
}

nlohmann::json sceneJson(const LoadedScene& loaded, const ViewRenderer& renderer, const LodOptions& lod,
                         TextureFiltering textures) {
  const Orbit start;
  nlohmann::json paths;
  for (const char* name : {"orbit", "approach", "flythrough"}) {
    for (const PathView& view : pathViews(loaded, name, start, kPathFrames, 16, 16))
      paths[name].push_back(pageCamera(view, renderer.center(), renderer.radius()));
  }
  const glm::dvec3 c = renderer.center();
  return {{"name", loaded.name},
          {"triangles", loaded.summary.triangles},
          {"nodes", loaded.scene.nodes.size()},
          {"center", {c.x, c.y, c.z}},
          {"radius", renderer.radius()},
          {"orbit", {start.azimuthDegrees, start.elevationDegrees, start.distance}},
          {"lod",
           {{"threshold", lod.threshold},
            {"overdraw", lod.overdraw},
            {"splat", splatModeName(lod.splat)},
            {"point", lod.pointSize}}},
          {"texture_filter", textureFilteringName(textures)},
          {"paths", paths}};
}

void run(const ViewOptions& options) {
  // Frame buffers of the largest view at its most (G-buffer, comparison images), for a few renderers.
  const std::uint64_t pixelBytes = std::uint64_t(kMaxViewWidth) * kMaxViewHeight * (36 + 32) * 2;
  FrameScene scene(
      {.scene = options.scene,
       .surfels = options.surfels,
       .cacheBytes = options.cacheMb << 20,
       .alongside = pixelBytes,
       .what = "viewing frames up to " + std::to_string(kMaxViewWidth) + "x" + std::to_string(kMaxViewHeight),
       .maxMemory = options.maxMemory});
  ViewRenderer renderer(scene, options.maxMemory, options.textures);
  // Without a .surfels file the page may ask for one to be made: declared after the renderer it hands
  // the file to, so that it stops first.
  std::optional<TemporaryFolder> temporary;
  std::optional<BackgroundSurfelize> background;
  if (options.surfels.empty()) {
    if (options.makeSurfels.empty()) temporary.emplace();
    const std::filesystem::path file =
        temporary ? temporary->path() / "scene.surfels" : std::filesystem::path(options.makeSurfels);
    background.emplace(scene.loaded.scene, scene.loaded.hierarchy, file,
                       [&renderer](const std::filesystem::path& made) { renderer.attachSurfels(made); });
  }
  ViewServer server(renderer, sceneJson(scene.loaded, renderer, options.lod, options.textures), options.lod,
                    background ? &*background : nullptr);
  const int port = server.bind(options.bind, options.port);
  if (!isLoopback(options.bind))
    std::fprintf(stderr, "warning: listening on %s: anyone who can reach this machine can view the scene\n",
                 options.bind.c_str());
  const std::string host = options.bind.find(':') != std::string::npos ? "[" + options.bind + "]" : options.bind;
  std::printf("pbs view: %s at http://%s:%d/ (Ctrl-C stops)\n", scene.loaded.name.c_str(), host.c_str(), port);
  std::fflush(stdout);
  // Ctrl-C and SIGTERM (blocked in every thread, see addViewCommand) end the serving from this thread.
  std::thread waiter([&server] {
    sigset_t stopping;
    sigemptyset(&stopping);
    sigaddset(&stopping, SIGINT);
    sigaddset(&stopping, SIGTERM);
    sigaddset(&stopping, SIGUSR1);
    int signal = 0;
    sigwait(&stopping, &signal);
    if (signal != SIGUSR1) server.stop();
  });
  const bool served = server.serve();
  pthread_kill(waiter.native_handle(), SIGUSR1);  // the server stopped by itself: let the waiter go
  waiter.join();
  if (!served) throw std::runtime_error("serving on " + options.bind + ":" + std::to_string(port) + " failed");
  std::printf("pbs view: stopped\n");
}

}  // namespace

void addViewCommand(CLI::App& app) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* command =
      app.add_subcommand("view", "Serve the scene to a browser: orbit, fly and compare, rendered on this CPU");
  command->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--surfels", options->surfels, "the scene's .surfels file (from pbs surfelize)");
  command
      ->add_option("--make-surfels", options->makeSurfels,
                   "without --surfels: where the surfels the page asks for are written (default: a temporary "
                   "file, removed when the viewer stops)")
      ->excludes("--surfels");
  command->add_option("--port", options->port, "TCP port (0: any free one)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  command
      ->add_option("--bind", options->bind,
                   "address to listen on; anything but loopback lets other machines view the scene (a warning)")
      ->capture_default_str();
  addLodOptions(*command, options->lod);
  addTextureFilterOption(*command, options->textures);
  addCacheOption(*command, options->cacheMb,
                 "surfels (and meshes, where the .surfels file allows) are read as frames draw them; the least "
                 "recently drawn are dropped beyond this many MB each");
  addMaxMemoryOption(*command, options->maxMemory);
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    // Before any thread starts (the scene's loading starts TBB's): every thread inherits the mask, so the
    // stopping signals reach only the waiter's sigwait, and a client gone mid-response is not a SIGPIPE.
    sigset_t stopping;
    sigemptyset(&stopping);
    sigaddset(&stopping, SIGINT);
    sigaddset(&stopping, SIGTERM);
    sigaddset(&stopping, SIGUSR1);
    pthread_sigmask(SIG_BLOCK, &stopping, nullptr);
    std::signal(SIGPIPE, SIG_IGN);
    runWithThreads(options->threads, [&] { run(*options); });
  });
}

}  // namespace pbs::cli
