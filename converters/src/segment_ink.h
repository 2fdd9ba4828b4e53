// Ink lines: the outlines a drawing puts between its regions (a cartoon's black contours), a few
// pixels wide, of one colour of their own that is no blend of the colours on either side. The
// graph stage gives their pixels to the regions they divide, whose meshes must then bend their
// colour steeply along every border; here they are found on the full-size image and each
// becomes a label of its own, to be drawn over the regions it divides (a flat shape, where its
// colour is one).
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace gm {

struct InkLineOptions {
    // A pixel is on an ink ridge when, along a row, a column or a diagonal, it lies at least
    // pixelContrast (0-255 RGB distance) from the pixels `a` before and `b` after it (a, b >= 1,
    // a + b <= maxSpan) and from every blend of the two, and is darker (or lighter) than both
    // by at least half of pixelContrast in luma, or the two are alike (a line of any hue on
    // one surrounding: their distance under a quarter of the pixel's from the nearer).
    int maxSpan = 6;
    double pixelContrast = 50;
    // Neighbouring ridge pixels of the same kind (dark or light) closer in colour than this
    // form one set.
    double joinDistance = 60;
    // A set's ink is the mean of its quarter of pixels furthest from the blends of their
    // sides; it is a line when those lie further than `contrast` from them on average. Its
    // pixels are those within maxResidual of a blend of the ink with one of their side pixels,
    // less its parts wider than maxWidth pixels (a dark area, not a line), plus the
    // anti-aliased fringe around them: 4-neighbours that blend the ink, at least
    // minFringeShare of it, with a side pixel.
    double contrast = 100;
    double maxResidual = 30;
    int maxWidth = 4;
    double minFringeShare = 0.2;
    // A set with at least minPixels such pixels is a line; each 8-connected piece of it of at
    // least minPiece pixels becomes a label (a line's pieces part where it fades or meets
    // another).
    long minPixels = 64;
    long minPiece = 16;
    // ... when its ink lies on average at least minSideDistance (0-255 RGB distance) from the
    // nearer of the colours either side of it: a drawing's ink, not a crease or a strand of
    // hair in a photograph, which a region's mesh draws better.
    double minSideDistance = 150;
    // Ink lines are lifted only where the drawing outlines its regions with them: when at
    // least this share of the borders between the labels lies within two pixels of them.
    double minInkedBorders = 0.3;
    int threads = 0;
};

// Gives the ink lines of `bgr` (8-bit BGR) in `labels` (one per pixel, 0..count-1) new labels
// from `count` on, each piece made 4-connected; sets their pixels to 1 in `ink` (width*height).
// Pixels already set in `ink`, or labelled `count` or more, are left alone. Returns the new
// label count.
int liftInkLines(const cv::Mat& bgr, std::vector<int>& labels, int count,
                 std::vector<uint8_t>& ink, const InkLineOptions& options);

}  // namespace gm
