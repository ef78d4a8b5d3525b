// ProgressMeter: throttled redraws, elapsed time and a linear estimate of the time left.
#include "progress_meter.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

namespace pbs::cli {
namespace {

using Clock = std::chrono::steady_clock;

std::string clockText(double seconds) {
  const long total = std::lround(std::max(0.0, seconds));
  char text[32];
  std::snprintf(text, sizeof text, "%ld:%02ld", total / 60, total % 60);
  return text;
}

}  // namespace

ProgressMeter::Style ProgressMeter::styleFor(bool quiet) {
  if (quiet) return Style::Quiet;
  return isatty(fileno(stderr)) ? Style::Bar : Style::Lines;
}

ProgressMeter::ProgressMeter(std::string label, Style style)
    : label_(std::move(label)), style_(style), start_(Clock::now()), lastShown_(start_) {}

void ProgressMeter::update(double fraction, std::string_view detail) {
  if (style_ == Style::Quiet) return;
  // A bar can redraw often; lines in a log should stay few.
  const auto interval = style_ == Style::Bar ? std::chrono::milliseconds(100) : std::chrono::milliseconds(5000);
  const auto now = Clock::now();
  if (now - lastShown_ < interval) return;
  lastShown_ = now;
  show(fraction, detail, false);
}

void ProgressMeter::finish(std::string_view detail) {
  if (style_ == Style::Quiet) return;
  show(1.0, detail, true);
}

void ProgressMeter::show(double fraction, std::string_view detail, bool final) {
  fraction = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  std::string timing = clockText(elapsed) + " elapsed";
  if (!final && fraction > 0.0)
    timing.append(", ").append(clockText(elapsed * (1.0 - fraction) / fraction)).append(" left");
  const int percent = int(std::floor(fraction * 100.0));
  if (style_ == Style::Bar) {
    constexpr int kWidth = 30;
    const int filled = int(std::lround(fraction * kWidth));
    const std::string bar = std::string(std::size_t(filled), '#') + std::string(std::size_t(kWidth - filled), '.');
    // \r returns to the line start, \x1b[K clears what a longer previous line left behind.
    std::fprintf(stderr, "\r%s [%s] %3d%% %.*s, %s\x1b[K%s", label_.c_str(), bar.c_str(), percent, int(detail.size()),
                 detail.data(), timing.c_str(), final ? "\n" : "");
  } else {
    std::fprintf(stderr, "%s: %3d%% %.*s, %s\n", label_.c_str(), percent, int(detail.size()), detail.data(),
                 timing.c_str());
  }
  std::fflush(stderr);
}

ProgressEvents progressMeters(bool quiet) {
  // Shared by the three callbacks (ProgressEvents is copied); a step's meter lives from begin to end.
  auto meters = std::make_shared<std::map<std::string, ProgressMeter>>();
  const ProgressMeter::Style style = ProgressMeter::styleFor(quiet);
  return {
      .begin = [meters, style](const std::string& step) { meters->insert_or_assign(step, ProgressMeter(step, style)); },
      .update =
          [meters](const std::string& step, double fraction, const std::string& detail) {
            if (auto found = meters->find(step); found != meters->end()) found->second.update(fraction, detail);
          },
      .end =
          [meters](const std::string& step, const std::string& detail) {
            if (auto found = meters->find(step); found != meters->end()) {
              found->second.finish(detail);
              meters->erase(found);
            }
          }};
}

}  // namespace pbs::cli
