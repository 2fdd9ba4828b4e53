// Whole images (docs/design.md §5): the narrowest neck of a region, where a straight cut splits it
// into two parts that each map onto a rectangle far better than the whole. One map of a region
// with a lobe behind a neck crowds the lobe into a sliver of the parameter rectangle: its grid
// lines fan out from the neck, the lobe's patches become long and thin, and its texture smears.
// Two meshes sharing the same patch budget, one each side of the neck, render the lobe far
// better.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "converters/region.h"

namespace gm {

struct NeckOptions {
    // A neck is a chord between two points of the outer loop whose length is at most this
    // fraction of the shorter loop arc between them.
    double maxRatio = 0.2;
    // Each side keeps at least this fraction of the region's area.
    double minShare = 0.15;
    // The chord runs inside the region: at least this fraction of its samples (1 px apart, its
    // ends left out) fall in region pixels (a chord across a bay of the outline is no neck).
    double minInside = 0.9;
    // Loop points are taken every `step` px of arc length, at most maxPoints of them.
    double step = 2.0;
    int maxPoints = 2000;
};

struct NeckCut {
    Vec2 a, b;          // the chord's ends on the outer loop
    double ratio = 0;   // chord length / shorter arc
    // width*height: 1 for the region's pixels on one side of the chord, 2 for the other side,
    // 0 elsewhere. Each side has at least one pixel.
    std::vector<uint8_t> side;
};

// The neck with the smallest ratio, or nothing when no chord qualifies. O(n²) in the loop's
// points (n ≤ maxPoints) plus a scanline pass over the region's bounding box.
std::optional<NeckCut> findNeck(const Region& region, const NeckOptions& options = {});

}  // namespace gm
