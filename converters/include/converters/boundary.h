// Part of pipeline stage 6, grid: boundary fidelity. The mesh's outline is made of its boundary
// patch edges (the rectangle's four sides and both sides of every slit), each one cubic between
// two nodes. Where a cubic strays from the region's outline (as the inverse map carries it), the
// parameter interval under it is halved, until every boundary curve lies within a tolerance of
// the outline: a face profile or a hole is then followed however smooth its colours are, which
// colour refinement alone would never ask for.
#pragma once

#include "converters/grid.h"

namespace gm {

struct BoundaryFitOptions {
    double tolerance = 0.5;   // pixels: Hausdorff distance to the outline
    int maxPatches = 400;     // the grid never grows past this many patches (or 1.5 times the
                              // initial grid's, when its slits alone need more)
    int maxRounds = 20;
};

struct BoundaryFitResult {
    int addedU = 0, addedV = 0;  // knots added
    int rounds = 0;
    double maxDeviation = 0;     // pixels, of the last grid (> tolerance only when capped)
};

// Halves boundary knot intervals until grid.build(options) meets the tolerance (or the patch
// cap or round limit is reached). When it adds knots, options.knotsU / knotsV are set to the
// complete knot vectors.
BoundaryFitResult fitBoundary(const GridBuilder& grid, GridOptions& options,
                              const BoundaryFitOptions& fit = {});

}  // namespace gm
