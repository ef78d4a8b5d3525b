// The measuring of `pbs analyze`: orderings of a captured root, or a file's arrays, and flat-patch spectra.
#include "pbs/evaluation/ordering_analysis.hpp"

#include "pbs/evaluation/report_numbers.hpp"

#include <pbs/scene/surface_area.hpp>
#include <pbs/surfels/surfel_nodes.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace pbs {
namespace {

// The k at which the mean nearest-neighbour distance is computed: each costs O(k), so every k would
// cost O(N²); 32 log-spaced values from 2 to N (the same spacing rho_mean uses) show its trend.
std::vector<std::size_t> logSpacedCounts(std::size_t n, int samples) {
  std::vector<std::size_t> ks;
  if (n < 2) return ks;
  const double span = std::log(double(n) / 2.0);
  for (int i = 0; i < samples; ++i) {
    const auto k = std::size_t(std::llround(2.0 * std::exp(span * i / std::max(1, samples - 1))));
    ks.push_back(std::clamp<std::size_t>(k, 2, n));
  }
  ks.push_back(n);
  std::sort(ks.begin(), ks.end());
  ks.erase(std::unique(ks.begin(), ks.end()), ks.end());
  return ks;
}

// A number of the prefix and spectrum tables: empty where not finite.
std::string prefixNumber(double value) {
  if (!std::isfinite(value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

double finalMeanNN(const MeasuredOrdering& m) { return m.meanNN.empty() ? 0.0 : m.meanNN.back().second; }

}  // namespace

void measureOrdering(MeasuredOrdering& m, std::span<const glm::vec3> points, std::span<const std::uint32_t> order) {
  m.count = order.size();
  m.minDistance = prefixMinDistances(points, order);
  m.summary = summarizeBlueNoise(points, order, m.area);
  for (std::size_t k : logSpacedCounts(order.size(), 32))
    m.meanNN.emplace_back(k, meanNearestNeighbourDistance(points, order, k));
}

nlohmann::json measuredJson(const MeasuredOrdering& m) {
  return {{"path", m.path},
          {"ordering", m.ordering},
          {"count", m.count},
          {"area", m.area},
          {"coverage", m.coverage},
          {"rho_min", m.summary.rhoMin},
          {"rho_mean", m.summary.rhoMean},
          {"d_min", m.count >= 2 ? m.minDistance.back() : 0.0},
          {"mean_nn", finalMeanNN(m)}};
}

std::string prefixCsv(const std::vector<MeasuredOrdering>& measured) {
  std::string csv = "ordering,path,array,k,d_min,rho,mean_nn\n";
  for (const MeasuredOrdering& m : measured) {
    std::string prefix = m.ordering;
    prefix.append(",").append(m.path).append(",");
    if (m.array >= 0) prefix.append(std::to_string(m.array));
    prefix.append(",");
    std::size_t next = 0;
    for (std::size_t k = 1; k <= m.count; ++k) {
      csv.append(prefix).append(std::to_string(k)).append(",");
      if (k >= 2)
        csv.append(prefixNumber(m.minDistance[k - 1])).append(",").append(prefixNumber(m.rho(k)));
      else
        csv.append(",");
      csv.append(",");
      if (next < m.meanNN.size() && m.meanNN[next].first == k) csv.append(prefixNumber(m.meanNN[next++].second));
      csv.append("\n");
    }
  }
  return csv;
}

PlotSeries rhoSeries(const MeasuredOrdering& m, std::string name) {
  PlotSeries series{.name = std::move(name), .points = {}, .color = {}};
  std::size_t k = 2;
  while (k <= m.count) {
    series.points.emplace_back(double(k), m.rho(k));
    const std::size_t step = k < 200 ? 1 : std::max<std::size_t>(1, std::size_t(double(k) * 0.01));
    if (k < m.count && k + step > m.count)
      k = m.count;
    else
      k += step;
  }
  return series;
}

std::vector<SpectrumResult> measureSpectra(const FlatSpectrumOptions& options) {
  std::vector<SpectrumResult> results;
  for (SurfelOrdering ordering : kAnalyzedOrderings) {
    const PointOrdering order = [ordering](std::span<const glm::vec3> points, std::uint32_t max, std::uint64_t seed) {
      return orderPoints(ordering, points, max, seed);
    };
    results.push_back({std::string(orderingName(ordering)), flatPatchSpectrum(order, options)});
  }
  return results;
}

std::string spectrumCsv(const std::vector<SpectrumResult>& spectra) {
  std::string csv = "ordering,points,frequency,power,anisotropy_db\n";
  for (const SpectrumResult& s : spectra) {
    const RadialSpectrum& r = s.spectrum.radial;
    for (std::size_t i = 0; i < r.frequency.size(); ++i) {
      csv.append(s.ordering).append(",").append(std::to_string(s.spectrum.count)).append(",");
      csv.append(prefixNumber(r.frequency[i])).append(",").append(prefixNumber(r.power[i])).append(",");
      csv.append(prefixNumber(r.anisotropy[i])).append("\n");
    }
  }
  return csv;
}

nlohmann::json spectrumJson(const std::vector<SpectrumResult>& spectra, const FlatSpectrumOptions& options) {
  nlohmann::json json = {{"candidates", options.candidates}, {"realizations", options.realizations}};
  for (const SpectrumResult& s : spectra) {
    const RadialSpectrum& r = s.spectrum.radial;
    const auto peak = std::max_element(r.power.begin(), r.power.end()) - r.power.begin();
    double anisotropy = 0.0;
    for (double a : r.anisotropy) anisotropy += a;
    json["points"] = s.spectrum.count;
    json["max_frequency"] = s.spectrum.maxFrequency;
    json["orderings"][s.ordering] = {
        {"low_frequency_power", s.spectrum.lowFrequencyPower},
        {"peak_power", r.power.empty() ? 0.0 : r.power[std::size_t(peak)]},
        {"peak_frequency", r.frequency.empty() ? 0.0 : r.frequency[std::size_t(peak)]},
        {"mean_anisotropy_db", r.anisotropy.empty() ? 0.0 : anisotropy / double(r.anisotropy.size())}};
  }
  return json;
}

Plot spectrumPlot(const std::vector<SpectrumResult>& spectra) {
  Plot plot;
  plot.title = "radial power of the first " + std::to_string(spectra.front().spectrum.count) + " points, flat patch";
  plot.x = {.label = "frequency (cycles across the patch)", .log = false, .min = 0.0, .max = {}};
  plot.y = {.label = "radially averaged power", .log = false, .min = 0.0, .max = {}};
  for (const SpectrumResult& s : spectra) {
    PlotSeries series{.name = s.ordering, .points = {}, .color = {}};
    for (std::size_t i = 0; i < s.spectrum.radial.frequency.size(); ++i)
      series.points.emplace_back(s.spectrum.radial.frequency[i], s.spectrum.radial.power[i]);
    plot.series.push_back(std::move(series));
  }
  return plot;
}

AnalyzedOrderings analyzeRoot(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t root,
                              const CaptureOptions& captureOptions, std::uint32_t max, std::uint64_t seed) {
  AnalyzedOrderings result;
  nlohmann::json& report = result.report;
  const CaptureResult capture = captureNode(scene, hierarchy, root, captureOptions);
  // Where the ordering sees them: each side of a thin surface apart.
  const std::vector<glm::vec3> points = orderingPositions(capture.surfels);
  const double area = subtreeSurfaceArea(scene, hierarchy, root);
  const std::string path = nodePath(scene, hierarchy, root);
  report["mode"] = "scene";
  report["root"] = {{"path", path},
                    {"name", scene.nodes[root].name},
                    {"triangles", hierarchy.subtreeTriangles[root]},
                    {"candidates", points.size()},
                    {"coverage", capture.coverage},
                    {"area", area},
                    {"resolution", captureOptions.resolution},
                    {"views", capture.views}};
  std::vector<MeasuredOrdering>& measured = result.measured;
  for (SurfelOrdering ordering : kAnalyzedOrderings) {
    MeasuredOrdering m;
    m.ordering = orderingName(ordering);
    m.path = path;
    m.area = area;
    m.coverage = capture.coverage;
    const auto start = std::chrono::steady_clock::now();
    const std::vector<std::uint32_t> order = orderPoints(ordering, points, max, seed);
    m.seconds = secondsSince(start);
    measureOrdering(m, points, order);
    measured.push_back(std::move(m));
  }
  for (const MeasuredOrdering& m : measured) {
    nlohmann::json entry = measuredJson(m);
    entry["seconds"] = m.seconds;
    report["nodes"].push_back(entry);
  }
  return result;
}

AnalyzedOrderings analyzeSurfelFile(SurfelFileReader& reader, std::optional<std::uint32_t> maxPrefix) {
  AnalyzedOrderings result;
  nlohmann::json& report = result.report;
  const std::string ordering(orderingName(reader.options().ordering));
  const auto arrays = reader.arrays();
  const auto nodes = reader.nodes();
  std::vector<MeasuredOrdering>& measured = result.measured;
  measured.resize(arrays.size());
  std::vector<std::vector<std::string>> users(arrays.size());
  for (const SurfelNodeRecord& node : nodes)
    if (node.array < arrays.size()) users[node.array].push_back(node.path);
  // Reading is sequential (one stream); measuring is parallel, a batch of arrays at a time.
  constexpr std::size_t kBatch = 64;
  for (std::size_t first = 0; first < arrays.size(); first += kBatch) {
    const std::size_t last = std::min(arrays.size(), first + kBatch);
    std::vector<std::vector<glm::vec3>> points(last - first);
    for (std::size_t a = first; a < last; ++a) {
      const std::uint32_t count = maxPrefix ? std::min(arrays[a].count, *maxPrefix) : arrays[a].count;
      points[a - first] = orderingPositions(reader.readPrefix(std::uint32_t(a), count));
    }
    tbb::parallel_for(first, last, [&](std::size_t a) {
      MeasuredOrdering& m = measured[a];
      m.ordering = ordering;
      m.array = std::int64_t(a);
      m.path = users[a].empty() ? "" : users[a].front();
      m.area = arrays[a].area;
      m.coverage = arrays[a].coverage;
      const std::vector<glm::vec3>& p = points[a - first];
      std::vector<std::uint32_t> order(p.size());
      std::iota(order.begin(), order.end(), 0u);
      measureOrdering(m, p, order);
    });
  }
  report["mode"] = "file";
  report["ordering"] = ordering;
  report["colors"] = surfelColorsName(reader.options().colors);
  report["seed"] = reader.options().seed;
  report["arrays"] = nlohmann::json::array();
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    nlohmann::json entry = measuredJson(measured[a]);
    entry.erase("path");
    entry["array"] = a;
    entry["stored_count"] = arrays[a].count;
    entry["packing"] = arrays[a].packing;
    entry["two_sided_share"] = arrays[a].twoSidedShare;
    entry["nodes"] = users[a];
    report["arrays"].push_back(entry);
  }
  report["nodes"] = nlohmann::json::array();
  for (const SurfelNodeRecord& node : nodes) {
    if (node.array >= arrays.size()) continue;
    nlohmann::json entry = measuredJson(measured[node.array]);
    entry["path"] = node.path;
    entry["array"] = node.array;
    report["nodes"].push_back(entry);
  }
  return result;
}

}  // namespace pbs
