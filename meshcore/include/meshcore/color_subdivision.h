// Exact colour in formats whose patches interpolate colour bilinearly (SVG meshgradient, PDF
// and PostScript patch meshes): split each patch k×k so that the bilinear interpolation of each
// piece's corner colours stays within a tolerance of the true bicubic colour.
#pragma once

#include <vector>

#include "meshcore/bezier_patch.h"

namespace gm {

// The smallest k (1..maxK) for which every k×k piece's bilinear colour is within `tolerance`
// (0–1 units, max over channels) of the patch colour; maxK when none is.
int colorSubdivisionCount(const BezierPatch& patch, double tolerance, int maxK = 64);

// The k×k exact sub-patches; piece (a, b) (a along s, b along t) is at index b*k + a.
std::vector<BezierPatch> subdivideUniform(const BezierPatch& patch, int k);

}  // namespace gm
