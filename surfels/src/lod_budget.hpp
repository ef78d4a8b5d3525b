// traverseLod's cut chosen by cost (LodOptions::budget) instead of by the threshold.
#pragma once

#include "pbs/surfels/lod_render.hpp"

#include <array>

namespace pbs {

// The resolution divisors a budget in seconds may draw a frame at, finest first (LodBudget::lowerResolution).
inline constexpr std::array<double, 7> kBudgetDivisors{1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0};

// The same view drawn at width / divisor × height / divisor pixels (rounded, at least 1).
Camera reducedCamera(const Camera& camera, double divisor);

// The frame's resolution divisor under options.budget: the least of kBudgetDivisors at which the coarsest cut
// (the one traverseWithBudget refines from), plus the upscale below 1 (predictUpscaleCost), is predicted to fit
// the limit, the largest when none does; 1 for a budget of primitives, none, or one that keeps the resolution.
// Deterministic.
double budgetResolutionDivisor(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                               const Camera& camera, const LodOptions& options);

// The greedy refinement LodBudget describes; options.budget.limit > 0.
LodDraws traverseWithBudget(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                            const Camera& camera, const LodOptions& options);

}  // namespace pbs
