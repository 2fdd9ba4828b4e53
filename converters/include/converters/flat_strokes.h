// Whole images (docs/design.md §5): a thin flat region — a line, a ring, a scribble — drawn as a
// stroke along its centreline (a stroked FlatShape) rather than as a filled outline around both
// of its sides: half the path, and a width that stays even where a traced outline wobbles.
#pragma once

#include <cstdint>
#include <vector>

#include "converters/region.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

struct StrokeOptions {
    double maxWidth = 7;           // pixels: a region thicker than this anywhere stays filled
    int minPixels = 12;            // smaller regions stay filled
    // Pixels: the centreline's cubics against the traced one. A line's anti-aliased edges show
    // a tenth of a pixel.
    double curveTolerance = 0.1;
    // Centrelines whose widths lie within this share of each other are one stroke.
    double widthTolerance = 0.2;
    // The strokes must draw the region's colour where the image holds it: the summed
    // difference of their coverage from the region's (its pixels' share of its colour),
    // over the pixels nothing drawn later covers, at most this per pixel of the region.
    double maxMismatch = 0.06;
    // ... and the pixels where it differs by more than one half at most this share of the
    // region's pixels (where crossing lines meet, a stroke's even width draws them less
    // exactly than their outline does).
    double maxWrongShare = 0.01;
};

// Region `own` of colour `col` as stroked shapes (one per width, in canvas pixels), or none
// when strokes would not draw it well: too thick or too small, or their coverage differs from
// the region's by more than options.maxMismatch and maxWrongShare allow. `under` (the image's size) marks the pixels
// that regions drawn later paint over, where the strokes may reach freely.
std::vector<FlatShape> traceStrokes(const RgbaImage& image, const Region& own, const Vec3& col,
                                    const std::vector<uint8_t>& under,
                                    const StrokeOptions& options = {});

}  // namespace gm
