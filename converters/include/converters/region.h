// Plain data passed between the raster → mesh stages (docs/design.md §3). Image coordinates are
// pixels, x right, y down; pixel (x, y) covers [x, x+1) x [y, y+1), its centre at (x+.5, y+.5).
#pragma once

#include <cstdint>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gm {

// A simple closed polygon; the last point joins the first (not repeated).
// Orientation: outer loops have polygonSignedArea > 0 (clockwise as seen on screen, y down),
// hole loops < 0.
struct Polygon {
    std::vector<Vec2> points;
};

// Σ (x_k·y_{k+1} − x_{k+1}·y_k) / 2 in image coordinates (y down).
double polygonSignedArea(const Polygon& poly);

// One 8-connected object region of an image.
struct Region {
    int width = 0, height = 0;    // the image's size
    std::vector<uint8_t> mask;    // width*height, 1 inside the region (holes filled below
                                  // --min-hole are 1, kept holes 0)
    int pixelCount = 0;           // pixels with mask 1
    Polygon outer;                // sub-pixel outer loop
    std::vector<Polygon> holes;   // one sub-pixel loop per kept hole
    int label = 1;                // the label value it came from (label maps), else 1
};

}  // namespace gm
