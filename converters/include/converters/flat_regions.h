// Whole images (docs/design.md §5): regions of one colour become flat shapes (FlatShape: one
// colour, a cubic Bézier outline with holes) instead of meshes, so that a flat drawing costs a
// path per region rather than patches along every jagged outline.
#pragma once

#include <cstdint>
#include <vector>

#include "converters/colors.h"
#include "converters/region.h"
#include "converters/regions.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

// How a traced outline is smoothed along its length before its Bézier fit: a Gaussian of
// `sigma` points of the outline densified to a pixel apart or less (0: not smoothed), held at the points where it turns more than `holdTurn`
// degrees within a pixel either side, and moving no point further than `maxShift` pixels.
struct OutlineSmoothing {
    double sigma = 0;
    double holdTurn = 50;
    double maxShift = 0.5;
};

struct FlatOptions {
    // A region is flat when one colour fits its interior pixels (those whose four neighbours
    // are in the region too; all its pixels when fewer than minInterior, or than
    // minInteriorShare of its pixels, are) with E at most
    // errorShare times the conversion's error target. Border pixels are left out: in an
    // anti-aliased drawing they mix the region's colour with its neighbour's, which the shape's
    // anti-aliased outline reproduces.
    double errorShare = 0.25;
    int minInterior = 8;
    double minInteriorShare = 0.25;
    // ... and when at most outlierShare of those pixels are further than outlierError times
    // the target from the colour (a gentle gradient or texture with a low mean error is not
    // flat).
    double outlierShare = 0.02;
    double outlierError = 4;
    double curveTolerance = 0.5;    // pixels: the Bézier outline against the traced loop
    double inkCurveTolerance = 0.15;  // ... for an ink line, whose width is a pixel or two
    // Both hold for error targets up to toleranceError (0-255 units) and grow in proportion
    // above it: a coarser target asks for coarser outlines too (convertSegmented).
    double toleranceError = 3;
    // Where the outline lies, each border pixel is read as a blend of the shape's colour with
    // the colour around it furthest from it; with blendEachSide (ink lines, which part two
    // regions), with the one around it that explains it best.
    bool blendEachSide = false;
    double coverageSmoothing = 0.4;  // Gaussian sigma (pixels) on the coverage traced
    // The traced outline smoothed before the Bézier fit: a border anti-aliased in steps traces
    // as a staircase, which the fit would follow with a curve per step. An ink line's ends turn
    // within a pixel or two, so its outline is held wherever it turns more gently.
    OutlineSmoothing outlineSmoothing{1.5, 50, 0.5};
    OutlineSmoothing inkOutlineSmoothing{1.0, 30, 0.5};
    // Where a shape reaches under regions drawn after it, its outline lies up to hiddenReach
    // pixels beneath them and may stray from the traced one as far as it keeps clear of the
    // pixels it must not paint and of its own that show (outline_slack.h): what covers it
    // there hides its jagged border. 0: it follows the trace everywhere.
    double hiddenReach = 1.5;
    // A shape whose outline or centreline was fitted within coarseGridTolerance pixels or more
    // has its points put on a grid of coarseGrid pixels (convertSegmented): an SVG then writes
    // one decimal where it wrote two. 0: never.
    double coarseGrid = 0.1;
    double coarseGridTolerance = 0.5;
    // Holes of fewer pixels are filled: a border pixel that holds less than half of the shape's
    // colour makes a speck of a hole, which what is drawn on top covers anyway.
    int minHole = 3;
};

// The colour that fits a region and whether it is flat.
struct FlatFit {
    bool flat = false;
    Vec3 col;           // sRGB 0–1, the mean over the interior pixels
    FitError interior;  // of that colour over the interior pixels
    FitError all;       // ... and over all the region's pixels
};

// An ink line (segment_ink.h, `inkLine`) is always flat, its colour fitted as a thin region's.
FlatFit fitFlatColour(const RgbaImage& image, const Region& own, double maxError,
                      bool inkLine = false, const FlatOptions& options = {});

// The region as a flat shape of colour `col`: its outline traced around its pixels grown by
// `overlap` pixels into `under` (width*height, the pixels of whatever is drawn on top of it),
// with its holes that lie wholly under `under` filled (what is drawn on top paints them), fitted
// with cubic Béziers within options.curveTolerance. Where the shape is seen, the outline lies
// where the image's anti-aliased border pixels say (each pixel's share of `col` against the
// colour beyond, traced at one half). Subpaths: the outer boundary (clockwise on screen), then
// each hole (counter-clockwise). With a `gradient` (stops), the shape is painted with it and
// its border pixels are read against the gradient's colour at each. Throws gm::Error if
// nothing is left.
FlatShape traceFlatShape(const RgbaImage& image, const Region& own, const Vec3& col, int overlap,
                         const std::vector<uint8_t>& under, const FlatOptions& options = {},
                         const LinearGradient& gradient = {});

// How much of colour `col` each pixel holds, 0–1, for tracing an outline between pixel centres:
// 1 where the shape reaches under later regions (`grown` and `under`, or grown beyond `own`:
// they paint over it), else the share of `col` in the pixel's colour against its blend partner
// within two pixels (an anti-aliased border blends the two; with `eachSide`, the neighbour
// that explains the pixel best, else the one furthest from col); a pixel with no such
// neighbour, or whose neighbours' colour is too close to `col` to tell a share, is 1 in the
// region and 0 outside it. With a `gradient`, its colour at each pixel stands for `col`. All
// masks are the image's size.
Coverage shareCoverage(const RgbaImage& image, const std::vector<uint8_t>& own,
                       const std::vector<uint8_t>& grown, const std::vector<uint8_t>& under,
                       const Vec3& col, bool eachSide, const LinearGradient* gradient = nullptr);

// The whole canvas as a flat shape of colour `col`, its outline clockwise on screen.
FlatShape canvasRectangle(int width, int height, const Vec3& col);

// A closed polygon as closed cubic Béziers (FlatShape subpath layout) within `tolerance` pixels
// of it: corners sharper than 50 degrees stay corners; elsewhere the curves join smoothly.
// The polygon is first smoothed as `smoothing` says.
std::vector<Vec2> fitClosedCubics(const std::vector<Vec2>& polygon, double tolerance,
                                  const OutlineSmoothing& smoothing = {});

// An open polyline as cubic Béziers within `tolerance` pixels of it, in a stroked FlatShape's
// centreline layout (3n + 1 points), joining smoothly.
std::vector<Vec2> fitOpenCubics(const std::vector<Vec2>& polyline, double tolerance);

}  // namespace gm
