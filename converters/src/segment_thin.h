// Thin structures at full size: lines and rings a few pixels wide drawn on their surroundings.
// The segmentation's graph stage sees them blurred (and, on a large image, downscaled) and cuts
// them into fragments or gives them to what surrounds them; here they are found on the image
// itself and each becomes a label of its own.
#pragma once

#include <opencv2/core.hpp>

#include <vector>

namespace gm {

struct ThinStructureOptions {
    // A pixel is on a ridge when, along a row, a column or a diagonal, the pixels `a` before and
    // `b` after it (a, b >= 1, a + b <= maxSpan) are alike (their colour distance under half
    // of each's distance to the pixel) and both lie at least pixelContrast (0-255 RGB distance)
    // from it.
    int maxSpan = 6;
    double pixelContrast = 50;
    // An 8-connected set of ridge pixels becomes a label when it has at least minPixels pixels,
    // its mean colour lies further than contrast from the mean of the side pixels, and those
    // lie within maxSideSpread times that distance of their mean (RMS): a line drawn on one
    // flat surrounding, not an outline between different regions, which the graph stage draws
    // as their border.
    long minPixels = 64;
    double contrast = 100;
    double maxSideSpread = 0.5;
    int threads = 0;
};

// Relabels the thin structures of `bgr` (8-bit BGR) in `labels` (one per pixel, 0..count-1)
// with new labels from `count` on, each made 4-connected (a pixel added where it touches
// itself only diagonally). Returns the new label count.
int liftThinStructures(const cv::Mat& bgr, std::vector<int>& labels, int count,
                       const ThinStructureOptions& options);

// Grows the labels from `firstThin` to `count` (the thin structures liftThinStructures made)
// into the 4-neighbouring pixels of earlier labels whose colour is of the structure rather than
// of their own label: nearer to the structure's mean colour than half their distance to their
// label's, and within `contrast` / 2 of it. A structure thin in places and wider in others (a
// ring drawn off-centre) is found as a ridge only where it is thin; the graph stage may have
// given the rest to what surrounds it. Returns the pixels taken.
long growThinStructures(const cv::Mat& bgr, std::vector<int>& labels, int firstThin, int count,
                        double contrast);

// Cuts every label no wider than about 2·maxSteps+1 pixels (each pixel within maxSteps
// 4-neighbour steps of another label) that encloses other labels (a ring) in two across its
// longer side, when both halves are 4-connected and of at least minPixels pixels: the second
// half gets a new label. A thin
// ring meshed whole maps onto a mesh rectangle mostly taken by its hole, its own pixels
// squeezed into a sliver of it; each arc maps onto one as a strip. Returns the new label count.
int cutThinLoops(std::vector<int>& labels, int W, int H, int count, int maxSteps,
                 long minPixels);

}  // namespace gm
