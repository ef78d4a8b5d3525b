// Entry point of the `pbs` command line: dispatches to the subcommands and turns errors into one
// `error:` line with exit status 1 (2 for bad usage); a command may end with its own status (CommandExit).
#include "commands.hpp"

#include <exception>
#include <iostream>

int main(int argc, char** argv) {
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
