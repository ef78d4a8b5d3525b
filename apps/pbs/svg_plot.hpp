// Line plots as hand-written SVG (ρ(k) curves, error-vs-time curves), and whole-or-nothing text files.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pbs::cli {

struct PlotSeries {
  std::string name;                               // legend entry
  std::vector<std::pair<double, double>> points;  // (x, y) in drawing order; non-finite points, and
                                                  // points ≤ 0 on a log axis, are left out
  std::string color;                              // any SVG colour; empty: the next one of a palette
};

struct PlotAxis {
  std::string label;
  bool log = false;            // base-10 logarithmic scale, ticks at powers of ten
  std::optional<double> min;   // range; unset: fitted to the data (linear ranges padded to nice ticks)
  std::optional<double> max;
};

struct Plot {
  std::string title;
  PlotAxis x;
  PlotAxis y;
  std::vector<PlotSeries> series;  // one <polyline> each, drawn in order, listed in the legend
  int width = 800;                 // SVG size in pixels
  int height = 500;
};

// The plot as a standalone SVG document (starts with "<svg"): frame, ticks with labels, grid lines,
// axis labels, title, one polyline per series and a legend. Text is XML-escaped.
std::string renderSvg(const Plot& plot);

// Writes `text` to a temporary name beside `file`, then renames it into place. Throws
// std::runtime_error naming the file on failure (the temporary is removed).
void writeTextFile(const std::filesystem::path& file, const std::string& text);

}  // namespace pbs::cli
