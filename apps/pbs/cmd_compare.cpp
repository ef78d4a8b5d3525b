// `pbs compare A B [--json]`: how far image A is from image B (RMSE, PSNR, luminance SSIM, holes).
#include "commands.hpp"
#include "image_files.hpp"
#include "report_numbers.hpp"

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
nlohmann::json differenceJson(const ImageDifference& d, const RgbaImage& a) {
  nlohmann::json j;
  j["rmse"] = d.rmse;
  j["psnr"] = finiteOrNull(d.psnr);
  j["ssim"] = d.ssim;
  j["hole_fraction"] = d.holeFraction;
  j["width"] = a.width;
  j["height"] = a.height;
  j["pixels_surface_a"] = d.surfaceA;
  j["pixels_surface_b"] = d.surfaceB;
  return j;
}

void printDifference(const ImageDifference& d, const RgbaImage& a) {
  const std::string size = sizeText(a);
  char psnr[32] = "inf";
  if (std::isfinite(d.psnr)) std::snprintf(psnr, sizeof psnr, "%.2f", d.psnr);
  std::printf("rmse %.4g  psnr %s dB  ssim %.4f  holes %.4g (A: %s, %llu surface px; B: %s, %llu surface px)\n",
              d.rmse, psnr, d.ssim, d.holeFraction, size.c_str(), static_cast<unsigned long long>(d.surfaceA),
              size.c_str(), static_cast<unsigned long long>(d.surfaceB));
}

}  // namespace

void addCompareCommand(CLI::App& app) {
  struct Options {
    std::string a;
    std::string b;
    bool json = false;
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "compare", "Compare image A with B: RMSE, PSNR, luminance SSIM, and holes (background in A, surface in B)");
  command->add_option("a", options->a, "image A (PNG, EXR, …; alpha < 0.5 is background), e.g. a surfel render")
      ->required();
  command->add_option("b", options->b, "image B of the same size, e.g. the reference render")->required();
  command->add_flag("--json", options->json, "print JSON instead of text (psnr null when the images are identical)");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    runWithThreads(options->threads, [&] {
      const RgbaImage a = readImage(options->a);
      const RgbaImage b = readImage(options->b);
      if (a.width != b.width || a.height != b.height)
        throw std::runtime_error("A and B differ in size (" + options->a + ": " + sizeText(a) + ", " + options->b +
                                 ": " + sizeText(b) + ")");
      const ImageDifference d = compareImages(a, b);
      if (options->json)
        std::cout << differenceJson(d, a).dump(2) << "\n";
      else
        printDifference(d, a);
    });
  });
}

}  // namespace pbs::cli
