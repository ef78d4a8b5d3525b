// The routes of ViewServer, the table of each client's newest frame, and a frame's encoding.
#include "view_server.hpp"

#include "../png_writer.hpp"
#include "jpeg_encoder.hpp"
#include "node_inspection.hpp"
#include "view_page.hpp"

#include <pbs/evaluation/contact_sheet.hpp>

#include <httplib.h>

#include <chrono>
#include <map>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

namespace pbs::cli {
namespace {

constexpr int kJpegQuality = 85;
constexpr std::size_t kMaxClients = 4096;          // the table of newest frames starts afresh beyond it
constexpr std::size_t kMaxDrawsListed = 2000;      // /api/draws: the largest nodes on screen
constexpr std::size_t kRhoCurvePoints = 120;       // /api/node/rho: log-spaced prefix lengths
constexpr std::uint32_t kCaptureViewPixels = 160;  // /api/node/views: each view's side

// Straight RGBA over white, as the page shows it, for JPEG (which has no alpha): a sheet of one tile.
std::vector<std::uint8_t> overWhite(const std::vector<std::uint8_t>& rgba, std::uint32_t width, std::uint32_t height) {
  constexpr std::uint8_t kWhite[3] = {255, 255, 255};
  return contactSheet(width, height, 1, {std::span<const std::uint8_t>(rgba)}, kWhite);
}

nlohmann::json frameStats(const ViewFrame& frame, double encodeSeconds, std::size_t bytes) {
  nlohmann::json stats = {{"render_ms", frame.seconds * 1e3},
                          {"encode_ms", encodeSeconds * 1e3},
                          {"bytes", bytes},
                          {"drawn_by", renderModeName(frame.drawnBy)},
                          {"samples", frame.samples},
                          {"triangles", frame.stats.triangles},
                          {"surfels", frame.stats.surfels},
                          {"nodes_geometry", frame.stats.nodesGeometry},
                          {"nodes_surfels", frame.stats.nodesSurfels}};
  if (frame.foregroundFlip) stats["flip"] = *frame.foregroundFlip;
  return stats;
}

std::multimap<std::string, std::string> parameters(const httplib::Request& request) {
  return {request.params.begin(), request.params.end()};
}

std::uint32_t requiredNode(const ViewRequest& request) {
  if (!request.node) throw std::invalid_argument("node: missing");
  return *request.node;
}

void sendBytes(httplib::Response& response, const std::vector<std::uint8_t>& bytes, const char* type) {
  response.set_content(reinterpret_cast<const char*>(bytes.data()), bytes.size(), type);
}

}  // namespace

// Each client's newest frame number: an older request still waiting for the renderer is dropped. Outside the
// anonymous namespace: ViewServer::State holds one, and in the unity build this file is not the main file.
class NewestFrames {
 public:
  void note(const std::string& client, std::uint64_t sequence) {
    const std::lock_guard lock(mutex_);
    if (newest_.size() >= kMaxClients && !newest_.count(client)) newest_.clear();
    std::uint64_t& newest = newest_[client];
    newest = std::max(newest, sequence);
  }
  bool superseded(const std::string& client, std::uint64_t sequence) const {
    const std::lock_guard lock(mutex_);
    const auto found = newest_.find(client);
    return found != newest_.end() && found->second > sequence;
  }

 private:
  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::uint64_t> newest_;
};

struct ViewServer::State {
  ViewRenderer& renderer;
  BackgroundSurfelize* background;
  nlohmann::json scene;
  ViewRequest defaults;
  NewestFrames newest;
  httplib::Server http;
};

ViewServer::ViewServer(ViewRenderer& renderer, nlohmann::json scene, const LodOptions& defaults,
                       BackgroundSurfelize* background)
    : state_(new State{renderer, background, std::move(scene), {}, {}, {}}) {
  state_->defaults.target = renderer.center();
  state_->defaults.lod = defaults;
  httplib::Server& http = state_->http;
  // SO_REUSEADDR (a restarted viewer gets its port back at once) without httplib's default SO_REUSEPORT,
  // with which a second server would share a port that is taken instead of being refused.
  http.set_socket_options([](socket_t socket) {
    const int yes = 1;
    setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  // Requests carry their parameters in the URL: nothing has a body.
  http.set_payload_max_length(1024);
  http.set_read_timeout(5, 0);
  http.set_write_timeout(10, 0);
  for (const PageFile& file : viewPageFiles())
    http.Get(std::string(file.path), [&file](const httplib::Request&, httplib::Response& response) {
      response.set_content(file.content.data(), file.content.size(), std::string(file.type).c_str());
    });
  State& state = *state_;
  http.Get("/api/scene", [&state](const httplib::Request&, httplib::Response& response) {
    response.set_header("Cache-Control", "no-store");
    nlohmann::json scene = state.scene;
    scene["surfels"] = state.renderer.hasSurfels();  // surfels made in the background arrive
    scene["can_make_surfels"] = state.background != nullptr;
    response.set_content(scene.dump(), "application/json");
  });
  // Surfels made in the background: POST starts, GET tells how far it is.
  const auto surfelizing = [&state](const httplib::Request& request, httplib::Response& response) {
    response.set_header("Cache-Control", "no-store");
    if (!state.background) {
      response.status = 400;
      response.set_content("error: this view was started with its surfels\n", "text/plain; charset=utf-8");
      return;
    }
    if (request.method == "POST") state.background->start();
    response.set_content(state.background->status().dump(), "application/json");
  };
  http.Get("/api/surfelize", surfelizing);
  http.Post("/api/surfelize", surfelizing);
  // Every API route: the request parsed and validated, the answer uncached, a refusal a 400 with the reason.
  const auto route = [&http, &state](const char* path, auto answer) {
    http.Get(path, [&state, answer](const httplib::Request& http_request, httplib::Response& response) {
      response.set_header("Cache-Control", "no-store");
      try {
        answer(parseViewRequest(parameters(http_request), state.defaults), response);
      } catch (const std::invalid_argument& error) {
        response.status = 400;
        response.set_content(std::string("error: ") + error.what() + "\n", "text/plain; charset=utf-8");
      }
    });
  };
  route("/api/frame", [&state](const ViewRequest& request, httplib::Response& response) {
    state.newest.note(request.client, request.sequence);
    const std::optional<ViewFrame> frame =
        state.renderer.render(request, [&] { return state.newest.superseded(request.client, request.sequence); });
    if (!frame) {
      response.status = 204;  // a newer frame of this client is on its way
      response.set_header("X-Pbs-Dropped", "superseded");
      return;
    }
    // Encoded outside the renderer's lock: the next frame renders meanwhile.
    const auto start = std::chrono::steady_clock::now();
    const std::vector<std::uint8_t> bytes = request.encoding == ViewEncoding::Jpeg
                                                ? encodeJpeg(overWhite(frame->rgba8, request.width, request.height),
                                                             request.width, request.height, kJpegQuality)
                                                : encodePng8(request.width, request.height, 4, frame->rgba8.data());
    const double encodeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    response.set_header("X-Pbs-Stats", frameStats(*frame, encodeSeconds, bytes.size()).dump());
    sendBytes(response, bytes, request.encoding == ViewEncoding::Jpeg ? "image/jpeg" : "image/png");
  });
  // The nodes a frame draws, for the page's overlay of boxes.
  route("/api/draws", [&state](const ViewRequest& request, httplib::Response& response) {
    nlohmann::json nodes = nlohmann::json::array();
    for (const NodeDraw& draw : state.renderer.nodeDraws(request, kMaxDrawsListed))
      nodes.push_back({{"node", draw.node},
                       {"kind", drawKindName(draw.kind)},
                       {"rect", {draw.rect.x, draw.rect.y, draw.rect.z, draw.rect.w}},
                       {"size", draw.size},
                       {"surfels", draw.surfels},
                       {"full", draw.full},
                       {"triangles", draw.triangles}});
    response.set_content(nodes.dump(), "application/json");
  });
  // The node that drew a pixel, described.
  route("/api/pick", [&state](const ViewRequest& request, httplib::Response& response) {
    const std::optional<std::uint32_t> node = state.renderer.pick(request);
    const nlohmann::json answer =
        node ? state.renderer.locked([&] { return describeNode(state.renderer.scene(), *node); }) : nullptr;
    response.set_content(answer.dump(), "application/json");
  });
  route("/api/node", [&state](const ViewRequest& request, httplib::Response& response) {
    const std::uint32_t node = requiredNode(request);
    response.set_content(state.renderer.locked([&] { return describeNode(state.renderer.scene(), node); }).dump(),
                         "application/json");
  });
  route("/api/node/rho", [&state](const ViewRequest& request, httplib::Response& response) {
    const std::uint32_t node = requiredNode(request);
    const nlohmann::json curve =
        state.renderer.locked([&] { return rhoCurve(state.renderer.scene(), node, kRhoCurvePoints); });
    response.set_content(curve.dump(), "application/json");
  });
  route("/api/node/views", [&state](const ViewRequest& request, httplib::Response& response) {
    const std::uint32_t node = requiredNode(request);
    sendBytes(response,
              state.renderer.locked([&] { return captureViewsPng(state.renderer.scene(), node, kCaptureViewPixels); }),
              "image/png");
  });
  // Anything else the server could not do (an allocation refused, a renderer's failure) is a 500 with the
  // reason, never a crash of the server.
  http.set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr thrown) {
    std::string reason = "unknown";
    try {
      std::rethrow_exception(thrown);
    } catch (const std::exception& error) {
      reason = error.what();
    } catch (...) {
    }
    response.status = 500;
    response.set_content("error: " + reason + "\n", "text/plain; charset=utf-8");
  });
}

ViewServer::~ViewServer() = default;

int ViewServer::bind(const std::string& host, int port) {
  const int bound = port == 0 ? state_->http.bind_to_any_port(host) : state_->http.bind_to_port(host, port) ? port : -1;
  if (bound <= 0) throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port));
  return bound;
}

bool ViewServer::serve() { return state_->http.listen_after_bind(); }

void ViewServer::stop() { state_->http.stop(); }

}  // namespace pbs::cli
