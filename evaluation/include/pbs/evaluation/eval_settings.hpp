// The settings `pbs eval` measures: the peers (exact renderers: "embree=N" rays at N samples per
// pixel, "exact=N" the rasterizer drawing every triangle), "surfels" (the baseline LOD options), and
// sweeps over it: each the baseline with one value changed, named "KEY=VALUE" ("overdraw=2",
// "threshold=64", "primitives=500000" (a budget of triangles plus surfels), "ms=33" (a frame-time budget), "point=1",
// "band=0", "rule=packing", "ordering=dart", "simplify=0.05": simplified meshes in place of surfels), or several at
// once
// ("point=2+threshold=128").
#pragma once

#include <pbs/surfels/frame_renderer.hpp>
#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/ordering.hpp>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pbs {

// A --peers or --sweep text that names no setting: `option` is the option it came from, what() the reason.
class SweepError : public std::invalid_argument {
 public:
  SweepError(std::string option, const std::string& reason)
      : std::invalid_argument(reason), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

struct EvalSetting {
  std::string name;  // as given, normalised for peers ("exact" → "exact=1"): the CSV's setting column
  RenderMode mode = RenderMode::Surfels;
  std::uint32_t samples = 1;               // per pixel (peers)
  LodOptions lod;                          // the baseline with this setting's change
  std::optional<SurfelOrdering> ordering;  // unset: the surfel file's own arrays
  // Set (mode Simplified): small nodes draw their subtree from meshes simplified to this fraction of
  // their triangles (renderSimplifiedLod) instead of surfels.
  std::optional<double> simplify;

  bool isPeer() const { return mode == RenderMode::Exact || mode == RenderMode::Embree; }
  bool drawsSurfels() const { return mode == RenderMode::Surfels; }
  // The same frames: mode, samples, every LOD option, ordering and simplification alike (names aside).
  bool drawsLike(const EvalSetting& other) const;
};

// The keys a sweep may name, for help and errors.
std::string sweepKeys();

// "KEY=V1,V2,…" (one setting per value), "KEY=V+KEY=V…" (one setting with all those changes),
// "surfels" (the baseline) or "exact", as settings over `baseline`, in the given order. Throws
// SweepError naming `option` for an unknown key, a value out of range or a list inside a
// combined setting.
std::vector<EvalSetting> parseSweep(const std::string& text, const LodOptions& baseline,
                                    const std::string& option = "--sweep");

// The peers every run measures unless --peers says otherwise: Embree at 1, 4 and 16 samples, exact at 1.
std::vector<std::string> defaultPeers();

// What `pbs eval` sweeps without --sweep: overdraw 1, 2, 8; threshold 64, 256; point 1, 4; ordering
// dart and random (those not the file's own: `fileOrdering`); simplify 0.25, 0.05, 0.01.
std::vector<std::string> defaultSweep(SurfelOrdering fileOrdering);

// The peers, then "surfels" (the baseline), then the settings of every sweep in order; a setting that
// draws like an earlier one is dropped.
std::vector<EvalSetting> evalSettings(const std::vector<std::string>& peers, const std::vector<std::string>& sweeps,
                                      const LodOptions& baseline);

// The index of "surfels", the baseline the contact sheet and the summary point at.
std::size_t baselineSetting(const std::vector<EvalSetting>& settings);

}  // namespace pbs
