// Line and scatter plots as hand-written SVG (ρ(k) curves, error against time), and whole-or-nothing
// text files.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pbs {

struct PlotSeries {
  std::string name;                               // legend entry
  std::vector<std::pair<double, double>> points;  // (x, y) in drawing order; non-finite points, and
                                                  // points ≤ 0 on a log axis, are left out
  std::string color;                              // any SVG colour; empty: the next one of a palette
};

// One labelled point of a scatter plot (a <circle class="marker">, its label beside it).
struct PlotMarker {
  double x = 0.0;
  double y = 0.0;
  std::string label;  // drawn beside the point and as its tooltip
  std::string color;  // any SVG colour; empty: black
};

struct PlotAxis {
  std::string label;
  bool log = false;           // base-10 logarithmic scale, ticks at powers of ten
  std::optional<double> min;  // range; unset: fitted to the data (linear ranges padded to nice ticks)
  std::optional<double> max;
};

struct Plot {
  std::string title;
  PlotAxis x;
  PlotAxis y;
  std::vector<PlotSeries> series;   // one <polyline> each, drawn in order, listed in the legend
  std::vector<PlotMarker> markers;  // drawn over the series, not in the legend; non-finite ones (and ≤ 0
                                    // on a log axis) are left out; fitted ranges include them
  int width = 800;                  // SVG size in pixels
  int height = 500;
};

// The plot as a standalone SVG document (starts with "<svg"): frame, ticks with labels, grid lines,
// axis labels, title, one polyline per series, the markers and a legend. Text is XML-escaped.
std::string renderSvg(const Plot& plot);

// Writes `text` to a temporary name beside `file`, then renames it into place. Throws
// std::runtime_error naming the file on failure (the temporary is removed).
void writeTextFile(const std::filesystem::path& file, const std::string& text);

}  // namespace pbs
