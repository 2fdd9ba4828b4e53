// Whole-image segmentation into a few large regions (docs/design.md §5, paper §4.6): graph-based
// segmentation (Felzenszwalb–Huttenlocher, OpenCV's) on a downscaled copy, its slivers and
// small pieces merged; each segment's boundary band refined with GrabCut; the gaps GrabCut
// leaves filled by seeded region growing on colour; lines and rings a few pixels wide drawn on
// a flat surrounding found at full size and given labels of their own; small, thin (but not
// such distinct lines) and weakly separated regions merged, so that every label is one
// 4-connected region; thin rings cut into two arcs.
//
// The paper asks for a "large threshold"; on OpenCV's FH a large k leaks across object
// boundaries (several objects and the table they stand on become one region), so the default
// is a moderate k with a large min_size, which gives a few large regions that follow the
// objects.
#pragma once

#include <vector>

#include "meshcore/image.h"

namespace gm {

struct SegmentOptions {
    // Felzenszwalb–Huttenlocher k, in 0–255 colour units, for FH's working image (see
    // workPixels). 0 = chosen: by a few bisection steps on k towards `segments` when that is
    // given, else defaultThreshold scaled to the working image's size.
    double threshold = 0;
    // Wanted number of regions, roughly (0 = a few large regions, as many as the image has:
    // two on a silhouette, a few to a few dozen on a photo).
    int segments = 0;
    // Regions under this many pixels are merged into a neighbour; 0 = max(64, w*h/1000), and
    // distinct lines and arcs of at least 64 pixels kept.
    int minRegion = 0;
    // Refine boundaries with GrabCut.
    bool grabCut = true;

    // --- finer controls -----------------------------------------------------------------
    // FH runs on the image area-downscaled to at most this many pixels (never upscaled): a
    // run then costs little whatever the image size, so k can be searched for, and k means
    // the same on every image size. GrabCut brings the boundaries back to full resolution.
    int workPixels = 1 << 16;
    double sigma = 0.8;              // FH's Gaussian pre-smoothing, working-image pixels
    double defaultThreshold = 300;   // k for a 2^16-pixel working image, scaled by its size
    // FH's min_size, working-image pixels. 0 = the larger of minRegion (scaled) and an eighth
    // of the mean region size wanted (working pixels / segments, segments defaulting to 12):
    // a large min_size rather than a large k keeps FH from leaking across object boundaries
    // (the distinct pieces it would swallow are lifted out again: distinctContrast).
    int fhMinSize = 0;
    int maxTrials = 7;               // FH runs spent searching k for `segments`
    int grabCutIterations = 1;
    // GrabCut runs on the image area-downscaled to at most this many pixels: its cost grows
    // with the area of the segments' windows (several times the image's), so a large photo's
    // boundaries are refined at this resolution, then at full size (upscaleLabelsRefined,
    // segment_borders.h).
    // 0 = always full size.
    int grabCutPixels = 1 << 18;
    // When the regions were found on a downscaled copy (FH's working image, or GrabCut's),
    // give each full-size pixel near a border the neighbouring label of closest local colour
    // (segment_borders.h) rather than its downscaled pixel's label.
    bool refineBorders = true;
    int band = 0;  // GrabCut's uncertain band, pixels each side; 0 = the larger of 3 and the
                   // downscaling factor + 2
    // Segments smaller than this many (full-size) pixels are not refined by GrabCut (their
    // boundary stays as FH drew it); 0 = minRegion.
    int grabCutMinPixels = 0;
    int threads = 0;  // segments refined by GrabCut at once (0: all hardware threads)
    // Regions no wider than this (every pixel within (sliverWidth-1)/2 steps of another
    // region) are merged like tiny ones: FH leaves such slivers along blurred edges. Applied to
    // FH's result on the working image and to the final labels. 0 = keep slivers.
    int sliverWidth = 4;
    // Adjacent regions are merged when the mean colour step across their shared border
    // (0–255 RGB distance between the pixels one further out on either side) is under this:
    // FH splits flat areas along arbitrary lines. Applied where sliverWidth is. 0 = never.
    double weakEdge = 12;
    // A piece of FH's result under its minimum size stays a region of its own when its mean
    // colour lies further than this (0–255 RGB distance) from every neighbour's and it has at
    // least minRegion pixels: a small object is not merged into what surrounds it. The same
    // contrast keeps thin regions (lines, rings) from the sliver merge and finds thin
    // structures at full size (segment_thin.h). 0 = merge by size alone.
    double distinctContrast = 100;
    // Ink lines between regions (a drawing's outlines) become labels of their own, drawn over
    // the regions they divide (segment_ink.h; the contrast is distinctContrast). A whole-image
    // conversion in the hermite colour model turns them off.
    bool inkLines = true;
};

struct SegmentStats {
    double seconds = 0, fhSeconds = 0, grabCutSeconds = 0, growSeconds = 0, mergeSeconds = 0;
    double inkSeconds = 0;  // finding ink lines and merging what they cut off
    int fhRegions = 0, regions = 0;
    long grabCutChanged = 0, grown = 0, merged = 0;
    long weakMerged = 0;      // merges across weak borders (final stage)
    long borderRefined = 0;   // full-size pixels whose label the border refinement changed
    double threshold = 0;     // the k of the FH run used
    int fhTrials = 0;         // FH runs (1 when k was given)
    int fhCleanRegions = 0;   // FH's regions after slivers and small pieces are merged
    int workWidth = 0, workHeight = 0;        // FH's image
    int grabCutWidth = 0, grabCutHeight = 0;  // GrabCut's image
    int grabCutSegments = 0;  // segments GrabCut refined
    long grabCutPixels = 0;   // total area of their GrabCut windows
    int components = 0;       // 4-connected components before merging
    int thinStructures = 0;   // lines and rings found at full size (segment_thin.h)
    long thinGrown = 0;       // pixels of other labels they took in (growThinStructures)
    int inkLines = 0;         // of the final labels, ink lines drawn between regions
};

struct Segmentation {
    int width = 0, height = 0, count = 0;
    // width*height, row-major, every pixel in 0..count-1. Each label is ONE 4-connected set
    // of at least minRegion pixels (unless the whole image is smaller; under the default
    // minRegion, a distinct line or arc may have as few as 64, a piece of an ink line 16);
    // labels are ordered by size, largest first, except the ink lines.
    std::vector<int> labels;
    // The last inkLabels labels are ink lines drawn between regions (a cartoon's outlines,
    // segment_ink.h), after every other label whatever their size and by size among
    // themselves: they are drawn over the regions they divide.
    int inkLabels = 0;
    SegmentStats stats;
};

// Colour is taken premultiplied by alpha (transparent pixels count as black).
// Throws gm::Error on an empty image.
Segmentation segmentImage(const RgbaImage& image, const SegmentOptions& options = {});

}  // namespace gm
