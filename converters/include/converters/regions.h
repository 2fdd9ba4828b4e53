// Pipeline stage 1, regions (docs/design.md §3): object pixels → 8-connected regions with sub-pixel
// outer and hole loops. Coordinates as in region.h: pixels, x right, y down, pixel (x, y)
// covering [x, x+1) × [y, y+1).
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "converters/region.h"
#include "meshcore/image.h"

namespace gm {

// How much of each pixel the object covers, 0–1, width*height row-major, row 0 at the top.
// The object is where coverage ≥ 0.5; values in between (anti-aliased alpha or mask edges)
// place the traced loops between pixel centres.
struct Coverage {
    int width = 0, height = 0;
    std::vector<float> values;
};

struct RegionOptions {
    int minArea = 16;                // pixels; smaller components are dropped
    int minHole = 16;                // pixels; smaller holes are filled (noise)
    double smoothing = 0.8;          // Gaussian sigma, pixels, applied to the coverage before
                                     // tracing (0: none); it never changes which pixels are inside
    double simplifyTolerance = 0.3;  // Douglas–Peucker tolerance, pixels (0: keep every point)
    double maxSegment = 6.0;         // longest loop edge after simplification, pixels
    // Iso-level of the smoothed coverage that the outer loop follows (holes follow 0.5). Below
    // 0.5 the outline moves outwards, and it then never cuts inside an object pixel's edge: a
    // mesh within a fraction of a pixel of it covers every object pixel centre.
    double outerLevel = 0.5;
};

// Coverage = alpha of an image (straight alpha).
Coverage coverageFromAlpha(const RgbaImage& image);
// Coverage = luminance × alpha of a mask image: white opaque is object, black or transparent is
// background.
Coverage coverageFromMaskImage(const RgbaImage& mask);
// Coverage 1 where bits is non-zero, else 0. Throws gm::Error if bits.size() != width*height.
Coverage coverageFromBits(int width, int height, const std::vector<uint8_t>& bits);

// Throws gm::Error naming `maskName` unless the mask has the image's size.
void requireMaskMatchesImage(const RgbaImage& image, const RgbaImage& mask,
                             const std::string& maskName);

// The regions of the object: one per 8-connected component of coverage ≥ 0.5 of at least
// options.minArea pixels, largest first. Holes are the 4-connected background components not
// connected to the image border; those below options.minHole pixels are filled. Loops are simple
// polygons (outer: polygonSignedArea > 0, holes < 0) that never touch each other.
// Throws gm::Error if the size is invalid, no pixel is object, or every component is too small.
std::vector<Region> extractRegions(const Coverage& coverage, const RegionOptions& options = {});

// The regions of a label map (labels[y*width + x]; negative labels are background): each
// 8-connected component of each label is one region, Region::label saying which. Throws like
// extractRegions.
std::vector<Region> extractRegionsFromLabels(int width, int height, const std::vector<int>& labels,
                                             const RegionOptions& options = {});

// An 8-connected component of pixels of one class.
struct PixelComponent {
    int label = 0;  // its class
    int size = 0;   // pixels
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // inclusive bounding box
};

// Labels the 8-connected components of equal non-negative class (cls: width*height, -1 is
// background); compId (resized) gets each pixel's component index, -1 for background.
std::vector<PixelComponent> labelComponents(int width, int height, const std::vector<int>& cls,
                                            std::vector<int>& compId);

// The smallest box of pixels holding every non-zero pixel of a mask (width*height); empty()
// when there is none.
struct PixelBox {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive
    bool empty() const { return x1 < x0; }
};
PixelBox maskBounds(const std::vector<uint8_t>& mask, int w, int h);

// Whether pixel k of a w × h mask and its four neighbours are all in it (a pixel on the image's
// border never is): a region's inside, away from its anti-aliased border.
inline bool insideMask(const std::vector<uint8_t>& mask, int w, int h, size_t k) {
    const size_t width = static_cast<size_t>(w);
    const size_t x = k % width, y = k / width;
    return x > 0 && y > 0 && x + 1 < width && y + 1 < static_cast<size_t>(h) && mask[k] &&
           mask[k - 1] && mask[k + 1] && mask[k - width] && mask[k + width];
}

// Per pixel, the index of the first of `regions` (all of one size) whose mask holds it: the
// one drawn there first, when they are drawn in order; -1 where none does.
std::vector<int> firstRegionAt(const std::vector<Region>& regions);

// Per region (all of one size), the regions it touches (4-neighbours), by the pixels each is
// drawn at first (firstRegionAt).
std::vector<std::set<int>> touchingRegions(const std::vector<Region>& regions);

// The mask (width*height, non-zero = in) grown by `radius` pixels (a square neighbourhood).
std::vector<uint8_t> dilateMask(const std::vector<uint8_t>& mask, int w, int h, int radius);

// The mask less its parts thinner than 2·radius+1 pixels (a morphological opening with a
// square), never adding a pixel.
std::vector<uint8_t> openMask(const std::vector<uint8_t>& mask, int w, int h, int radius);

// The geometry of `own` for a mesh that reaches under its neighbours: the outline traced around
// its pixels dilated by `overlap` pixels into `under` (width*height; the pixels of whatever is
// drawn on top of it), holes under minHole pixels filled; Region::mask stays `own`'s pixels
// (what the colours are fitted to); outerLevel as RegionOptions::outerLevel. Throws gm::Error if
// nothing is left.
Region growRegionInto(const Region& own, int overlap, int minHole, const std::vector<uint8_t>& under,
                      double outerLevel = 0.5);

}  // namespace gm
