// Exact colour in formats whose patches interpolate colour bilinearly (SVG meshgradient, PDF
// and PostScript patch meshes): split each patch k×k so that the bilinear interpolation of each
// piece's corner colours stays within a tolerance of the true bicubic colour.
#pragma once

#include <utility>
#include <vector>

#include "meshcore/bezier_patch.h"

namespace gm {

// The smallest k (1..maxK) for which every k×k piece's bilinear colour is within `tolerance`
// (0–1 units, max over channels) of the patch colour; maxK when none is.
int colorSubdivisionCount(const BezierPatch& patch, double tolerance, int maxK = 64);

// How many pieces exact colour cuts a patch into, ks along s and kt along t: the k of
// colorSubdivisionCount, but along each direction no more pieces than keep them `minPiece`
// pixels long (the control polygon's longest run that way over minPiece, rounded up; 0: no
// limit). Pieces of a pixel or less are what a 1:1 render samples once each, so finer ones only
// add bytes: on a whole image of small patches the limit cuts the pieces several times over.
std::pair<int, int> exactColorPieces(const BezierPatch& patch, double tolerance, double minPiece,
                                     int maxK = 64);

// The ks×kt exact sub-patches; piece (a, b) (a along s, b along t) is at index b*ks + a.
std::vector<BezierPatch> subdivideGrid(const BezierPatch& patch, int ks, int kt);
// subdivideGrid(patch, k, k).
std::vector<BezierPatch> subdivideUniform(const BezierPatch& patch, int k);

}  // namespace gm
