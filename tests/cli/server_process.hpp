// A server the tests start as its own process (`pbs view`, chromedriver): started with posix_spawn, its
// output in files, waited for until it prints what the test needs, and stopped by its process id (also
// when the test fails half-way: the destructor kills what is still running).
#pragma once

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <optional>
#include <regex>
#include <spawn.h>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <vector>

extern char** environ;

namespace pbs::test {

class ServerProcess {
 public:
  // Runs `program` with `args`; stdout and stderr go to files in a scratch folder.
  ServerProcess(const std::string& program, const std::vector<std::string>& args) {
    std::vector<std::string> argv{program};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> pointers;
    for (std::string& arg : argv) pointers.push_back(arg.data());
    pointers.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&files, 1, (scratch_ / "stdout").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&files, 2, (scratch_ / "stderr").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (posix_spawn(&pid_, program.c_str(), &files, nullptr, pointers.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&files);
  }
  ~ServerProcess() {
    if (running()) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  bool started() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }
  bool running() const { return pid_ > 0 && !status_; }
  std::string out() const { return readFile(scratch_ / "stdout"); }
  std::string err() const { return readFile(scratch_ / "stderr"); }

  // The first match of `pattern` in stdout (its first group, else the whole match), waiting up to
  // `seconds` for it; nothing if the process ends first or the time runs out.
  std::optional<std::string> waitForOutput(const std::string& pattern, double seconds) {
    const std::regex expression(pattern);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < deadline) {
      std::smatch match;
      const std::string text = out();
      if (std::regex_search(text, match, expression)) return match.size() > 1 ? match[1].str() : match[0].str();
      if (reaped()) return std::nullopt;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return std::nullopt;
  }

  // Sends `signal` and waits up to `seconds` for the process to end: its exit status (128 + the signal
  // that ended it), or nothing if it is still running.
  std::optional<int> stop(int signal, double seconds) {
    if (running()) ::kill(pid_, signal);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!reaped() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return status_;
  }

 private:
  bool reaped() {
    if (status_) return true;
    int raw = 0;
    if (pid_ <= 0 || ::waitpid(pid_, &raw, WNOHANG) != pid_) return false;
    status_ = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
    return true;
  }

  ScratchDir scratch_;
  pid_t pid_ = -1;
  std::optional<int> status_;
};

// `pbs view ARGS --port 0` started and waited for: its port, or a failed expectation.
struct ViewServer {
  explicit ViewServer(const std::vector<std::string>& args) : process(PBS_BINARY, withPort(args)) {
    const std::optional<std::string> found = process.waitForOutput(R"(http://127\.0\.0\.1:(\d+)/)", 120.0);
    EXPECT_TRUE(found) << "pbs view did not print its address; stderr: " << process.err();
    if (found) port = std::stoi(*found);
  }
  static std::vector<std::string> withPort(std::vector<std::string> args) {
    args.insert(args.end(), {"--port", "0"});
    return args;
  }
  ServerProcess process;
  int port = 0;
};

}  // namespace pbs::test
