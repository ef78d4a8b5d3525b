// `pbs figure scaling|views|paths|stream -o DIR`: the evaluation's figures, each written by one command:
// frame time against scene size (figure_scaling.hpp), exact against surfels from near to far
// (figure_views.hpp), the camera paths seen from above (figure_paths.hpp), and a view's error while its
// surfels stream in (figure_stream.hpp).
#include "commands.hpp"
#include "figure_paths.hpp"
#include "figure_scaling.hpp"
#include "figure_stream.hpp"
#include "figure_views.hpp"
#include "orbit_views.hpp"

#include <pbs/raster/thread_arena.hpp>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>

namespace pbs::cli {
namespace {

// bunny.glb of the shared scenes: $PBS_SCENES, else ../shared/scenes from the current folder (the
// repository's root beside them). Read at run time, so an installed pbs names no build folder.
std::string defaultMesh() {
  const char* env = std::getenv("PBS_SCENES");
  const std::filesystem::path folder =
      env && *env ? std::filesystem::path(env) : std::filesystem::path("../shared/scenes");
  const std::filesystem::path mesh = folder / "bunny.glb";
  if (!std::filesystem::is_regular_file(mesh))
    throw std::runtime_error(mesh.string() +
                             " not found: give --mesh F.glb, or set PBS_SCENES to the shared scenes folder");
  return mesh.string();
}

void addScaling(CLI::App& figure) {
  struct Options {
    ScalingOptions scaling;
    std::string path = "orbit";
    std::string output;
    std::string size = "1920x1080";
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  ScalingOptions& scaling = options->scaling;
  CLI::App* command = figure.add_subcommand(
      "scaling",
      "frame time against scene size: generated cities of about 1 M to 1.4 G triangles (with bunny.glb), "
      "each surfelized in memory and drawn exactly and with surfels");
  command
      ->add_option("-o,--output", options->output,
                   "folder for scaling.csv, scaling.json, scaling.svg (created if missing)")
      ->required();
  command->add_option("--mesh", scaling.meshes,
                      "a .gltf/.glb file the cities instance (repeat for several; default: bunny.glb of $PBS_SCENES "
                      "or ../shared/scenes)");
  command->add_option("--frames", scaling.frames, "views per city along the --path")
      ->check(CLI::Range(1u, 1000u))
      ->capture_default_str();
  command->add_option("--size", options->size, "WxH pixels")->capture_default_str();
  command->add_option("--max-triangles", scaling.maxTriangles, "leave out the cities of more triangles")
      ->check(positiveNumber());
  addLodOptions(*command, scaling.lod);
  addPathOption(*command, options->path);
  command->add_flag("-q,--quiet", scaling.quiet, "no progress on stderr");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    std::tie(options->scaling.width, options->scaling.height) = parseSize(options->size);
    if (options->scaling.meshes.empty()) options->scaling.meshes = {defaultMesh()};
    options->scaling.path = *cameraPathFromName(options->path);
    runWithThreads(options->threads, [&] { writeScalingFigure(options->scaling, options->output); });
  });
}

void addViews(CLI::App& figure) {
  struct Options {
    ViewsOptions views;
    std::string output;
    std::string size = "1920x1080";
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  ViewsOptions& views = options->views;
  // As in `pbs demo`: surfels made here are captured at 256 px (surfelize's default is 512), a quarter
  // of the work; give a file from `pbs surfelize` for the full resolution.
  views.surfelize.file.resolution = 256;
  CLI::App* command = figure.add_subcommand(
      "views", "image quality near to far: one direction at three distances, exact | surfels | difference");
  command->add_option("scene", views.scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--surfels", views.surfels, "the scene's .surfels file (default: made in memory)");
  command
      ->add_option("-o,--output", options->output, "folder for views.png, views.csv, views.json (created if missing)")
      ->required();
  command->add_option("--size", options->size, "WxH pixels of each view")->capture_default_str();
  command->add_option("--direction", views.direction, "AZ,EL in degrees")->delimiter(',')->capture_default_str();
  command->add_option("--distances", views.distances, "NEAR,MIDDLE,FAR in bounding radii from the centre")
      ->delimiter(',')
      ->check(positiveNumber())
      ->capture_default_str();
  addCaptureOptions(*command, views.surfelize.file.resolution, views.surfelize.file.directions);
  addLodOptions(*command, views.lod);
  command->add_flag("-q,--quiet", views.quiet, "no progress on stderr");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    std::tie(options->views.width, options->views.height) = parseSize(options->size);
    runWithThreads(options->threads, [&] { writeViewsFigure(options->views, options->output); });
  });
}

void addPaths(CLI::App& figure) {
  struct Options {
    PathsFigureOptions paths;
    std::string output;
    std::string orbit = "30,20,2.5";
    std::string size = "1024x1024";
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = figure.add_subcommand(
      "paths",
      "the camera paths (orbit: blue, approach: red, flythrough: green) drawn from above over the scene "
      "rendered exactly: every eye (left panel) and the scene close up (right); paths.png, paths.json");
  command->add_option("scene", options->paths.scene, "a .gltf/.glb file, or 'default'")->capture_default_str();
  command->add_option("-o,--output", options->output, "folder for paths.png and paths.json (created if missing)")
      ->required();
  command->add_option("--frames", options->paths.frames, "cameras per path")
      ->check(CLI::Range(1u, 100000u))
      ->capture_default_str();
  command
      ->add_option("--orbit", options->orbit,
                   "AZ,EL,DIST: the orbit's start, and the approach's direction and start distance")
      ->capture_default_str();
  command->add_option("--size", options->size, "WxH pixels of each of the two panels")->capture_default_str();
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    options->paths.orbit = parseOrbit(options->orbit);
    std::tie(options->paths.width, options->paths.height) = parseSize(options->size);
    runWithThreads(options->threads, [&] { writePathsFigure(options->paths, options->output); });
  });
}

void addStream(CLI::App& figure) {
  struct Options {
    StreamFigureOptions stream;
    std::string output;
    std::string orbit = "30,20,2.5";
    std::string size = "1920x1080";
    int threads = 0;
  };
  auto options = std::make_shared<Options>();
  StreamFigureOptions& stream = options->stream;
  CLI::App* command = figure.add_subcommand(
      "stream",
      "a view while its surfels stream in over a simulated link: FLIP against a converged reference over "
      "time at two bandwidths, prefixes chunk by chunk beside whole arrays one by one");
  command->add_option("scene", stream.scene, "a .gltf/.glb file, or 'default'")->required();
  command->add_option("--surfels", stream.surfels, "the scene's .surfels file (from pbs surfelize)")->required();
  command
      ->add_option("-o,--output", options->output,
                   "folder for stream.svg, stream.png, stream.csv, stream.json (created if missing)")
      ->required();
  command->add_option("--bandwidths", stream.bandwidths, "MB/s (10^6 bytes a second) of the links compared")
      ->delimiter(',')
      ->check(positiveNumber())
      ->capture_default_str();
  command->add_option("--seconds", stream.seconds, "simulated time the plot spans")
      ->check(positiveNumber())
      ->capture_default_str();
  command->add_option("--steps", stream.steps, "frames per series, evenly spread over --seconds")
      ->check(CLI::Range(4u, 10000u))
      ->capture_default_str();
  command->add_option("--orbit", options->orbit, "AZ,EL,DIST: degrees, degrees, bounding radii (the view)")
      ->capture_default_str();
  command->add_option("--size", options->size, "WxH pixels")->capture_default_str();
  addSamplesOption(*command, "--reference-samples", stream.referenceSamples,
                   "Embree's samples per pixel for the reference");
  addLodOptions(*command, stream.lod);
  command->add_flag("-q,--quiet", stream.quiet, "no progress on stderr");
  addThreadsOption(*command, options->threads);
  command->callback([options] {
    options->stream.orbit = parseOrbit(options->orbit);
    std::tie(options->stream.width, options->stream.height) = parseSize(options->size);
    runWithThreads(options->threads, [&] { writeStreamFigure(options->stream, options->output); });
  });
}

}  // namespace

void addFigureCommand(CLI::App& app) {
  CLI::App* figure = app.add_subcommand("figure", "Write one of the evaluation's figures into a folder");
  figure->require_subcommand(1);
  addScaling(*figure);
  addViews(*figure);
  addPaths(*figure);
  addStream(*figure);
}

}  // namespace pbs::cli
