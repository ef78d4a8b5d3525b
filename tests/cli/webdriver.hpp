// A small W3C WebDriver client (the protocol chromedriver speaks: JSON over HTTP), for tests that drive a
// real headless Chromium: start it, open a page, run scripts, drag, click, type, take screenshots.
#pragma once

#include "server_process.hpp"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <netinet/in.h>
#include <optional>
#include <string>
#include <sys/socket.h>
#include <thread>
#include <unistd.h>

namespace pbs::test {

inline constexpr const char* kChromium = "/usr/bin/chromium";
inline constexpr const char* kChromedriver = "/usr/bin/chromedriver";
// Skips the calling test with a clear message where Chromium or chromedriver is not installed.
#define PBS_REQUIRE_CHROMIUM()                                                                                  \
  if (!std::filesystem::exists(::pbs::test::kChromium) || !std::filesystem::exists(::pbs::test::kChromedriver)) \
  GTEST_SKIP() << "Chromium or chromedriver not installed (apt-get install chromium chromium-driver; "          \
                  "scripts/setup.sh installs them)"

// The key WebDriver sends for ArrowLeft (the protocol's code point for it).
inline const std::string kArrowLeft = "\xEE\x80\x92";  // U+E012

// A TCP port free on 127.0.0.1 a moment ago (for a program that must be told its port).
inline int freeLoopbackPort() {
  const int socket = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  int port = 0;
  if (::bind(socket, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
      ::getsockname(socket, reinterpret_cast<sockaddr*>(&address), &size) == 0)
    port = ntohs(address.sin_port);
  ::close(socket);
  return port;
}

// Standard base64 (WebDriver's screenshots); characters outside the alphabet end the data.
inline std::string base64Decode(const std::string& text) {
  static const std::string kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  unsigned bits = 0;
  int count = 0;
  for (char c : text) {
    const std::size_t value = kAlphabet.find(c);
    if (value == std::string::npos) break;
    bits = (bits << 6) | unsigned(value);
    count += 6;
    if (count >= 8) {
      count -= 8;
      bytes.push_back(char((bits >> count) & 0xFF));
    }
  }
  return bytes;
}

class Browser {
 public:
  // Starts chromedriver on a loopback port and a headless Chromium session of `width` × `height`.
  Browser(int width, int height)
      : port_(freeLoopbackPort()),
        driver_(kChromedriver, {"--port=" + std::to_string(port_), "--allowed-ips=127.0.0.1"}),
        http_("127.0.0.1", port_) {
    http_.set_read_timeout(120, 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline) {
      const auto status = http_.Get("/status");
      if (status && status->status == 200 && nlohmann::json::parse(status->body)["value"]["ready"] == true) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    const nlohmann::json capabilities = {
        {"capabilities",
         {{"alwaysMatch",
           {{"browserName", "chrome"},
            {"goog:chromeOptions",
             {{"binary", kChromium},
              {"args",
               {"--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=" + std::to_string(width) + "," + std::to_string(height)}}}}}}}}};
    const nlohmann::json session = command("POST", "/session", capabilities);
    if (session.contains("sessionId")) session_ = session["sessionId"];
  }
  ~Browser() {
    if (!session_.empty()) command("DELETE", "/session/" + session_, nullptr);
    driver_.stop(SIGTERM, 10.0);
  }

  bool started() const { return !session_.empty(); }
  void open(const std::string& url) { command("POST", path("/url"), {{"url", url}}); }
  // Runs `script` (a function body) in the page and returns what it returns.
  nlohmann::json run(const std::string& script) {
    return command("POST", path("/execute/sync"), {{"script", script}, {"args", nlohmann::json::array()}});
  }
  // Runs `condition` (an expression) until it is true, for up to `seconds`.
  bool waitFor(const std::string& condition, double seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < deadline) {
      if (run("return Boolean(" + condition + ");") == true) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }
  std::string element(const std::string& css) {
    const nlohmann::json found = command("POST", path("/element"), {{"using", "css selector"}, {"value", css}});
    return found.is_object() && !found.empty() ? found.begin().value().get<std::string>() : "";
  }
  void click(const std::string& css) {
    command("POST", path("/element/" + element(css) + "/click"), nlohmann::json::object());
  }
  // Presses the mouse on `css`'s centre, moves by (dx, dy) in `steps` and releases: a real drag.
  void drag(const std::string& css, int dx, int dy, int steps) {
    nlohmann::json moves = nlohmann::json::array();
    moves.push_back({{"type", "pointerMove"}, {"origin", {{kElementKey, element(css)}}}, {"x", 0}, {"y", 0}});
    moves.push_back({{"type", "pointerDown"}, {"button", 0}});
    for (int s = 0; s < steps; ++s)
      moves.push_back(
          {{"type", "pointerMove"}, {"origin", "pointer"}, {"duration", 20}, {"x", dx / steps}, {"y", dy / steps}});
    moves.push_back({{"type", "pointerUp"}, {"button", 0}});
    perform({{"type", "pointer"}, {"id", "mouse"}, {"parameters", {{"pointerType", "mouse"}}}, {"actions", moves}});
  }
  // Presses and releases the mouse at (x, y) from `css`'s top-left corner: a click without a drag.
  void clickAt(const std::string& css, int x, int y) {
    const nlohmann::json rect = command("GET", path("/element/" + element(css) + "/rect"), nullptr);
    const int centerX = int(rect["width"].get<double>() / 2), centerY = int(rect["height"].get<double>() / 2);
    nlohmann::json presses = nlohmann::json::array();
    presses.push_back(
        {{"type", "pointerMove"}, {"origin", {{kElementKey, element(css)}}}, {"x", x - centerX}, {"y", y - centerY}});
    presses.push_back({{"type", "pointerDown"}, {"button", 0}});
    presses.push_back({{"type", "pointerUp"}, {"button", 0}});
    perform({{"type", "pointer"}, {"id", "mouse"}, {"parameters", {{"pointerType", "mouse"}}}, {"actions", presses}});
  }
  // Presses and releases each key of `keys` (UTF-8; WebDriver's special keys are code points U+E000…).
  void type(const std::vector<std::string>& keys) {
    nlohmann::json presses = nlohmann::json::array();
    for (const std::string& key : keys) {
      presses.push_back({{"type", "keyDown"}, {"value", key}});
      presses.push_back({{"type", "keyUp"}, {"value", key}});
    }
    perform({{"type", "key"}, {"id", "keyboard"}, {"actions", presses}});
  }
  // The window as a PNG file's bytes.
  std::string screenshot() {
    const nlohmann::json encoded = command("GET", path("/screenshot"), nullptr);
    return encoded.is_string() ? base64Decode(encoded.get<std::string>()) : "";
  }

 private:
  static constexpr const char* kElementKey = "element-6066-11e4-a52e-4f735466cecf";
  std::string path(const std::string& tail) const { return "/session/" + session_ + tail; }
  void perform(const nlohmann::json& source) {
    command("POST", path("/actions"), {{"actions", nlohmann::json::array({source})}});
  }
  // One WebDriver command: its "value", or null with a failed expectation naming the error.
  nlohmann::json command(const std::string& method, const std::string& where, const nlohmann::json& body) {
    httplib::Result result = method == "GET"      ? http_.Get(where)
                             : method == "DELETE" ? http_.Delete(where)
                                                  : http_.Post(where, body.dump(), "application/json");
    if (!result) {
      ADD_FAILURE() << method << " " << where << ": no answer from chromedriver";
      return nullptr;
    }
    const nlohmann::json answer = nlohmann::json::parse(result->body, nullptr, false);
    if (result->status != 200) {
      ADD_FAILURE() << method << " " << where << ": " << result->status << " " << result->body.substr(0, 400);
      return nullptr;
    }
    return answer.is_object() && answer.contains("value") ? answer["value"] : nlohmann::json(nullptr);
  }

  int port_;
  ServerProcess driver_;
  httplib::Client http_;
  std::string session_;
};

}  // namespace pbs::test
