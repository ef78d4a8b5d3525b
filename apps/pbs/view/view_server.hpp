// `pbs view`'s HTTP side (cpp-httplib): the page, the scene's description, and frames rendered for the
// camera each request carries. Requests are validated (HTTP 400 with the reason), frames a client has
// superseded are dropped rather than rendered, and nothing but the page and the frames is served.
#pragma once

#include "background_surfelize.hpp"
#include "view_renderer.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <string>

namespace pbs::cli {

class ViewServer {
 public:
  // `renderer` must outlive the server; `scene` describes it to the page (/api/scene). `defaults` are the
  // LOD options frames start from (the command line's). `background`, if any, makes surfels on request
  // (/api/surfelize) and must outlive the server.
  ViewServer(ViewRenderer& renderer, nlohmann::json scene, const LodOptions& defaults, BackgroundSurfelize* background);
  ~ViewServer();

  // Binds `host`:`port` (0: any free port) and returns the port; throws std::runtime_error when it cannot.
  int bind(const std::string& host, int port);
  // Serves until stop(); returns false if serving failed.
  bool serve();
  // From any thread: ends serve() after the requests in progress.
  void stop();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace pbs::cli
