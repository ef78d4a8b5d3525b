// traverseLod's cut chosen by cost (LodOptions::budget) instead of by the threshold.
#pragma once

#include "pbs/surfels/lod_render.hpp"

namespace pbs {

// The greedy refinement LodBudget describes; options.budget.limit > 0.
LodDraws traverseWithBudget(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                            const Camera& camera, const LodOptions& options);

}  // namespace pbs
