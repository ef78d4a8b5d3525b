// SVG line and scatter plots written by hand (no plotting dependency), and atomic text output.
#include "pbs/evaluation/svg_plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <system_error>

namespace pbs {
namespace {

constexpr std::array<const char*, 10> kPalette = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                                  "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out.append("&amp;"); break;
      case '<': out.append("&lt;"); break;
      case '>': out.append("&gt;"); break;
      case '"': out.append("&quot;"); break;
      case '\'': out.append("&apos;"); break;
      default: out.push_back(c);
    }
  }
  return out;
}

std::string number(double value, const char* format = "%.1f") {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

bool usable(double value, bool log) { return std::isfinite(value) && (!log || value > 0.0); }

// The drawn range of an axis and its ticks, in data units.
struct Scale {
  bool log = false;
  double lo = 0.0, hi = 1.0;  // in transformed units (log10 for a log axis)
  std::vector<double> ticks;  // data values
  double transform(double v) const { return log ? std::log10(v) : v; }
  double fraction(double v) const { return (transform(v) - lo) / (hi - lo); }
};

Scale makeScale(const PlotAxis& axis, double dataMin, double dataMax) {
  Scale scale;
  scale.log = axis.log;
  double lo = axis.min.value_or(dataMin), hi = axis.max.value_or(dataMax);
  if (!usable(lo, axis.log) || !usable(hi, axis.log) || lo > hi) {
    lo = axis.log ? 1.0 : 0.0;
    hi = axis.log ? 10.0 : 1.0;
  }
  if (axis.log) {
    double a = std::log10(lo), b = std::log10(hi);
    if (!axis.min) a = std::floor(a);
    // A fitted top keeps a quarter decade above the data, so a marker's label beside it stays inside.
    if (!axis.max) b = std::max(std::ceil(b), b + 0.25);
    if (b <= a) b = a + 1.0;
    scale.lo = a;
    scale.hi = b;
    const double step = std::max(1.0, std::ceil((std::floor(b) - std::ceil(a)) / 10.0));
    for (double e = std::ceil(a); e <= b + 1e-9; e += step) scale.ticks.push_back(std::pow(10.0, e));
    return scale;
  }
  if (hi - lo <= 0.0) {
    const double pad = lo == 0.0 ? 1.0 : std::abs(lo) * 0.1;
    lo -= pad;
    hi += pad;
  }
  const double raw = (hi - lo) / 6.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * magnitude;
    if (step >= raw) break;
  }
  if (!axis.min) lo = std::floor(lo / step) * step;
  if (!axis.max) hi = std::ceil(hi / step) * step;
  scale.lo = lo;
  scale.hi = hi;
  for (double i = std::ceil(lo / step - 1e-9); i * step <= hi + step * 1e-9; i += 1.0) {
    const double t = i * step;
    scale.ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
  }
  return scale;
}

}  // namespace

std::string renderSvg(const Plot& plot) {
  const double width = std::max(plot.width, 200), height = std::max(plot.height, 150);
  const double left = 72, right = 20, top = plot.title.empty() ? 20 : 40, bottom = 56;
  const double plotW = width - left - right, plotH = height - top - bottom;

  double xMin = std::numeric_limits<double>::infinity(), xMax = -xMin, yMin = xMin, yMax = -xMin;
  for (const PlotSeries& s : plot.series) {
    for (const auto& [x, y] : s.points) {
      if (!usable(x, plot.x.log) || !usable(y, plot.y.log)) continue;
      xMin = std::min(xMin, x), xMax = std::max(xMax, x);
      yMin = std::min(yMin, y), yMax = std::max(yMax, y);
    }
  }
  for (const PlotMarker& m : plot.markers) {
    if (!usable(m.x, plot.x.log) || !usable(m.y, plot.y.log)) continue;
    xMin = std::min(xMin, m.x), xMax = std::max(xMax, m.x);
    yMin = std::min(yMin, m.y), yMax = std::max(yMax, m.y);
  }
  const Scale xs = makeScale(plot.x, xMin, xMax);
  const Scale ys = makeScale(plot.y, yMin, yMax);
  const auto px = [&](double x) { return left + xs.fraction(x) * plotW; };
  const auto py = [&](double y) { return top + (1.0 - ys.fraction(y)) * plotH; };

  std::string svg;
  svg.append("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + number(width, "%.0f") + "\" height=\"" +
             number(height, "%.0f") + "\" viewBox=\"0 0 " + number(width, "%.0f") + " " + number(height, "%.0f") +
             "\" font-family=\"sans-serif\" font-size=\"12\">\n");
  svg.append("<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n");
  svg.append("<defs><clipPath id=\"plot-area\"><rect x=\"" + number(left) + "\" y=\"" + number(top) + "\" width=\"" +
             number(plotW) + "\" height=\"" + number(plotH) + "\"/></clipPath></defs>\n");
  if (!plot.title.empty())
    svg.append("<text x=\"" + number(left + plotW / 2) + "\" y=\"24\" text-anchor=\"middle\" font-size=\"14\">" +
               escape(plot.title) + "</text>\n");

  // Grid lines and tick labels.
  const auto tickLabel = [](double v) { return number(v, "%g"); };
  for (double t : xs.ticks) {
    const double x = px(t);
    svg.append("<line x1=\"" + number(x) + "\" y1=\"" + number(top) + "\" x2=\"" + number(x) + "\" y2=\"" +
               number(top + plotH) + "\" stroke=\"#ddd\"/>\n");
    svg.append("<text x=\"" + number(x) + "\" y=\"" + number(top + plotH + 16) + "\" text-anchor=\"middle\">" +
               escape(tickLabel(t)) + "</text>\n");
  }
  for (double t : ys.ticks) {
    const double y = py(t);
    svg.append("<line x1=\"" + number(left) + "\" y1=\"" + number(y) + "\" x2=\"" + number(left + plotW) + "\" y2=\"" +
               number(y) + "\" stroke=\"#ddd\"/>\n");
    svg.append("<text x=\"" + number(left - 6) + "\" y=\"" + number(y + 4) + "\" text-anchor=\"end\">" +
               escape(tickLabel(t)) + "</text>\n");
  }
  svg.append("<rect x=\"" + number(left) + "\" y=\"" + number(top) + "\" width=\"" + number(plotW) + "\" height=\"" +
             number(plotH) + "\" fill=\"none\" stroke=\"black\"/>\n");
  svg.append("<text x=\"" + number(left + plotW / 2) + "\" y=\"" + number(height - 14) + "\" text-anchor=\"middle\">" +
             escape(plot.x.label) + "</text>\n");
  svg.append("<text transform=\"translate(18 " + number(top + plotH / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
             escape(plot.y.label) + "</text>\n");

  // Series, then the legend above them.
  std::vector<std::string> colors;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const PlotSeries& s = plot.series[i];
    colors.push_back(s.color.empty() ? kPalette[i % kPalette.size()] : s.color);
    std::string points;
    for (const auto& [x, y] : s.points) {
      if (!usable(x, plot.x.log) || !usable(y, plot.y.log)) continue;
      if (!points.empty()) points.push_back(' ');
      points.append(number(px(x))).append(",").append(number(py(y)));
    }
    svg.append("<polyline fill=\"none\" stroke=\"" + escape(colors.back()) +
               "\" stroke-width=\"1.5\" clip-path=\"url(#plot-area)\" points=\"" + points + "\"><title>" +
               escape(s.name) + "</title></polyline>\n");
  }
  for (const PlotMarker& m : plot.markers) {
    if (!usable(m.x, plot.x.log) || !usable(m.y, plot.y.log)) continue;
    const std::string color = escape(m.color.empty() ? std::string("black") : m.color);
    svg.append("<circle class=\"marker\" cx=\"" + number(px(m.x)) + "\" cy=\"" + number(py(m.y)) +
               "\" r=\"4\" fill=\"" + color + "\"><title>" + escape(m.label) + "</title></circle>\n");
    svg.append("<text x=\"" + number(px(m.x) + 6) + "\" y=\"" + number(py(m.y) - 6) + "\" font-size=\"10\" fill=\"" +
               color + "\">" + escape(m.label) + "</text>\n");
  }
  if (!plot.series.empty()) {
    std::size_t longest = 0;
    for (const PlotSeries& s : plot.series) longest = std::max(longest, s.name.size());
    const double boxW = 40 + 7.0 * double(longest), boxH = 8 + 16.0 * double(plot.series.size());
    const double bx = left + plotW - boxW - 8, by = top + 8;
    svg.append("<rect x=\"" + number(bx) + "\" y=\"" + number(by) + "\" width=\"" + number(boxW) + "\" height=\"" +
               number(boxH) + "\" fill=\"white\" fill-opacity=\"0.85\" stroke=\"#999\"/>\n");
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
      const double y = by + 14 + 16.0 * double(i);
      svg.append("<line x1=\"" + number(bx + 6) + "\" y1=\"" + number(y - 4) + "\" x2=\"" + number(bx + 28) +
                 "\" y2=\"" + number(y - 4) + "\" stroke=\"" + escape(colors[i]) + "\" stroke-width=\"2\"/>\n");
      svg.append("<text x=\"" + number(bx + 34) + "\" y=\"" + number(y) + "\">" + escape(plot.series[i].name) +
                 "</text>\n");
    }
  }
  svg.append("</svg>\n");
  return svg;
}

void writeTextFile(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::path temporary = file;
  temporary += ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (out) out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (out) out.flush();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw std::runtime_error(file.string() + ": cannot write the file");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, file, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(file.string() + ": cannot write the file (" + error.message() + ")");
  }
}

}  // namespace pbs
