// Progress of a long command on stderr: a bar redrawn in place on a terminal, a plain line every few
// seconds otherwise (logs, CI), nothing with --quiet.
#pragma once

#include <pbs/evaluation/progress_events.hpp>

#include <chrono>
#include <string>
#include <string_view>

namespace pbs::cli {

class ProgressMeter {
 public:
  enum class Style { Bar, Lines, Quiet };

  // Bar when stderr is a terminal, Lines when it is not, Quiet when `quiet`.
  static Style styleFor(bool quiet);

  ProgressMeter(std::string label, Style style);

  // `fraction` of the work is done (0…1; it drives the estimate of time left); `detail` is shown
  // after it (counts, say). Redraws at most a few times a second, so callers may call it often.
  void update(double fraction, std::string_view detail);

  // The final state, always shown (except when quiet), ending the bar's line.
  void finish(std::string_view detail);

 private:
  void show(double fraction, std::string_view detail, bool final);

  std::string label_;
  Style style_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point lastShown_;
};

// Library steps shown as progress meters, one per step, in the style styleFor(quiet) picks.
ProgressEvents progressMeters(bool quiet);

}  // namespace pbs::cli
