// The exact median of a FLIP map, found in parallel without sorting.
#pragma once

#include <span>

namespace pbs::flip {

// The median of `values` (for an even count the mean of the two middle ones; 0 for none), which must
// all be non-negative (+0, not −0) and not NaN. Exact and independent of the thread count.
double medianOfNonNegative(std::span<const float> values);

}  // namespace pbs::flip
