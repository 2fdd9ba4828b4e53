// A drawing of flat shapes lies on a backdrop: the canvas in the colour of the region drawn
// first (convert_segments.cpp). Regions of nearly that colour which touch it, such as the
// pieces a segmentation cut a plain background into, need no shapes of their own: they join
// the first region, so that the backdrop covers them and their outlines are not written.
#pragma once

#include <cstddef>
#include <vector>

#include "converters/region.h"
#include "meshcore/gradient_mesh.h"

namespace gm {

// Merges into regions[0] every region before `firstInk` whose colour (colours[k], 0–1) lies
// within `tolerance` of colours[0] in every channel and that touches regions[0] or a region
// merged into it (4-neighbours). The merged regions leave `regions`, the others keep their
// order. Returns how many were merged.
// Whether colours a and b (0–1) lie within `tolerance` of each other in every channel.
bool coloursWithin(const Vec3& a, const Vec3& b, double tolerance);

// Adds the pixels of `from` to `into` (regions of one size).
void joinPixels(Region& into, const Region& from);

size_t mergeIntoBackdrop(std::vector<Region>& regions, size_t firstInk,
                         const std::vector<Vec3>& colours, double tolerance);

}  // namespace gm
