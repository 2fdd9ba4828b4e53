// Whole images: thin flat regions (lines, rings) drawn after the other regions, as strokes on
// top of them (convert_segments.cpp). Drawn last, a line lets the regions beneath it reach
// under it: they need no holes where it runs, and the regions of one colour it parted, such as
// a panel and the inside of a ring drawn on it, become one region again.
#pragma once

#include <cstddef>
#include <vector>

#include "converters/region.h"
#include "meshcore/gradient_mesh.h"

namespace gm {

// How thick the region is: the widest disc of pixels it holds, in pixels (a line 3 px wide: 3).
double regionThickness(const Region& region);

// Moves the regions before `firstInk` that `thin` marks after the others before it, each group
// in its order. Returns the index of the first region moved (firstInk when none was).
size_t liftThinRegions(std::vector<Region>& regions, size_t firstInk,
                       const std::vector<char>& thin);

// Merges each region before `firstThin` that `flat` marks into an earlier such region whose
// colour (colours[k], 0–1) lies within `tolerance` of its own in every channel, when both touch
// the same region from firstThin on (a thin region or ink line between them); and each flat
// region from firstThin on into an earlier one of them of such a colour that it touches (the
// pieces of one line). The merged regions leave `regions`; `firstInk` counts those before it
// out. Returns how many were merged.
size_t mergeAcrossThin(std::vector<Region>& regions, size_t firstThin, size_t& firstInk,
                       const std::vector<char>& flat, const std::vector<Vec3>& colours,
                       double tolerance);

}  // namespace gm
