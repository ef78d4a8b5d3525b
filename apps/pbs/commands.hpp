// The subcommands of `pbs`: each file registers one on the application.
#pragma once

#include <pbs/scene/loose_octree.hpp>
#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/ordering.hpp>
#include <pbs/surfels/surfelize.hpp>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include <cstdint>

namespace pbs::cli {

// Exit statuses beside 0: 1 bad input (an `error:` line), 2 bad usage, and this one: `pbs compare`'s
// images differ beyond a limit it was given (an image test failed).
inline constexpr int kExitThresholdExceeded = 3;

// Thrown by a command that finished its work but must end with another status than 0.
struct CommandExit {
  int status = 0;
};

void addDemoCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addGenerateCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addCaptureCommand(CLI::App& app);
void addAnalyzeCommand(CLI::App& app);
void addPrefixesCommand(CLI::App& app);
void addSurfelizeCommand(CLI::App& app);
void addMergeCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addCalibrateCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addFigureCommand(CLI::App& app);

// The `--threads` option every command has (0: all hardware threads).
void addThreadsOption(CLI::App& command, int& threads);

// --cache-mb: the budget of what a command reads on demand (surfel arrays, meshes), in MB.
void addCacheOption(CLI::App& command, std::uint64_t& cacheMb, const std::string& help);

// `--resolution` and `--directions` of the commands that capture nodes (see CaptureOptions).
void addCaptureOptions(CLI::App& command, std::uint32_t& resolution, std::uint32_t& directions);

// `--min-triangles` of the commands that make surfels: nodes with more subtree triangles get an array.
// Its old spelling, `--threshold` (a unit shared with render's pixels), still works with a warning.
void addMinTrianglesOption(CLI::App& command, std::uint64_t& minTriangles);

// When a scene is rebuilt as a loose octree before its surfels are made: asked for (`--octree`), or
// because a node draws a mesh of more than `above` triangles (`--octree-above`, 0: never); its leaves
// hold at most `leaf` triangles (`--octree-leaf`).
struct OctreeChoice {
  bool always = false;
  std::uint64_t above = kDefaultOctreeAboveTriangles;
  std::uint32_t leaf = kDefaultOctreeLeafTriangles;

  // The octree's leaf size for `scene` (which may be opened without its mesh arrays), or 0 for none.
  std::uint32_t leavesFor(const Scene& scene) const { return always || needsLooseOctree(scene, above) ? leaf : 0; }
};
void addOctreeOptions(CLI::App& command, OctreeChoice& octree);

// What the commands draw with where LodOptions' own default differs: rays where they cost less than surfels
// (LodOptions::descendWhereRaysCheaper; the commands' frames have a ray caster behind them).
void applyCommandLodDefaults(LodOptions& lod);

// The LOD options of `pbs render` (and the baseline `pbs eval` sweeps from), on applyCommandLodDefaults:
// --threshold-pixels (old spelling --threshold, still working with a warning), --band, --overdraw, --point-size,
// --prefix-rule, --geometry, --rays-cheaper and the budgets.
void addLodOptions(CLI::App& command, LodOptions& lod);

// A samples-per-pixel option (`--samples`, `--reference-samples`): 1, 4, 16, 64 or 256 (supersampling.hpp).
// A check for options that take a positive, finite number ("expected a positive number, not 0"; CLI11's
// PositiveNumber prints the whole double range instead).
CLI::Validator positiveNumber();

void addSamplesOption(CLI::App& command, const std::string& name, std::uint32_t& samples, const std::string& help);

// `--texture-filter anisotropic|isotropic|none`: how the frames' textures are sampled (TextureFiltering).
void addTextureFilterOption(CLI::App& command, TextureFiltering& textures);

// `--path orbit|approach|flythrough`: the camera path of the commands that render frames (camera_paths.hpp).
void addPathOption(CLI::App& command, std::string& path);

// `--background R,G,B` (each in [0, 1]) and `--ppd` (FLIP's pixels per degree): how images are compared.
void addCompareOptions(CLI::App& command, glm::vec3& background, double& pixelsPerDegree);

// `--ordering farthest|dart|random`.
void addOrderingOption(CLI::App& command, SurfelOrdering& ordering);

// `--capture-from auto|triangles|children`: what inner nodes' captures draw (see CaptureSource).
void addCaptureSourceOption(CLI::App& command, CaptureSource& source, const std::string& help);

}  // namespace pbs::cli
