// The blue-noise property of orderings, measured (`pbs analyze`): a scene's root captured and ordered every
// way, or every array of a .surfels file in its stored order. Per prefix k: d_min(k), ρ(k) and (at
// log-spaced k) the mean nearest-neighbour distance; summaries rho_min / rho_mean; and the flat-patch
// spectrum of each ordering.
#pragma once

#include "pbs/evaluation/svg_plot.hpp"

#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>
#include <pbs/surfels/blue_noise_metrics.hpp>
#include <pbs/surfels/capture.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/point_spectrum.hpp>
#include <pbs/surfels/surfel_file.hpp>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace pbs {

// The orderings a scene's root is ordered with, in the order they are reported.
inline constexpr SurfelOrdering kAnalyzedOrderings[] = {SurfelOrdering::Farthest, SurfelOrdering::Dart,
                                                        SurfelOrdering::Random};

// One measured ordered point array.
struct MeasuredOrdering {
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

// Measures the first order.size() points of `points` in that order (m.area set before).
void measureOrdering(MeasuredOrdering& m, std::span<const glm::vec3> points, std::span<const std::uint32_t> order);

// path, ordering, count, area, coverage, rho_min, rho_mean, d_min (of the whole prefix), mean_nn.
nlohmann::json measuredJson(const MeasuredOrdering& m);

// One row per k = 1 … count of every measured array; d_min and rho are empty at k = 1 (no pair), mean_nn
// is filled only at the log-spaced k where it was computed.
std::string prefixCsv(const std::vector<MeasuredOrdering>& measured);

// ρ(k) on a log-k axis: every k up to 200, then ~400 log-spaced k (the plot's resolution).
PlotSeries rhoSeries(const MeasuredOrdering& m, std::string name);

struct SpectrumResult {
  std::string ordering;
  FlatSpectrum spectrum;
};

// Each of kAnalyzedOrderings on flat patches, its radially averaged power.
std::vector<SpectrumResult> measureSpectra(const FlatSpectrumOptions& options);
std::string spectrumCsv(const std::vector<SpectrumResult>& spectra);
nlohmann::json spectrumJson(const std::vector<SpectrumResult>& spectra, const FlatSpectrumOptions& options);
Plot spectrumPlot(const std::vector<SpectrumResult>& spectra);

struct AnalyzedOrderings {
  std::vector<MeasuredOrdering> measured;
  nlohmann::json report;  // what `pbs analyze --json` prints of them ("mode", then per mode its entries)
};

// Scene mode: `root` captured with `capture`, ordered with every ordering (up to `max` points, `seed`),
// each measured and timed.
AnalyzedOrderings analyzeRoot(const Scene& scene, const Hierarchy& hierarchy, std::uint32_t root,
                              const CaptureOptions& capture, std::uint32_t max, std::uint64_t seed);

// File mode: every distinct array once, in its stored order (its first `maxPrefix` surfels when set);
// every node record listed with its array's values.
AnalyzedOrderings analyzeSurfelFile(SurfelFileReader& reader, std::optional<std::uint32_t> maxPrefix = std::nullopt);

}  // namespace pbs
