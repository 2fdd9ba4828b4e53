// Whole images (docs/design.md §5, paper §4.6): the image is segmented into large regions
// (segment.h), each region — holes included — becomes one mesh through the per-region pipeline
// (convertRegion; a region too thin in places for one map: its core and those parts, see
// convertSegmented), the regions converted in parallel. No seams: each region's mesh reaches about
// a pixel under its neighbours (its outline traced around the region dilated by one pixel; its
// colours fitted to its own pixels only), and a coarse base mesh over the whole image, drawn
// first, paints whatever no region mesh reaches.
#pragma once

#include <string>
#include <vector>

#include "converters/convert_image.h"
#include "converters/flat_gradient.h"
#include "converters/flat_regions.h"
#include "converters/flat_residue.h"
#include "converters/flat_strokes.h"
#include "converters/neck.h"
#include "converters/segment.h"

namespace gm {

// The default patch budget per region of a whole-image conversion: large enough that most
// regions stop at the error target rather than at the budget (an object conversion's 400 leaves
// large textured regions of a photo well above the default target).
constexpr int kSegmentMaxPatches = 8000;

struct SegmentConvertOptions {
    ConvertOptions convert;      // per region: --max-error, --max-patches, colours, ...
    SegmentOptions segment;
    int threads = 0;             // regions converted at once (0: all hardware threads)
    // When > 0, each region's budget is its pixels / pixelsPerPatch, at least
    // minRegionPatches and at most convert.maxPatches: a small, busy region does not get a
    // patch for every few pixels.
    double pixelsPerPatch = 8;
    int minRegionPatches = 36;
    int overlap = 1;             // pixels each region's outline reaches under its neighbours
    // convert.subPixelEdgePull for every region (ColorOptions::subPixelEdgePull). Region
    // meshes meet along outlines where the image's colour turns within a pixel or two, and a
    // row of sub-pixel patches there draws that turn wherever Inkscape samples it. An object's
    // conversion leaves it off: its outline is drawn by the fill path's anti-aliasing, and the
    // pull there costs patches that refinement adds back.
    double subPixelEdgePull = 0.5;
    // A region of at least neckMinPixels whose mesh misses --max-error by more than
    // neckErrorFactor (or that fails) is cut at its narrowest neck (neck.h) and each side
    // converted on its own (the sides share the region's budget by their pixels), recursively
    // up to neckSplits cuts deep; the cut is kept when it lowers the region's error by 5 %.
    // 0 neckSplits: never.
    int neckSplits = 2;
    int neckMinPixels = 2000;
    double neckErrorFactor = 1.1;
    NeckOptions neck;
    // A region whose mesh has inverted sheets of more than foldedArea pixels (meshcore's
    // foldedArea: a grid fanned into a narrow notch between two limbs folds over it and paints
    // the regions drawn before it, which the region's own error does not see) is cut at its
    // neck the same way. The cut is kept when it halves the inverted area without raising the
    // region's error by more than 10 %. Not for a region drawn first (nothing beneath it but the
    // base mesh). 0: never.
    double foldedArea = 40;
    // Pixels per patch side of the base mesh: basePatchSize when a region failed (the base
    // mesh then paints all of it), else coarseBasePatchSize (it only fills the slivers no
    // region mesh reaches, a tiny fraction of the pixels, and a finer base would be a large
    // share of the patches of a file at small budgets).
    double basePatchSize = 64;
    double coarseBasePatchSize = 256;
    // When > 0 (--total-patches): one patch budget for the whole image, shared out where it
    // lowers the squared error most. Every region is converted at budgets 4·2^(i/2) rounded
    // (4, 6, 8, 11, 16, 23, ...) up to a generous one (topBudgetShare times its share of
    // totalPatches by pixels, at least topBudgetShare times the mean share, rounded up to the
    // ladder; at most convert.maxPatches). The meshes kept are those whose patches total at
    // most totalPatches with the least summed squared error (allotPatches; no further
    // conversion): each mesh's over its region's pixels plus its spill over the regions drawn
    // before it (SegmentConvertReport::keptSpill).
    // The ladders of a larger total hold those of a smaller one, so the summed error never
    // rises with the total. --max-error still stops each region.
    int totalPatches = 0;
    double topBudgetShare = 2;
    // ... and with flatShapes, a shaded region's ladder starts with the region as a flat shape
    // of its colour (no patches): where the total is too small for every region's mesh, the
    // allotment draws the regions that gain least from a mesh flat, as a tracer would.
    bool flatRungs = true;
    // --total-patches 0: every region a flat shape of its fitted colour, no mesh (the image
    // posterized into flat-colour paths, as a tracer draws it); a region whose outline cannot
    // be traced is left to the base mesh. The curve's low end: no patches and no mesh script.
    // Like flatRungs, only with flatShapes (which fits the regions' colours).
    bool flatOnly = false;
    // Regions of one colour (fitFlatColour against convert.maxError) become flat shapes
    // (Document::shapes) in their place in the drawing order instead of meshes.
    bool flatShapes = true;
    // A photograph segmented finer. When the region count is automatic (segment.segments and
    // segment.threshold 0), ink lines were looked for and none found (without them, with
    // --colors hermite or a compact file's budget, a drawing cannot be told from a photograph)
    // and the shaded regions (neither flat nor ink) hold at least shadedShare of the pixels,
    // the image is segmented again towards shadedSegments regions, kept when that gives at
    // least twice as many regions. A mesh refines whole rows and columns of its grid, so in one
    // large region the patches that draw a detail run across all of it; smaller regions keep
    // them where the detail is. A drawing keeps its few regions: they are flat, or drawn
    // between ink lines. Not under a total budget of fewer than finerPatchesPerSegment patches
    // per region wanted: there each region's outline costs more than its patches save.
    // 0 shadedSegments: never.
    int shadedSegments = 100;
    double shadedShare = 0.5;
    int finerPatchesPerSegment = 10;
    FlatOptions flat;
    // A flat region thin enough (a line, a ring) is drawn as strokes along its centreline
    // (flat_strokes.h) when they match it; else as a filled outline. False: always filled.
    bool strokes = true;
    StrokeOptions stroke;
    // A flat region whose colour runs across it is painted with a linear gradient
    // (flat_gradient.h) when that pays, and a shaded region that a gradient fits is a graded
    // flat shape when that draws it no worse than its mesh. False: one colour per flat region,
    // a mesh for every shaded one.
    bool gradients = true;
    // What each byte a flat shape's extras add to an SVG (a gradient, a residue region) must
    // win back: squared error, 0–255 units, the mean over channels, summed over pixels.
    double flatErrorPerByte = 1000;
    GradientFitOptions gradient;
    // With flatOnly, what the regions' paint misses by far (a bubble on a plain background)
    // becomes regions of their own on top (flat_residue.h), where that pays as gradients do.
    bool residue = true;
    ResidueOptions residueOptions;
    // With meshes, what the drawn document misses by far becomes flat shapes on top of it
    // (residueShapes), blobs from 6 pixels on, where each wins back per byte
    // residuePriceOverAverage times what the document wins back per byte on average.
    ResidueOptions meshResidueOptions{{8, 5, 3}, 6};
    double residuePriceOverAverage = 0.5;
};

struct SegmentConvertReport {
    ConvertReport convert;       // regions (each with label, fallback), error over ALL pixels
    SegmentStats segmentation;
    std::vector<int> regionLabels;        // per convert.regions entry: its segment label
    std::vector<std::string> fallbacks;   // per entry: "" or what was done when it failed
    int failedRegions = 0;       // left to the base mesh
    int filledRegions = 0;       // converted with their holes filled (inner regions on top)
    int trimmedRegions = 0;      // converted as their core without the parts thinner than 5 (or
                                 // 11) px, and those parts as meshes of their own
    int splitRegions = 0;        // cut at necks, each side converted on its own
    int flatRegions = 0;         // flat shapes instead of meshes (part "flat")
    int finerSegments = 0;       // the shadedSegments target of the finer segmentation kept,
                                 // else 0
    int basePatches = 0;         // 0 with a flat backdrop
    bool flatBackdrop = false;   // every region flat: a flat rectangle instead of the base mesh
    int mergedIntoBackdrop = 0;  // flatOnly: regions of nearly the backdrop's colour that joined
                                 // it (flat_backdrop.h)
    int residueRegions = 0;      // blobs the regions (flatOnly) or the drawn document missed,
                                 // drawn on top of them (flat_residue.h)
    int liftedThin = 0;          // thin flat regions drawn after the others (thin_on_top.h)
    int mergedAcrossThin = 0;    // ... and regions of one colour they parted, merged
    double regionUncovered = 0;  // fraction of pixels no region mesh paints (the base does)
    FitError border;             // error over pixels with a 4-neighbour of another segment
    FitError interior;           // ... and over the others
    double segmentSeconds = 0, regionsSeconds = 0, convertSeconds = 0, measureSeconds = 0;
    double totalSeconds = 0;     // wall, segmentation to measurement
    // --total-patches: per convert.regions entry, the largest budget tried and the budget of
    // the mesh kept; and how many conversions were made in all.
    std::vector<int> largestBudget, keptBudget;
    // ... and the kept meshes' squared error (0-255 units, per pixel the mean over channels)
    // where they paint over regions drawn before them, which the allotment adds to their own
    // (allotPatches minimises the sum).
    std::vector<double> keptSpill;
    int conversions = 0;
};

// --total-patches, the budget shared out: one converted mesh of a region, its patches, its
// squared error summed over its pixels, and which conversion made it.
struct RdPoint {
    double patches = 0, sse = 0;
    size_t job = 0;
};

// A region's measured meshes that are worth their patches: fewest patches first, each with
// more patches than the one before and a strictly smaller error (of meshes with equal
// patches, the better).
std::vector<RdPoint> paretoFront(std::vector<RdPoint> points);

// allotPatches works on at most this many (region, patch count) cells: beyond it the patch
// counts are taken in coarser units (rounded up, so the total still holds) and the choice may
// fall a little short of the best.
constexpr double kAllotCells = 1e7;

// Picks one point of each region's front (an index into it; each front non-empty, as
// paretoFront makes it) so that the patches total at most `total` with the least summed
// squared error: an exact multiple-choice knapsack over the patch counts. When the first
// points alone exceed the total they are kept (nothing smaller was measured).
std::vector<size_t> allotPatches(const std::vector<std::vector<RdPoint>>& fronts, int total);

// Throws gm::Error naming `imageName` when the image is empty or the segmentation fails. A
// region whose mesh misses the error target (see neckSplits) or whose map fails is first cut at
// its narrowest neck; a region that cannot be converted otherwise is retried with its holes
// filled, then as its core without the parts thinner than 5 px, then 11 px (holes filled), plus
// those parts as meshes of their own (convertThinParts: in parts or tiles where no map works),
// and else left to the base mesh (each reported in `fallbacks`, never silently).
Document convertSegmented(const RgbaImage& image, const SegmentConvertOptions& options,
                          const std::string& imageName, SegmentConvertReport* report = nullptr);

}  // namespace gm
