// The measuring half of `pbs eval`: an exact reference pass over the orbit, then every setting over
// the same views, each frame timed and compared with the reference of its view.
#pragma once

#include "contact_sheet.hpp"
#include "eval_settings.hpp"
#include "orbit_views.hpp"

#include <pbs/raster/image_metrics.hpp>
#include <pbs/scene/hierarchy.hpp>
#include <pbs/scene/scene.hpp>
#include <pbs/surfels/lod_render.hpp>
#include <pbs/surfels/scene_surfels.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pbs::cli {

// One row of eval.csv.
struct EvalFrame {
  std::uint32_t frame = 0;
  double azimuthDegrees = 0.0;
  double seconds = 0.0;  // the whole frame (FrameResult::seconds)
  LodStats stats;
  ImageDifference error;  // this frame (A) against the exact reference of the same view (B)
};

struct EvalSettingResult {
  std::vector<EvalFrame> frames;
  std::vector<std::uint8_t> firstImage;       // frame 0 as RGBA8, for the contact sheet
  std::vector<std::uint8_t> firstDifference;  // |frame 0 − reference| × kDifferenceGain as RGBA8
};

struct EvalResults {
  std::vector<EvalFrame> reference;             // the exact pass (errors all 0 by definition)
  std::vector<std::uint8_t> referenceFirst;     // its frame 0 as RGBA8
  std::vector<EvalSettingResult> settings;      // parallel to the settings given
};

// Renders views × (1 + settings) frames. `surfelsOf` gives the arrays a surfel setting draws (called
// once per setting, never for exact ones; simplify settings take their traversal's decisions from
// them), `simplifiedOf` the simplified scene a simplify setting draws (called once per such setting);
// `onProgress(done, total, detail)` after every frame. Memory:
// the reference images of all views are kept (16 bytes a pixel each).
EvalResults runEval(const Scene& scene, const Hierarchy& hierarchy, const std::vector<OrbitView>& views,
                    const std::vector<EvalSetting>& settings,
                    const std::function<const SceneSurfels&(const EvalSetting&)>& surfelsOf,
                    const std::function<const Scene&(const EvalSetting&)>& simplifiedOf,
                    const std::function<void(std::size_t, std::size_t, const std::string&)>& onProgress);

}  // namespace pbs::cli
