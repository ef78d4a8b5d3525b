// Shared helpers for the test suites: where the shared scenes are, scratch folders, running `pbs`.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sys/wait.h>
#include <string>

namespace pbs::test {

// ../shared/scenes (or $PBS_SCENES), or nothing when it is absent.
inline std::optional<std::filesystem::path> sharedScenesDir() {
  const char* env = std::getenv("PBS_SCENES");
  std::filesystem::path dir = env && *env ? std::filesystem::path(env) : std::filesystem::path(PBS_DEFAULT_SCENES);
  if (std::filesystem::is_directory(dir)) return dir;
  return std::nullopt;
}

// Skips the calling test with a clear message when the shared scenes are absent.
#define PBS_SHARED_SCENE(var, file)                                                    \
  const auto var##_dir = ::pbs::test::sharedScenesDir();                               \
  if (!var##_dir)                                                                      \
    GTEST_SKIP() << "shared scenes not found (set PBS_SCENES or put ../shared/scenes " \
                    "beside the repository)";                                          \
  const std::filesystem::path var = *var##_dir / (file)

// A fresh, empty folder under the system temp dir, removed when the object goes away.
class ScratchDir {
 public:
  ScratchDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("pbs-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

inline void writeFile(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string readFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct CommandResult {
  int status = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// `path` in single quotes, for a command line. Appended rather than "'" + … + "'": GCC 12 warns about
// that concatenation where it inlines it (-Wrestrict, a false positive).
inline std::string quoted(const std::filesystem::path& path) {
  std::string text = "'";
  text.append(path.string()).append("'");
  return text;
}

// Runs the built `pbs` with `args` (already shell-quoted), capturing stdout and stderr.
inline CommandResult runPbs(const std::string& args) {
  ScratchDir scratch;
  const auto outFile = scratch / "stdout";
  const auto errFile = scratch / "stderr";
  const std::string command = std::string("'") + PBS_BINARY + "' " + args + " >'" + outFile.string() + "' 2>'" +
                              errFile.string() + "' </dev/null";
  const int raw = std::system(command.c_str());
  CommandResult result;
  result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  result.out = readFile(outFile);
  result.err = readFile(errFile);
  return result;
}

}  // namespace pbs::test
