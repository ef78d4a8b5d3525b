// FLIP's feature pipeline: edge and point detection on luminance and the per-pixel feature error ΔEf.
#pragma once

#include "flip_filters.hpp"

#include <cstdint>

namespace pbs::flip {

// The 1-D parts of the separable edge and point detectors for one viewing distance: a 2-D detector
// along x is the edge (or point) kernel along x times the Gaussian along y, and likewise along y.
struct FeatureFilters {
  HalfKernel gaussian;  // normalised to sum 1
  HalfKernel edge;      // first derivative: positive taps sum to 1, negative ones to −1
  HalfKernel point;     // second derivative, normalised the same way
};

FeatureFilters makeFeatureFilters(double pixelsPerDegree);

// ΔEf in [0, 1] for rows [yBegin, yEnd), written to out (row yBegin first, width values a row), from
// the achromatic planes (Y' = 116·Y/Yn − 16) of the two images.
void featureErrorRows(const FeatureFilters& filters, const Plane& reference, const Plane& test, std::uint32_t yBegin,
                      std::uint32_t yEnd, float* out);

}  // namespace pbs::flip
