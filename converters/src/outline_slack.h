// Whole images (docs/design.md §5): where a flat shape's outline may stray from the traced one.
// Regions drawn later paint over the part of a shape that reaches under them, so there its
// outline need not follow the region's jagged border: it may take the simplest curve that
// neither uncovers the region's own pixels nor reaches the pixels that must stay as they are.
#pragma once

#include <cstdint>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gm {

struct OutlineSlack {
    int width = 0, height = 0;
    std::vector<float> room;  // per pixel: how far (px) an outline point there may stray
    // The room at the pixel that holds p; 0 outside the image or without a map.
    double at(Vec2 p) const;
};

// The room of the outline of region `own` drawn beneath `under` (both the image's size, w × h):
// at each pixel, the distance to the nearest pixel the shape must not paint (neither own nor
// under) and to the nearest pixel of own that shows (own, not under), whichever is nearer, less
// `margin` for the anti-aliased edge, at most `reach`; 0 where that is not positive.
OutlineSlack hiddenOutlineSlack(const std::vector<uint8_t>& own, const std::vector<uint8_t>& under,
                                int w, int h, double reach, double margin = 1.5);

}  // namespace gm
