// The settings `pbs eval` sweeps: each one the baseline LOD options with one value changed, named
// "KEY=VALUE" ("overdraw=2", "threshold=64", "point=1", "band=0", "rule=packing", "ordering=dart",
// "simplify=0.05": simplified meshes in place of surfels), or several at once ("point=2+threshold=128"),
// plus "exact" (the exact rasterizer against itself: every error 0).
#pragma once

#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/ordering.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pbs::cli {

struct EvalSetting {
  std::string name;  // "exact" or "KEY=VALUE" as given (the CSV's setting column)
  bool exact = false;
  LodOptions lod;                          // the baseline with this setting's change
  std::optional<SurfelOrdering> ordering;  // unset: the surfel file's own arrays
  // Set: small nodes draw their subtree from meshes simplified to this fraction of their triangles
  // (renderSimplifiedLod) instead of surfels.
  std::optional<double> simplify;
};

// The keys a sweep may name, for help and errors: overdraw, threshold, point, band, rule, ordering,
// simplify.
std::string sweepKeys();

// "KEY=V1,V2,…" (one setting per value), "KEY=V+KEY=V…" (one setting with all those changes) or
// "exact", as settings over `baseline`, in the given order. Throws CLI::ValidationError naming --sweep
// for an unknown key, a value out of range or a list inside a combined setting.
std::vector<EvalSetting> parseSweep(const std::string& text, const LodOptions& baseline);

// What `pbs eval` sweeps without --sweep: overdraw 1, 2, 4 (the baseline), 8; threshold 64, 256;
// point 1, 4; ordering dart and random (those not the file's own: `fileOrdering`); simplify 0.25,
// 0.05, 0.01.
std::vector<std::string> defaultSweep(SurfelOrdering fileOrdering);

// "exact" first, then the settings of every sweep in order, later duplicates of a name dropped.
std::vector<EvalSetting> evalSettings(const std::vector<std::string>& sweeps, const LodOptions& baseline);

// The setting the contact sheet and the summary call the baseline: the first surfel setting whose LOD
// options equal `baseline` and that uses the file's own arrays; else the first surfel setting; else
// none (only exact or simplified meshes).
std::optional<std::size_t> baselineSetting(const std::vector<EvalSetting>& settings, const LodOptions& baseline);

}  // namespace pbs::cli
