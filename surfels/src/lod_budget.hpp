// traverseLod's cut chosen by cost (LodOptions::budget) instead of by the threshold.
#pragma once

#include "pbs/surfels/lod_render.hpp"

#include <array>
#include <optional>

namespace pbs {

// The resolution divisors a budget in seconds may draw a frame at, finest first (LodBudget::lowerResolution).
inline constexpr std::array<double, 7> kBudgetDivisors{1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0};

// The same view drawn at width / divisor × height / divisor pixels (rounded, at least 1).
Camera reducedCamera(const Camera& camera, double divisor);

// How a budget in seconds draws a frame: the least of kBudgetDivisors at which the coarsest cut (the one
// traverseWithBudget refines from), plus the upscale below full size (predictUpscaleCost), is predicted to fit
// the limit, the largest when none does; and the budget of that pass: the limit, less the upscale's price below
// full size. When the refined cut at that size is still coarse (discs several drawn pixels wide: the budget
// left nothing to refine it with), smaller sizes follow while their refined cut looks finer. Divisor 1 and the
// budget as given for a budget of primitives, none, or one that keeps the resolution. Deterministic.
struct BudgetResolution {
  double divisor = 1.0;
  LodBudget pass;
  // The refined cut at that size under `pass` (traverseWithBudget's), when choosing the size made it: the
  // frame draws it rather than traversing again. With the seconds its traversals took.
  std::optional<LodDraws> draws = std::nullopt;
  double traverseSeconds = 0.0;
};
BudgetResolution budgetResolution(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                                  const Camera& camera, const LodOptions& options);

// The greedy refinement LodBudget describes; options.budget.limit > 0.
LodDraws traverseWithBudget(const Scene& scene, const Hierarchy& hierarchy, const SceneSurfels& surfels,
                            const Camera& camera, const LodOptions& options);

}  // namespace pbs
