// The options several commands share, defined once so their names, checks and help agree.
#include "commands.hpp"

#include <pbs/evaluation/frame_calibration.hpp>
#include <pbs/raster/raster_limits.hpp>
#include <pbs/raster/supersampling.hpp>
#include <pbs/scene/input_error.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>

namespace pbs::cli {

void addThreadsOption(CLI::App& command, int& threads) {
  command.add_option("--threads", threads, "worker threads (0: all hardware threads)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
}

void addCacheOption(CLI::App& command, std::uint64_t& cacheMb, const std::string& help) {
  command.add_option("--cache-mb", cacheMb, help)
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 30))
      ->capture_default_str();
}

void addCaptureOptions(CLI::App& command, std::uint32_t& resolution, std::uint32_t& directions) {
  command.add_option("--resolution", resolution, "capture pixels along the larger side of each view")
      ->check(CLI::Range(1u, kMaxViewportSize))
      ->capture_default_str();
  command.add_option("--directions", directions, "capture views: 8 for the box corners, else N spread over the sphere")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
}

namespace {

// `old`, an earlier spelling of the option `current` (bound to the same value, with the same check; given
// both, the later wins): it still works, so scripts do not break, and says on stderr what to write instead.
template <class T>
void addOldSpelling(CLI::App& command, const std::string& old, CLI::Option* current, T& value,
                    const CLI::Validator& check) {
  const std::string replacement = current->get_name();
  const CLI::Validator warn(
      [old, replacement](std::string&) {
        std::cerr << "warning: " << old << " is deprecated here: write " << replacement << "\n";
        return std::string();
      },
      "");
  command.add_option(old, value, "the old spelling of " + replacement + " (deprecated)")->check(warn)->check(check);
}

}  // namespace

void addMinTrianglesOption(CLI::App& command, std::uint64_t& minTriangles) {
  CLI::Option* option =
      command.add_option("--min-triangles", minTriangles, "nodes with more subtree triangles than this get surfels")
          ->capture_default_str();
  addOldSpelling(command, "--threshold", option, minTriangles, CLI::Range(std::uint64_t(0), ~std::uint64_t(0)));
}

void addOctreeOptions(CLI::App& command, OctreeChoice& octree) {
  command.add_flag("--octree", octree.always,
                   "rebuild the scene as a loose octree first, so a flat scene gets levels of detail");
  command
      .add_option("--octree-above", octree.above,
                  "rebuild as a loose octree when a node draws a mesh of more triangles than this (0: never)")
      ->capture_default_str();
  command.add_option("--octree-leaf", octree.leaf, "triangles per loose-octree leaf at most")
      ->check(CLI::Range(1u, ~0u))
      ->capture_default_str();
}

namespace {

// The frame costs of a `pbs calibrate` file; InputError naming the file otherwise.
FrameCosts readCalibration(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, "", "cannot be read");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, "", std::string("not JSON: ") + e.what());
  }
  return frameCostsFromJson(json, file);
}

}  // namespace

void applyCommandLodDefaults(LodOptions& lod) {
  // The commands draw surfels mode through FrameRenderer, which has rays to draw geometry with.
  lod.descendWhereRaysCheaper = true;
}

void addLodOptions(CLI::App& command, LodOptions& lod) {
  applyCommandLodDefaults(lod);
  // Defined before the budgets, so that CLI11 (which runs callbacks in definition order) has read the
  // costs whatever the order on the command line.
  command
      .add_option_function<std::string>(
          "--calibration", [&lod](const std::string& file) { lod.frameCosts = readCalibration(file); },
          "a pbs calibrate file: what --budget-ms prices frames with (default: costs measured on a 2-core machine)")
      ->check(CLI::ExistingFile);
  CLI::Option* primitives =
      command
          .add_option_function<double>(
              "--budget-primitives", [&lod](double limit) { lod.budget = LodBudget::primitives(limit); },
              "choose the cut by a budget: refine the nodes largest on screen, none below --threshold-pixels, while "
              "the triangles plus surfels drawn stay within this many")
          ->check(positiveNumber());
  CLI::Option* milliseconds =
      command
          .add_option_function<double>(
              "--budget-ms", [&lod](double ms) { lod.budget = LodBudget::seconds(ms / 1e3); },
              "choose the cut by a frame time: refine the nodes largest on screen, none below --threshold-pixels, "
              "while the frame's predicted time (--calibration) stays within this many milliseconds")
          ->check(positiveNumber())
          ->excludes(primitives);
  // After --budget-ms, whose callback sets the whole budget.
  command
      .add_option_function<std::string>(
          "--budget-resolution", [&lod](const std::string& value) { lod.budget.lowerResolution = value == "auto"; },
          "with --budget-ms: auto (default) draws a frame whose coarsest cut does not fit at a lower resolution "
          "(1/1.5 to 1/8 a side) and upscales it; full keeps the full resolution, over the budget if need be")
      ->check(CLI::IsMember({"auto", "full"}))
      ->needs(milliseconds);
  CLI::Option* threshold =
      command
          .add_option("--threshold-pixels", lod.threshold, "projected size (pixels) above which nodes are descended")
          ->check(positiveNumber())
          ->capture_default_str();
  addOldSpelling(command, "--threshold", threshold, lod.threshold, positiveNumber());
  command.add_option("--band", lod.band, "transition band above the threshold, as a fraction of it")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  command.add_option("--overdraw", lod.overdraw, "surfels per covered pixel (the paper's 4 was for 2-pixel points)")
      ->check(positiveNumber())
      ->capture_default_str();
  command
      .add_option_function<std::string>(
          "--splat",
          [&lod](const std::string& name) {
            const std::optional<SplatMode> mode = splatModeFromName(name);
            if (!mode) throw CLI::ValidationError("--splat", "expected blend or nearest, got " + name);
            lod.splat = *mode;
          },
          "blend (discs blended on the front surface, fractional coverage) or nearest (points, nearest wins)")
      ->default_str(splatModeName(lod.splat));
  command
      .add_option("--point-size", lod.pointSize,
                  "0: sized from the prefix (discs that close the surface); else a fixed size in pixels for "
                  "--splat nearest, below 1 sub-pixel points")
      ->check(CLI::Range(0.0f, 64.0f))
      ->capture_default_str();
  command
      .add_option("--cull", lod.backFaceCosine,
                  "surfels whose cosine to the eye is below this are not drawn (-1: draw all)")
      ->check(CLI::Range(-1.0f, 1.0f))
      ->capture_default_str();
  command.add_option("--coverage-gain", lod.coverageGain, "blend mode: multiplies each splat's coverage")
      ->check(CLI::Range(0.1f, 10.0f))
      ->capture_default_str();
  const std::map<std::string, bool> exhausted = {{"descend", true}, {"grow", false}};
  command
      .add_option("--exhausted", lod.descendExhausted,
                  "a node whose array is too short for its size: descend (lower its threshold, the default) or "
                  "grow (draw the whole array with larger points, the paper's cap)")
      ->transform(CLI::CheckedTransformer(exhausted));
  const std::map<std::string, bool> cheaperRays = {{"descend", true}, {"keep", false}};
  command
      .add_option("--rays-cheaper", lod.descendWhereRaysCheaper,
                  "a node below the threshold whose subtree drawn by rays is predicted to cost less than its "
                  "surfels: descend (draw it exactly, the default) or keep (its surfels: the threshold alone "
                  "decides, the paper's rule)")
      ->transform(CLI::CheckedTransformer(cheaperRays));
  command
      .add_option("--rays-preference", lod.raysPreference,
                  "with --rays-cheaper descend: rays are chosen while predicted to cost up to this many times the "
                  "surfels")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  command
      .add_option("--rays-near-share", lod.raysNearShare,
                  "with --rays-cheaper descend, where rays draw the geometry: a frame whose geometry fills more than "
                  "this share of its cut is drawn by more rays, all rays from 0.1 above it (1: never)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  const std::map<std::string, PrefixRule> rules = {{"coverage", PrefixRule::Coverage},
                                                   {"packing", PrefixRule::Packing}};
  command.add_option("--prefix-rule", lod.prefixRule, "coverage (paper, default) or packing (authors' later rule)")
      ->transform(CLI::CheckedTransformer(rules));
  std::map<std::string, GeometryDrawer> drawers;
  for (GeometryDrawer d : {GeometryDrawer::Raster, GeometryDrawer::Rays, GeometryDrawer::Auto})
    drawers.emplace(geometryDrawerName(d), d);
  command
      .add_option("--geometry", lod.geometry,
                  "what draws the nodes drawn as triangles in surfels mode: raster, rays (Embree) or auto (the "
                  "cheaper per frame, the default)")
      ->transform(CLI::CheckedTransformer(drawers));
}

CLI::Validator positiveNumber() {
  return CLI::Validator(
      [](const std::string& text) {
        double value = 0.0;
        return CLI::detail::lexical_cast(text, value) && std::isfinite(value) && value > 0.0
                   ? std::string()
                   : "expected a positive number, not " + text;
      },
      "POSITIVE");
}

void addSamplesOption(CLI::App& command, const std::string& name, std::uint32_t& samples, const std::string& help) {
  command.add_option(name, samples, help + " (1, 4, 16, 64 or 256: a fixed rotated-grid pattern, box-filtered)")
      ->check(CLI::Validator(
          [](const std::string& text) {
            std::uint32_t n = 0;
            return CLI::detail::lexical_cast(text, n) && isSupportedSampleCount(n) ? std::string()
                                                                                   : "expected 1, 4, 16, 64 or 256";
          },
          "SAMPLES"))
      ->capture_default_str();
}

void addTextureFilterOption(CLI::App& command, TextureFiltering& textures) {
  std::map<std::string, TextureFiltering> names;
  for (TextureFiltering f : {TextureFiltering::Anisotropic, TextureFiltering::Isotropic, TextureFiltering::None})
    names.emplace(textureFilteringName(f), f);
  command
      .add_option("--texture-filter", textures,
                  "anisotropic (the default: mip levels as each texture's sampler asks, up to 4 probes along a "
                  "slanted footprint), isotropic (one probe) or none (the full-size image alone: fastest, aliased "
                  "where textures are minified)")
      ->transform(CLI::CheckedTransformer(names));
}

void addPathOption(CLI::App& command, std::string& path) {
  command
      .add_option("--path", path,
                  "camera path: orbit (around the scene), approach (from far outside into its densest part) or "
                  "flythrough (a closed loop through its box, among the geometry)")
      ->check(CLI::IsMember({"orbit", "approach", "flythrough"}))
      ->capture_default_str();
}

void addCompareOptions(CLI::App& command, glm::vec3& background, double& pixelsPerDegree) {
  command.add_option_function<std::string>(
      "--background",
      [&background](const std::string& text) {
        glm::vec3 colour(-1.0f);
        char comma1 = 0, comma2 = 0;
        std::istringstream in(text);
        in >> colour.r >> comma1 >> colour.g >> comma2 >> colour.b;
        const bool inRange = glm::all(glm::greaterThanEqual(colour, glm::vec3(0.0f))) &&
                             glm::all(glm::lessThanEqual(colour, glm::vec3(1.0f)));
        if (!in || comma1 != ',' || comma2 != ',' || !(in >> std::ws).eof() || !inRange)
          throw CLI::ValidationError("--background", "expected R,G,B with each in [0, 1], got " + text);
        background = colour;
      },
      "R,G,B in [0, 1]: the background both images are composited over (default 1,1,1: white)");
  command.add_option("--ppd", pixelsPerDegree, "FLIP's observer: pixels per degree of visual angle")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
}

void addOrderingOption(CLI::App& command, SurfelOrdering& ordering) {
  std::map<std::string, SurfelOrdering> names;
  for (SurfelOrdering o : {SurfelOrdering::Farthest, SurfelOrdering::Dart, SurfelOrdering::Random})
    names.emplace(std::string(orderingName(o)), o);
  command.add_option("--ordering", ordering, "surfel order: farthest (default), dart or random")
      ->transform(CLI::CheckedTransformer(names));
}

void addCaptureSourceOption(CLI::App& command, CaptureSource& source, const std::string& help) {
  std::map<std::string, CaptureSource> names;
  for (CaptureSource s : {CaptureSource::Auto, CaptureSource::Triangles, CaptureSource::ChildSurfels})
    names.emplace(std::string(captureSourceName(s)), s);
  command
      .add_option("--capture-from", source,
                  help + " (auto, the default: children where the triangles are over twice as many)")
      ->transform(CLI::CheckedTransformer(names));
}

}  // namespace pbs::cli
