// `pbs bench raster [SCENE] [--json]`: the rasterizer against llvmpipe and Embree, same run (with
// --sweep, on terrains of several triangle sizes); `pbs bench order`: the orderings.
#include "bench/order_bench.hpp"
#include "bench/raster_bench.hpp"
#include "bench/raster_sweep.hpp"
#include "commands.hpp"
#include "scene_report.hpp"

#include <pbs/evaluation/report_numbers.hpp>
#include <pbs/evaluation/svg_plot.hpp>
#include <pbs/raster/raster_limits.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

namespace pbs::cli {
namespace {

// A contender's figure `key`, scaled and printed by `format`, or that it is missing (and why, if `why`).
std::string figure(const nlohmann::json& entry, const char* key, const char* format, double scale = 1.0,
                   bool why = true) {
  if (entry.contains("missing")) return why ? "missing (" + entry["missing"].get<std::string>() + ")" : "missing";
  char text[64];
  std::snprintf(text, sizeof text, format, scale * entry[key].get<double>());
  return text;
}

std::string seconds(const nlohmann::json& entry) { return figure(entry, "seconds", "%.4f s"); }
std::string mpoints(const nlohmann::json& entry) { return figure(entry, "mpoints_per_s", "%.1f Mpoints/s"); }

void printRasterReport(const nlohmann::json& r) {
  const auto& c = r["capture"];
  std::printf("capture: 8 orthographic views at %u², depth + colour + position + normal\n",
              r["resolution"].get<unsigned>());
  std::printf("(%d interleaved rounds: medians of the times; ratios are medians of the per-round ratios)\n",
              r["repeats"].get<int>());
  std::printf("  pbs, 1 thread     %s\n", seconds(c["pbs_1_thread"]).c_str());
  std::printf("  pbs, %d threads    %s  (%.2fx one thread)\n", r["threads"].get<int>(), seconds(c["pbs"]).c_str(),
              c["thread_scaling"].get<double>());
  if (c["llvmpipe"].contains("missing"))
    std::printf("  llvmpipe          %s\n", seconds(c["llvmpipe"]).c_str());
  else
    std::printf(
        "  llvmpipe          %s  (pbs %.1fx faster; same channels, positions agree on %.2f%% of pixels, "
        "colours within 4/255 on %.2f%%)\n",
        seconds(c["llvmpipe"]).c_str(), c["vs_llvmpipe"].get<double>(),
        100.0 * c["llvmpipe"]["position_agreement"].get<double>(),
        100.0 * c["llvmpipe"]["color_agreement"].get<double>());
  std::printf("  embree packets    %s  (pbs %.1fx faster; BVH build %.4f s apart)\n", seconds(c["embree"]).c_str(),
              c["vs_embree"].get<double>(), c["embree"]["bvh_seconds"].get<double>());
  for (const char* size : {"1px", "4px"}) {
    const auto& p = r["points"][size];
    std::printf("points: %s points of %s\n", withThousands(r["point_count"].get<std::uint64_t>()).c_str(), size);
    std::printf("  pbs, 1 thread     %s\n", mpoints(p["pbs_1_thread"]).c_str());
    std::printf("  pbs, %d threads    %s  (%.2fx one thread)\n", r["threads"].get<int>(), mpoints(p["pbs"]).c_str(),
                p["thread_scaling"].get<double>());
    if (p["llvmpipe"].contains("missing"))
      std::printf("  llvmpipe          %s\n", mpoints(p["llvmpipe"]).c_str());
    else
      std::printf("  llvmpipe          %s  (pbs %.1fx faster)\n", mpoints(p["llvmpipe"]).c_str(),
                  p["vs_llvmpipe"].get<double>());
  }
}

// A time in milliseconds, or "missing" for a peer that could not run (the table says why below it).
std::string milliseconds(const nlohmann::json& entry) { return figure(entry, "seconds", "%.2f", 1e3, false); }

std::string ratio(const nlohmann::json& value) {
  if (value.is_null()) return "-";
  char text[64];
  std::snprintf(text, sizeof text, "%.1fx", value.get<double>());
  return text;
}

void printSweepReport(const nlohmann::json& r) {
  std::printf("capture sweep: %s, %d orthographic views at %u², depth + colour + position + normal, %d threads\n",
              r["mesh"].get<std::string>().c_str(), r["views"].get<int>(), r["resolution"].get<unsigned>(),
              r["threads"].get<int>());
  std::printf(
      "(%d interleaved rounds: medians of the times; ratios are medians of the per-round ratios;\n"
      " throughput counts each triangle once per view)\n",
      r["repeats"].get<int>());
  std::printf("%10s %12s %10s %10s %12s %9s %11s %12s\n", "px/tri", "triangles", "pbs ms", "Embree ms", "llvmpipe ms",
              "vs Embree", "vs llvmpipe", "pbs Mtri/s");
  for (const nlohmann::json& size : r["sizes"]) {
    const nlohmann::json& c = size["capture"];
    std::printf("%10.4g %12s %10s %10s %12s %9s %11s %12.1f\n", size["pixels_per_triangle"].get<double>(),
                withThousands(size["triangles"].get<std::uint64_t>()).c_str(), milliseconds(c["pbs"]).c_str(),
                milliseconds(c["embree"]).c_str(), milliseconds(c["llvmpipe"]).c_str(), ratio(c["vs_embree"]).c_str(),
                ratio(c["vs_llvmpipe"]).c_str(), size["mtriangles_per_s"]["pbs"].get<double>());
  }
  const nlohmann::json& first = r["sizes"].front()["capture"]["llvmpipe"];
  if (first.contains("missing")) std::printf("llvmpipe missing: %s\n", first["missing"].get<std::string>().c_str());
}

void printOrderReport(const nlohmann::json& r) {
  std::printf("ordering %s of %s points on a unit sphere, one thread\n",
              withThousands(r["max"].get<std::uint64_t>()).c_str(),
              withThousands(r["points"].get<std::uint64_t>()).c_str());
  for (const char* name : {"farthest", "dart", "random"}) {
    const auto& o = r[name];
    std::printf("  %-9s %8.3f s  rho_min %.3f  rho_mean %.3f  (%s surfels)\n", name, o["seconds"].get<double>(),
                o["rho_min"].get<double>(), o["rho_mean"].get<double>(),
                withThousands(o["count"].get<std::uint64_t>()).c_str());
  }
  std::printf("  dart takes %.1fx the time of farthest\n", r["ratios"]["dart_over_farthest_seconds"].get<double>());
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  struct Options {
    std::string scene = "default";
    bool json = false;
    bool sweep = false;
    std::string plot;
    bench::RasterSweepOptions sweepOptions;  // its raster options serve the single scene too
  };
  auto options = std::make_shared<Options>();
  CLI::App* bench = app.add_subcommand("bench", "Measure pbs against its peers");
  bench->require_subcommand(1);
  CLI::App* raster = bench->add_subcommand("raster", "capture views and point splats vs llvmpipe and Embree");
  CLI::Option* scene =
      raster->add_option("scene", options->scene, "a .gltf/.glb file, or 'default'")->capture_default_str();
  raster->add_flag("--json", options->json, "print JSON instead of text");
  CLI::Option* sweep =
      raster->add_flag("--sweep", options->sweep, "the capture alone, on terrains of each --sizes triangle size")
          ->excludes(scene);
  raster->add_option("--resolution", options->sweepOptions.raster.resolution, "capture and point image size")
      ->check(CLI::Range(1u, kMaxViewportSize))
      ->capture_default_str();
  raster->add_option("--points", options->sweepOptions.raster.points, "number of random points")
      ->check(CLI::Range(1, 1'000'000'000))
      ->excludes(sweep)
      ->capture_default_str();
  raster->add_option("--repeat", options->sweepOptions.raster.repeats, "timed runs per measurement (median reported)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  raster->add_option("--sizes", options->sweepOptions.pixelsPerTriangle, "--sweep's mean pixels per triangle")
      ->delimiter(',')
      ->check(CLI::PositiveNumber)
      ->needs(sweep)
      ->capture_default_str();
  raster->add_option("--plot", options->plot, "--sweep: write the throughput plot to this SVG file")->needs(sweep);
  addThreadsOption(*raster, options->sweepOptions.raster.threads);
  raster->callback([options] {
    if (options->sweep) {
      const nlohmann::json report = bench::benchRasterSweep(options->sweepOptions);
      if (!options->plot.empty()) writeTextFile(options->plot, renderSvg(bench::rasterSweepPlot(report)));
      if (options->json)
        std::cout << report.dump(2) << "\n";
      else
        printSweepReport(report);
      return;
    }
    const LoadedScene loaded = loadAndAnalyze(options->scene, LoadOptions{});
    const nlohmann::json report = bench::benchRaster(loaded.scene, loaded.hierarchy, options->sweepOptions.raster);
    if (options->json)
      std::cout << report.dump(2) << "\n";
    else
      printRasterReport(report);
  });

  struct OrderOptions {
    std::uint64_t points = 1'000'000;
    std::uint32_t max = 100'000;
    std::uint64_t seed = 1;
    bool json = false;
  };
  auto order = std::make_shared<OrderOptions>();
  CLI::App* orderCommand = bench->add_subcommand("order", "farthest, dart and random orderings on a sphere");
  orderCommand->add_option("--points", order->points, "initial points on the unit sphere")
      ->check(CLI::Range(1, 100'000'000))
      ->capture_default_str();
  orderCommand->add_option("--max", order->max, "surfels to order")
      ->check(CLI::Range(1, 100'000'000))
      ->capture_default_str();
  orderCommand->add_option("--seed", order->seed, "seed of the points and the orderings")->capture_default_str();
  orderCommand->add_flag("--json", order->json, "print JSON instead of text");
  orderCommand->callback([order] {
    nlohmann::json report = bench::benchOrder(order->points, order->max, order->seed);
    report["points"] = order->points;
    report["max"] = order->max;
    if (order->json)
      std::cout << report.dump(2) << "\n";
    else
      printOrderReport(report);
  });
}

}  // namespace pbs::cli
