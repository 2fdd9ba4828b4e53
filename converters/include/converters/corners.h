// Pipeline stage 2, corners (docs/design.md §3, paper §4.1): the four points of a region's outer
// loop that map to the corners of the parameter rectangle (tri_mesh.h), and the rectangle's size.
#pragma once

#include <array>

#include "converters/region.h"

namespace gm {

struct CornerOptions {
    double radius = 5;            // pixels: disk of the integral invariant
    double lambda = 0.1;          // weight of the distance to the bounding-box corner, per pixel
    double searchFraction = 0.05; // search within this fraction of the perimeter (paper: 1/20)
};

struct RegionCorners {
    // Indices into Region::outer.points of corner k = 0 top-left, 1 top-right, 2 bottom-right,
    // 3 bottom-left. They follow the loop's order (positive signed area), so side k runs from
    // corner k to corner k+1: 0 top, 1 right, 2 bottom, 3 left.
    std::array<int, 4> index{};
    std::array<double, 4> sideLength{};  // arc length of side k along the loop, pixels
    double px = 0;                       // max(top, bottom): the rectangle's width
    double py = 0;                       // max(left, right): its height
};

// Paper §4.1: PCA-align the region bounded by the outer loop, take the loop vertices nearest the
// corners of its bounding box, then within searchFraction × perimeter of each pick the vertex
// minimising |n − πr²/4| + λ·distance, n being the area of the region inside the disk of radius r
// (exact, from the outer loop). Which corner is top-left: the labelling whose top and bottom
// sides point most nearly along +x in the image. Throws gm::Error if the outer loop has fewer
// than 4 points.
RegionCorners findCorners(const Region& region, const CornerOptions& options = {});

// The alternative when the map squeezes a long thin part (a leg between two corners, both
// flanks on one side): the four sharpest convex tips of the outer loop (smallest share of the
// radius-r disk inside the region), each at least 1/12 of the perimeter from the others, so
// that thin parts end at corners and their flanks fall on two sides. findCorners when fewer
// than four such tips exist.
RegionCorners findTipCorners(const Region& region, const CornerOptions& options = {});

}  // namespace gm
