// `pbs compare A B [--json] [--max-flip …]`: how far image A is from the reference B (PSNR over the
// whole image and its foreground, SSIM, FLIP, holes and bloat), and an image test's pass or fail.
#include "commands.hpp"
#include "image_files.hpp"
#include <pbs/evaluation/report_numbers.hpp>

#include <pbs/raster/flip.hpp>
#include <pbs/raster/image_metrics.hpp>
#include <pbs/raster/thread_arena.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

namespace pbs::cli {
namespace {

std::string sizeText(const RgbaImage& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

// PSNR is +infinity for identical images: written as null.
nlohmann::json differenceJson(const ImageDifference& d, const RgbaImage& a, const CompareOptions& options) {
  return {{"rmse", d.rmse},
          {"psnr", finiteOrNull(d.psnr)},
          {"foreground_rmse", d.foregroundRmse},
          {"foreground_psnr", finiteOrNull(d.foregroundPsnr)},
          {"foreground_pixels", d.foregroundPixels},
          {"ssim", d.ssim},
          {"flip_mean", d.flipMean},
          {"flip_median", d.flipMedian},
          {"flip_max", d.flipMax},
          {"flip_foreground_mean", d.flipForegroundMean},
          {"hole_fraction", d.holeFraction},
          {"bloat_fraction", d.bloatFraction},
          {"coverage_a", d.coverageA},
          {"coverage_b", d.coverageB},
          {"width", a.width},
          {"height", a.height},
          {"background", {options.background.r, options.background.g, options.background.b}},
          {"pixels_per_degree", options.pixelsPerDegree}};
}

void printDifference(const ImageDifference& d, const RgbaImage& a) {
  std::printf(
      "flip %.4f (median %.4f, max %.3f, foreground %.4f)  psnr %s dB (foreground %s dB)  ssim %.4f  "
      "holes %.4g  bloat %.4g (%s; coverage A %.0f px, B %.0f px)\n",
      d.flipMean, d.flipMedian, d.flipMax, d.flipForegroundMean, decibelText(d.psnr).c_str(),
      decibelText(d.foregroundPsnr).c_str(), d.ssim, d.holeFraction, d.bloatFraction, sizeText(a).c_str(), d.coverageA,
      d.coverageB);
}

}  // namespace

void addCompareCommand(CLI::App& app) {
  struct Options {
    std::string a;
    std::string b;
    glm::vec3 background{1.0f};
    double pixelsPerDegree = kDefaultPixelsPerDegree;
    std::string flipMap;
    ImageThresholds thresholds;
    bool json = false;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "compare",
      "Compare image A with the reference B, both composited over one background: FLIP, PSNR over the whole image "
      "and over the foreground (pixels either covers), luminance SSIM, holes (B covers, A does not) and bloat (A "
      "covers, B does not) as fractions of B's coverage. With limits (--max-flip, …) it is an image test: exit "
      "status 3 when one is broken (1: bad input, 2: bad usage)");
  command->add_option("a", options->a, "image A (PNG, EXR, …; alpha is coverage), e.g. a surfel render")->required();
  command->add_option("b", options->b, "the reference B, of the same size")->required();
  addCompareOptions(*command, options->background, options->pixelsPerDegree);
  command->add_option("--flip-map", options->flipMap, "write FLIP's per-pixel error as a colour-scaled PNG");
  ImageThresholds& limits = options->thresholds;
  command->add_option("--max-flip", limits.maxFlip, "fail when the mean FLIP is above this")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--min-psnr", limits.minPsnr, "fail when the whole image's PSNR (dB) is below this");
  command->add_option("--min-foreground-psnr", limits.minForegroundPsnr,
                      "fail when the foreground's PSNR (dB) is below this");
  command->add_option("--max-holes", limits.maxHoles, "fail when the hole fraction is above this")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--max-bloat", limits.maxBloat, "fail when the bloat fraction is above this")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--json", options->json,
                    "print JSON instead of text (psnr null when identical; failed limits under \"failed\")");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    bool passed = true;
    runWithThreads(options->threads, [&] {
      const CompareOptions compare{.background = options->background,
                                   .pixelsPerDegree = options->pixelsPerDegree,
                                   .flip = true,
                                   .keepFlipMap = !options->flipMap.empty()};
      const RgbaImage a = readImage(options->a);
      const RgbaImage b = readImage(options->b);
      if (a.width != b.width || a.height != b.height)
        throw std::runtime_error("A and B differ in size (" + options->a + ": " + sizeText(a) + ", " + options->b +
                                 ": " + sizeText(b) + ")");
      const ImageDifference d = compareImages(a, b, compare);
      if (!options->flipMap.empty()) writeImage8(options->flipMap, a.width, a.height, 4, flipMapRgba8(d.flipMap));
      const std::vector<ThresholdFailure> failures = failedThresholds(d, options->thresholds);
      passed = failures.empty();
      if (options->json) {
        nlohmann::json report = differenceJson(d, a, compare);
        report["passed"] = passed;
        report["failed"] = nlohmann::json::array();
        for (const ThresholdFailure& f : failures)
          report["failed"].push_back({{"option", f.option}, {"value", finiteOrNull(f.value)}, {"limit", f.limit}});
        std::cout << report.dump(2) << "\n";
      } else {
        printDifference(d, a);
      }
      for (const ThresholdFailure& f : failures)
        std::fprintf(stderr, "fail: %s %g (measured %g)\n", f.option.c_str(), f.limit, f.value);
    });
    if (!passed) throw CommandExit{kExitThresholdExceeded};
  });
}

}  // namespace pbs::cli
