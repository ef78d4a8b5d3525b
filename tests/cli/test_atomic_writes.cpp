// Nothing lost: a `pbs surfelize` killed at any moment leaves the previous output whole (every file
// pbs writes goes to a temporary name first and is renamed into place).
#include "test_fixtures.hpp"
#include "test_support.hpp"

#include <pbs/scene/gltf_export.hpp>
#include <pbs/surfels/surfel_file.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

namespace pbs {
namespace {

using test::ScratchDir;

// Starts the pbs binary with `args` (stdout and stderr to /dev/null); returns its process id.
pid_t startPbs(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(126);
    std::vector<char*> argv{const_cast<char*>(PBS_BINARY)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(PBS_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

TEST(AtomicWrites, KilledSurfelizeLeavesTheOldFileWhole) {
  ScratchDir scratch;
  const auto scene = scratch / "groups.glb";
  writeGlb(test::twoIdenticalGroups(), scene);
  const auto out = scratch / "out.surfels";
  const std::vector<std::string> first = {"surfelize", scene.string(),  "-o",  out.string(),   "--min-triangles",
                                          "1000",      "--max-surfels", "500", "--resolution", "64",
                                          "--quiet"};
  int status = 0;
  waitpid(startPbs(first), &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const std::string old = test::readFile(out);
  ASSERT_GT(old.size(), 500u * kSurfelBytes);

  // A longer run with other options (a different file), killed after 0 … 1.5 s: before, during and
  // (for the longest delays, on a fast machine) after its write.
  const std::vector<std::string> second = {"surfelize", scene.string(),  "-o",    out.string(),   "--min-triangles",
                                           "1000",      "--max-surfels", "20000", "--resolution", "384",
                                           "--quiet"};
  int survivedWhole = 0, replacedWhole = 0;
  for (int delayMs : {0, 5, 20, 50, 100, 200, 400, 800, 1500}) {
    const pid_t pid = startPbs(second);
    std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    const std::string now = test::readFile(out);
    if (now == old) {
      ++survivedWhole;
    } else {
      // The run finished before the kill: the new file must be whole and readable.
      EXPECT_NO_THROW(readSurfelFile(out)) << "after " << delayMs << " ms";
      ++replacedWhole;
      test::writeFile(out, old);  // start the next round from the old file again
    }
  }
  EXPECT_GT(survivedWhole, 0);
  std::printf("killed runs: old file intact %d times, replaced by a whole new file %d times\n", survivedWhole,
              replacedWhole);
  // Whatever the kills left behind (temporaries), the output itself still reads.
  EXPECT_NO_THROW(readSurfelFile(out));
}

}  // namespace
}  // namespace pbs
