// `pbs analyze SCENE|FILE.surfels [--json] [-o DIR]`: the blue-noise property of orderings, measured.
// A scene: its root is captured and ordered on the fly with every ordering; a .surfels file: every array
// in it, in its stored order. Per prefix k: d_min(k), ρ(k) and (at log-spaced k) the mean nearest-
// neighbour distance; summaries rho_min / rho_mean; and the flat-patch spectrum of each ordering.
#include "commands.hpp"
#include <pbs/evaluation/report_numbers.hpp>
#include "scene_report.hpp"
#include <pbs/evaluation/svg_plot.hpp>

#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/scene/surface_area.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/surfels/blue_noise_metrics.hpp>
#include <pbs/surfels/capture.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/point_spectrum.hpp>
#include <pbs/surfels/surfel_file.hpp>
#include <pbs/surfels/surfel_nodes.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>

namespace pbs::cli {
namespace {

constexpr SurfelOrdering kOrderings[] = {SurfelOrdering::Farthest, SurfelOrdering::Dart, SurfelOrdering::Random};

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

// One measured ordered point array.
struct Measured {
  std::string ordering;
  std::string path;         // the node (file mode: the first node using the array)
  std::int64_t array = -1;  // file mode: the array's index
  std::size_t count = 0;
  double area = 0.0;
  double coverage = 0.0;
  double seconds = 0.0;                                // time to order (scene mode)
  std::vector<double> minDistance;                     // d_min(k) at entry k-1
  std::vector<std::pair<std::size_t, double>> meanNN;  // (k, mean NN distance of the first k)
  BlueNoiseSummary summary;

  double rho(std::size_t k) const { return relativeRadius(minDistance[k - 1], k, area); }
};

void measure(Measured& m, std::span<const glm::vec3> points, std::span<const std::uint32_t> order) {
  m.count = order.size();
  m.minDistance = prefixMinDistances(points, order);
  m.summary = summarizeBlueNoise(points, order, m.area);
  for (std::size_t k : logSpacedCounts(order.size(), 32))
    m.meanNN.emplace_back(k, meanNearestNeighbourDistance(points, order, k));
}

double finalMeanNN(const Measured& m) { return m.meanNN.empty() ? 0.0 : m.meanNN.back().second; }

nlohmann::json measuredJson(const Measured& m) {
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

std::string csvNumber(double value) {
  if (!std::isfinite(value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

// One row per k = 1 … count of every measured array; d_min and rho are empty at k = 1 (no pair), mean_nn
// is filled only at the log-spaced k where it was computed.
std::string prefixCsv(const std::vector<Measured>& measured) {
  std::string csv = "ordering,path,array,k,d_min,rho,mean_nn\n";
  for (const Measured& m : measured) {
    std::string prefix = m.ordering;
    prefix.append(",").append(m.path).append(",");
    if (m.array >= 0) prefix.append(std::to_string(m.array));
    prefix.append(",");
    std::size_t next = 0;
    for (std::size_t k = 1; k <= m.count; ++k) {
      csv.append(prefix).append(std::to_string(k)).append(",");
      if (k >= 2)
        csv.append(csvNumber(m.minDistance[k - 1])).append(",").append(csvNumber(m.rho(k)));
      else
        csv.append(",");
      csv.append(",");
      if (next < m.meanNN.size() && m.meanNN[next].first == k) csv.append(csvNumber(m.meanNN[next++].second));
      csv.append("\n");
    }
  }
  return csv;
}

// ρ(k) on a log-k axis: every k up to 200, then ~400 log-spaced k (the plot's resolution).
PlotSeries rhoSeries(const Measured& m, std::string name) {
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

struct SpectrumResult {
  std::string ordering;
  FlatSpectrum spectrum;
};

std::vector<SpectrumResult> measureSpectra(const FlatSpectrumOptions& options) {
  std::vector<SpectrumResult> results;
  for (SurfelOrdering ordering : kOrderings) {
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
      csv.append(csvNumber(r.frequency[i])).append(",").append(csvNumber(r.power[i])).append(",");
      csv.append(csvNumber(r.anisotropy[i])).append("\n");
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

struct Options {
  std::string input;
  bool json = false;
  std::string output;
  std::string csv;
  std::uint32_t max = 10000;
  std::uint64_t seed = 1;
  std::uint32_t root = 0;
  CaptureOptions capture;
  bool noSpectrum = false;
  FlatSpectrumOptions spectrum;
  int threads = 0;
  bool maxGiven = false;
  std::string scene;  // file mode: the scene the file must belong to (checked by fingerprint)
};

bool isSurfelFile(const std::string& input) { return std::filesystem::path(input).extension() == ".surfels"; }

// Scene mode: capture a root, order it every way, measure each ordering.
std::vector<Measured> analyzeScene(const Options& options, nlohmann::json& report) {
  const LoadedScene loaded = loadAndAnalyze(options.input, LoadOptions{});
  if (options.root >= loaded.scene.roots.size())
    throw InputError(loaded.name, "root " + std::to_string(options.root),
                     "the scene has " + std::to_string(loaded.scene.roots.size()) + " roots");
  const std::uint32_t root = loaded.scene.roots[options.root];
  const CaptureResult capture = captureNode(loaded.scene, loaded.hierarchy, root, options.capture);
  // Where the ordering sees them: each side of a thin surface apart.
  const std::vector<glm::vec3> points = orderingPositions(capture.surfels);
  const double area = subtreeSurfaceArea(loaded.scene, loaded.hierarchy, root);
  const std::string path = nodePath(loaded.scene, loaded.hierarchy, root);
  report["mode"] = "scene";
  report["root"] = {{"path", path},
                    {"name", loaded.scene.nodes[root].name},
                    {"triangles", loaded.hierarchy.subtreeTriangles[root]},
                    {"candidates", points.size()},
                    {"coverage", capture.coverage},
                    {"area", area},
                    {"resolution", options.capture.resolution},
                    {"views", capture.views}};
  std::vector<Measured> measured;
  for (SurfelOrdering ordering : kOrderings) {
    Measured m;
    m.ordering = orderingName(ordering);
    m.path = path;
    m.area = area;
    m.coverage = capture.coverage;
    const auto start = std::chrono::steady_clock::now();
    const std::vector<std::uint32_t> order = orderPoints(ordering, points, options.max, options.seed);
    m.seconds = secondsSince(start);
    measure(m, points, order);
    measured.push_back(std::move(m));
  }
  for (const Measured& m : measured) {
    nlohmann::json entry = measuredJson(m);
    entry["seconds"] = m.seconds;
    report["nodes"].push_back(entry);
  }
  return measured;
}

// File mode: every distinct array once, in its stored order; every node record listed with its array's values.
std::vector<Measured> analyzeFile(const Options& options, nlohmann::json& report) {
  SurfelFileReader reader(options.input);
  if (!options.scene.empty()) reader.requireScene(sceneFingerprint(loadAndAnalyze(options.scene, LoadOptions{}).scene));
  const std::string ordering(orderingName(reader.options().ordering));
  const auto arrays = reader.arrays();
  const auto nodes = reader.nodes();
  std::vector<Measured> measured(arrays.size());
  std::vector<std::vector<std::string>> users(arrays.size());
  for (const SurfelNodeRecord& node : nodes)
    if (node.array < arrays.size()) users[node.array].push_back(node.path);
  // Reading is sequential (one stream); measuring is parallel, a batch of arrays at a time.
  constexpr std::size_t kBatch = 64;
  for (std::size_t first = 0; first < arrays.size(); first += kBatch) {
    const std::size_t last = std::min(arrays.size(), first + kBatch);
    std::vector<std::vector<glm::vec3>> points(last - first);
    for (std::size_t a = first; a < last; ++a) {
      const std::uint32_t count = options.maxGiven ? std::min(arrays[a].count, options.max) : arrays[a].count;
      points[a - first] = orderingPositions(reader.readPrefix(std::uint32_t(a), count));
    }
    tbb::parallel_for(first, last, [&](std::size_t a) {
      Measured& m = measured[a];
      m.ordering = ordering;
      m.array = std::int64_t(a);
      m.path = users[a].empty() ? "" : users[a].front();
      m.area = arrays[a].area;
      m.coverage = arrays[a].coverage;
      const std::vector<glm::vec3>& p = points[a - first];
      std::vector<std::uint32_t> order(p.size());
      std::iota(order.begin(), order.end(), 0u);
      measure(m, p, order);
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
  return measured;
}

Plot rhoPlot(const std::vector<Measured>& measured, const Options& options) {
  Plot plot;
  plot.x = {.label = "k (prefix length)", .log = true, .min = {}, .max = {}};
  plot.y = {.label = "relative radius rho(k)", .log = false, .min = 0.0, .max = {}};
  if (!isSurfelFile(options.input)) {
    plot.title = "rho(k) of " + options.input + ", root captured at " + std::to_string(options.capture.resolution);
    for (const Measured& m : measured) plot.series.push_back(rhoSeries(m, m.ordering));
    return plot;
  }
  // A file may hold thousands of arrays: the ten longest are drawn.
  std::vector<std::size_t> byCount(measured.size());
  std::iota(byCount.begin(), byCount.end(), std::size_t(0));
  std::stable_sort(byCount.begin(), byCount.end(),
                   [&](std::size_t a, std::size_t b) { return measured[a].count > measured[b].count; });
  byCount.resize(std::min<std::size_t>(byCount.size(), 10));
  plot.title = "rho(k) of " + std::filesystem::path(options.input).filename().string() + " (" +
               (measured.empty() ? std::string("no") : measured.front().ordering) + ", " +
               std::to_string(byCount.size()) + " of " + std::to_string(measured.size()) + " arrays)";
  for (std::size_t a : byCount) {
    const Measured& m = measured[a];
    plot.series.push_back(rhoSeries(m, "array " + std::to_string(a) + (m.path.empty() ? "" : " " + m.path)));
  }
  return plot;
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

void printText(const nlohmann::json& report) {
  if (report["mode"] == "scene") {
    const auto& r = report["root"];
    std::printf("%s: root %s (%s triangles), captured at %u: %s candidates, coverage %.3f, area %.6g\n",
                report["source"].get<std::string>().c_str(), r["path"].get<std::string>().c_str(),
                withThousands(r["triangles"].get<std::uint64_t>()).c_str(), r["resolution"].get<unsigned>(),
                withThousands(r["candidates"].get<std::uint64_t>()).c_str(), r["coverage"].get<double>(),
                r["area"].get<double>());
    std::printf("  %-9s %8s %10s %9s %9s %9s %10s %8s\n", "ordering", "count", "area", "coverage", "rho_min",
                "rho_mean", "mean_nn", "seconds");
    for (const auto& n : report["nodes"])
      std::printf("  %-9s %8s %10.4g %9.3f %9.3f %9.3f %10.4g %8.3f\n", n["ordering"].get<std::string>().c_str(),
                  withThousands(n["count"].get<std::uint64_t>()).c_str(), n["area"].get<double>(),
                  n["coverage"].get<double>(), n["rho_min"].get<double>(), n["rho_mean"].get<double>(),
                  n["mean_nn"].get<double>(), n["seconds"].get<double>());
  } else {
    std::printf("%s: %zu arrays, %zu nodes, ordering %s (seed %llu), %s colours\n",
                report["source"].get<std::string>().c_str(), report["arrays"].size(), report["nodes"].size(),
                report["ordering"].get<std::string>().c_str(),
                static_cast<unsigned long long>(report["seed"].get<std::uint64_t>()),
                report["colors"].get<std::string>().c_str());
    std::printf("  %-16s %6s %8s %10s %9s %9s %9s\n", "node", "array", "count", "area", "coverage", "rho_min",
                "rho_mean");
    for (const auto& n : report["nodes"])
      std::printf("  %-16s %6u %8s %10.4g %9.3f %9.3f %9.3f\n", n["path"].get<std::string>().c_str(),
                  n["array"].get<unsigned>(), withThousands(n["count"].get<std::uint64_t>()).c_str(),
                  n["area"].get<double>(), n["coverage"].get<double>(), n["rho_min"].get<double>(),
                  n["rho_mean"].get<double>());
  }
  if (report.contains("spectrum")) {
    const auto& s = report["spectrum"];
    std::printf("flat patch, ~%u ordered points of %u candidates, %u seeds: low-frequency power",
                s["points"].get<unsigned>(), s["candidates"].get<unsigned>(), s["realizations"].get<unsigned>());
    const char* separator = " ";
    for (SurfelOrdering ordering : kOrderings) {
      const std::string name(orderingName(ordering));
      std::printf("%s%s %.3f", separator, name.c_str(), s["orderings"][name]["low_frequency_power"].get<double>());
      separator = ", ";
    }
    std::printf(" (white noise 1; blue noise well below)\n");
  }
  if (report.contains("files"))
    for (const auto& [what, file] : report["files"].items()) std::printf("wrote %s\n", file.get<std::string>().c_str());
}

void run(const Options& options) {
  nlohmann::json report;
  report["source"] = options.input;
  std::vector<Measured> measured =
      isSurfelFile(options.input) ? analyzeFile(options, report) : analyzeScene(options, report);
  std::vector<SpectrumResult> spectra;
  if (!options.noSpectrum) {
    spectra = measureSpectra(options.spectrum);
    report["spectrum"] = spectrumJson(spectra, options.spectrum);
  }
  // Everything is measured before anything is written: a failure leaves no partial set of files.
  const auto write = [&](const std::string& key, const std::filesystem::path& file, const std::string& text) {
    writeTextFile(file, text);
    report["files"][key] = file.string();
  };
  if (!options.csv.empty()) write("csv", options.csv, prefixCsv(measured));
  if (!options.output.empty()) {
    const std::filesystem::path folder(options.output);
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error || !std::filesystem::is_directory(folder))
      throw std::runtime_error(folder.string() + ": cannot create the output folder");
    if (options.csv.empty()) write("csv", folder / "analyze.csv", prefixCsv(measured));
    write("svg", folder / "rho.svg", renderSvg(rhoPlot(measured, options)));
    if (!spectra.empty()) {
      write("spectrum_csv", folder / "spectrum.csv", spectrumCsv(spectra));
      write("spectrum_svg", folder / "spectrum.svg", renderSvg(spectrumPlot(spectra)));
    }
  }
  if (options.json)
    std::cout << report.dump(2) << "\n";
  else
    printText(report);
}

}  // namespace

void addAnalyzeCommand(CLI::App& app) {
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "analyze", "Measure the blue-noise property: rho(k) of a scene's root per ordering, or of a .surfels file");
  command->add_option("input", options->input, "a .gltf/.glb file, 'default', or a .surfels file")->required();
  command->add_flag("--json", options->json, "print JSON instead of text");
  command->add_option("--scene", options->scene, "with a .surfels file: fail unless it was made for this scene");
  command->add_option("-o,--output", options->output,
                      "folder for analyze.csv, rho.svg, spectrum.csv and spectrum.svg (created if missing)");
  command->add_option("--csv", options->csv,
                      "write the per-prefix table (k, d_min, rho, mean_nn) to this file (instead of DIR/analyze.csv)");
  command->add_option("--max", options->max, "surfels to order (scene); prefix measured (file: default whole arrays)")
      ->check(CLI::Range(1u, 100'000'000u))
      ->capture_default_str();
  command->add_option("--seed", options->seed, "seed of the orderings and of the spectrum's point sets")
      ->capture_default_str();
  command->add_option("--root", options->root, "which root of the scene to capture (index in the scene's roots)")
      ->capture_default_str();
  addCaptureOptions(*command, options->capture.resolution, options->capture.directions);
  command->add_flag("--no-spectrum", options->noSpectrum, "skip the flat-patch spectrum");
  command->add_option("--spectrum-points", options->spectrum.count, "points of each flat-patch sample")
      ->check(CLI::Range(16u, 65536u))
      ->capture_default_str();
  command
      ->add_option("--spectrum-candidates", options->spectrum.candidates,
                   "candidates the flat-patch points are ordered from")
      ->check(CLI::Range(16u, 10'000'000u))
      ->capture_default_str();
  command->add_option("--spectrum-seeds", options->spectrum.realizations, "flat-patch samples averaged")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  addThreadsOption(*command, options->threads);
  command->callback([options, command] {
    options->maxGiven = command->count("--max") > 0;
    options->spectrum.seed = options->seed;
    if (options->spectrum.count > options->spectrum.candidates)
      throw CLI::ValidationError("--spectrum-points", "exceeds --spectrum-candidates");
    runWithThreads(options->threads, [&] { run(*options); });
  });
}

}  // namespace pbs::cli
