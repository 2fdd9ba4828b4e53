// Whole images (docs/design.md §5): what a flat trace's regions miss, drawn on top of them. A
// flat region paints one colour (or a gradient) over pixels the segmentation gave it; a detail
// of another colour inside it (a bubble on a plain background, a highlight on a sweet) is lost
// unless the segmentation cut it out. Connected pixels that their region's paint misses by far
// become regions of their own, drawn after the others, where their colour wins back more error
// than their outline costs.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "converters/flat_regions.h"
#include "converters/region.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

struct ResidueOptions {
    // Passes from coarse to fine: pixels whose mean channel error (0–255 units) exceeds
    // errorMultiples[i] times the error target form the pass's blobs. A coarser target leaves
    // more to the regions: at E 40 only what differs by more than 120.
    std::vector<double> errorMultiples{8, 5, 3};
    int minPixels = 15;  // smaller blobs (8-connected) are left
    // What a blob's flat shape adds to an SVG, bytes: the element, and its outline per border
    // pixel. Set above what the path text alone takes: a blob's traced, anti-aliased outline
    // wins back less than its pixels painted exactly would.
    double bytesPerBlob = 100;
    double bytesPerBorderPixel = 3;
};

// Adds to `regions` (before the ink lines, from firstInk on, which moves past them) a region per
// blob of pixels that `paint(k, p)` (region k's colour at pixel index p) misses, whose squared
// error (0–255 units, mean over channels, summed) falls by at least errorPerByte per byte of its
// shape when painted in its mean colour. A pixel belongs to the last region before firstInk
// that holds it; pixels an ink line holds are left, and so are those beside another region's
// (an anti-aliased border blends the two). Returns how many were added.
size_t addResidueRegions(const RgbaImage& image, std::vector<Region>& regions, size_t& firstInk,
                         const std::function<Vec3(size_t, size_t)>& paint, double maxError,
                         double errorPerByte, const ResidueOptions& options = {});

// What a filled flat shape adds to an SVG, roughly, in bytes: its element, and its segments.
double flatShapeSvgBytes(const FlatShape& shape);

// Over regions already drawn (meshes and flat shapes alike; `painted`: the drawing's colour at
// each pixel, canvas-sized), the blobs it misses, chosen as addResidueRegions chooses them, as
// flat shapes of their mean colour to draw on top of everything: a highlight or a speck that a
// mesh would need many patches for. The passes' limits are multiples of the larger of
// `maxError` and the drawing's own E (a mesh at a small budget misses by more than its
// target everywhere; its blobs are what it misses by far more than that). Outlines are traced
// as any flat shape's (traceFlatShape with `flat`); a blob is left when its traced shape, drawn
// by our renderer over the drawing, wins back less than errorPerByte per flatShapeSvgBytes.
std::vector<FlatShape> residueShapes(const RgbaImage& image, const std::vector<Region>& regions,
                                     size_t firstInk, std::vector<Vec3> painted,
                                     double maxError, double errorPerByte,
                                     const FlatOptions& flat, const ResidueOptions& options = {});

}  // namespace gm
