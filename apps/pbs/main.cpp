// Entry point of the `pbs` command line: dispatches to the subcommands and turns errors into one
// `error:` line with exit status 1 (2 for bad usage); a command may end with its own status (CommandExit).
#include "commands.hpp"

#include <malloc.h>

#include <exception>
#include <iostream>

namespace {

// Frames allocate images and G-buffer channels of 8 to 33 MB at 1920×1080. glibc maps a block that large
// afresh and unmaps it when freed, until its threshold adapts, and gives freed heap back beyond twice that
// threshold, so a renderer's first frames faulted every page of its buffers in again: about 100 ms on top of
// a 30 ms Embree frame on the 2-core VM, charged to whichever renderer drew first (pbs eval's peer). Blocks
// up to 32 MiB (glibc's largest threshold) come from the heap, and up to 128 MiB of freed heap is kept for
// the next frame's.
void keepFrameBuffersMapped() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 128 << 20);
}

}  // namespace

int main(int argc, char** argv) {
  keepFrameBuffersMapped();
  CLI::App app{"pbs: Progressive Blue Surfels on the CPU"};
  app.require_subcommand(1);
  pbs::cli::addDemoCommand(app);
  pbs::cli::addInfoCommand(app);
  pbs::cli::addGenerateCommand(app);
  pbs::cli::addCaptureCommand(app);
  pbs::cli::addAnalyzeCommand(app);
  pbs::cli::addPrefixesCommand(app);
  pbs::cli::addSurfelizeCommand(app);
  pbs::cli::addMergeCommand(app);
  pbs::cli::addRenderCommand(app);
  pbs::cli::addViewCommand(app);
  pbs::cli::addCalibrateCommand(app);
  pbs::cli::addCompareCommand(app);
  pbs::cli::addEvalCommand(app);
  pbs::cli::addFigureCommand(app);
  pbs::cli::addBenchCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const pbs::cli::CommandExit& e) {
    return e.status;
  } catch (const CLI::ParseError& e) {
    std::cerr << "error: " << e.what() << " (see pbs --help)\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
