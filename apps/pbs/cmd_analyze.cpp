// `pbs analyze SCENE|FILE.surfels [--json] [-o DIR]`: the blue-noise property of orderings, measured
// (pbs/evaluation/ordering_analysis.hpp), printed, and written as CSV tables and SVG plots.
#include "commands.hpp"
#include "scene_report.hpp"

#include <pbs/evaluation/ordering_analysis.hpp>
#include <pbs/evaluation/report_numbers.hpp>
#include <pbs/evaluation/svg_plot.hpp>
#include <pbs/raster/thread_arena.hpp>
#include <pbs/scene/input_error.hpp>
#include <pbs/scene/mesh_closure.hpp>
#include <pbs/scene/scene_fingerprint.hpp>
#include <pbs/surfels/surfel_file.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numeric>
#include <optional>

namespace pbs::cli {
namespace {

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
AnalyzedOrderings analyzeScene(const Options& options) {
  const LoadedScene loaded = loadAndAnalyze(options.input, LoadOptions{});
  if (options.root >= loaded.scene.roots.size())
    throw InputError(loaded.name, "root " + std::to_string(options.root),
                     "the scene has " + std::to_string(loaded.scene.roots.size()) + " roots");
  CaptureOptions capture = options.capture;
  const std::vector<MeshClosure> closures = meshClosures(loaded.scene);  // as surfelize draws each mesh
  capture.meshClosures = closures;
  return analyzeRoot(loaded.scene, loaded.hierarchy, loaded.scene.roots[options.root], capture, options.max,
                     options.seed);
}

// File mode: every distinct array once, in its stored order.
AnalyzedOrderings analyzeFile(const Options& options) {
  SurfelFileReader reader(options.input);
  if (!options.scene.empty())
    reader.requireScene(
        sceneFingerprint(loadAndAnalyze(options.scene, LoadOptions{reader.options().octreeLeafTriangles}).scene));
  return analyzeSurfelFile(reader, options.maxGiven ? std::optional(options.max) : std::nullopt);
}

Plot rhoPlot(const std::vector<MeasuredOrdering>& measured, const Options& options) {
  Plot plot;
  plot.x = {.label = "k (prefix length)", .log = true, .min = {}, .max = {}};
  plot.y = {.label = "relative radius rho(k)", .log = false, .min = 0.0, .max = {}};
  if (!isSurfelFile(options.input)) {
    plot.title = "rho(k) of " + options.input + ", root captured at " + std::to_string(options.capture.resolution);
    for (const MeasuredOrdering& m : measured) plot.series.push_back(rhoSeries(m, m.ordering));
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
    const MeasuredOrdering& m = measured[a];
    plot.series.push_back(rhoSeries(m, "array " + std::to_string(a) + (m.path.empty() ? "" : " " + m.path)));
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
    for (SurfelOrdering ordering : kAnalyzedOrderings) {
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
  AnalyzedOrderings analyzed = isSurfelFile(options.input) ? analyzeFile(options) : analyzeScene(options);
  const std::vector<MeasuredOrdering>& measured = analyzed.measured;
  nlohmann::json& report = analyzed.report;
  report["source"] = options.input;
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
