// Part of pipeline stage 6, grid: boundary fidelity. The mesh's outline is made of its boundary
// patch edges (the rectangle's four sides and both sides of every slit), each one cubic between
// two nodes. Where a cubic strays from the region's outline (as the inverse map carries it), the
// parameter interval under it is split where the cubic strays most, until every boundary curve
// lies within a tolerance of the outline: a face profile or a hole is then followed however
// smooth its colours are, which colour refinement alone would never ask for.
#pragma once

#include "converters/grid.h"

namespace gm {

struct BoundaryFitOptions {
    double tolerance = 0.5;   // pixels: Hausdorff distance to the outline
    double holeTolerance = 0.2;  // pixels: the same for hole outlines (both sides of a slit)
    int maxPatches = 400;     // the grid never grows past this many patches (or 1.5 times the
                              // initial grid's, when its slits alone need more)
    int maxRounds = 40;
    // A new knot goes at the worst point of its interval's edges, at least this fraction of
    // the interval from either end (0.5: always the middle).
    double knotMargin = 0.25;
    // A round splits only intervals at least this fraction of the round's worst deviation, so
    // that a budget too small for the whole outline goes to its worst parts first.
    double roundFraction = 0.5;
};

struct BoundaryFitResult {
    int addedU = 0, addedV = 0;  // knots added
    int rounds = 0;
    double maxDeviation = 0;     // pixels, of the last grid (> tolerance only when capped)
};

// Splits boundary knot intervals, each at the worst point of its edges, until
// grid.build(options) meets the tolerance (or the patch cap or round limit is reached). When it
// adds knots, options.knotsU / knotsV are set to the complete knot vectors.
BoundaryFitResult fitBoundary(const GridBuilder& grid, GridOptions& options,
                              const BoundaryFitOptions& fit = {});

// The largest Hausdorff distance between a boundary edge of `mesh` (built by `grid`) and the
// outline under it, pixels: BoundaryFitResult::maxDeviation of that mesh.
double outlineDeviation(const GridBuilder& grid, const GradientMesh& mesh);

}  // namespace gm
