// Pipeline stage 8, refine (docs/design.md §3, paper §4.5): starting from the initial grid, split
// the u or v interval whose split removes the most error, re-derive the grid through the
// inverse map with the new knot (so geometry keeps following the map) and refit the colours;
// repeat until the mean error E is at most the target or the patch budget is spent.
//
// Candidates are ranked by an estimate of the error their split removes: the part of the
// residual in their column (u interval) or row (v interval) of patches that varies along the
// split direction (a u split adds freedom along u only). The top few are tried and the best
// kept; a split is accepted only when it lowers E, so E never increases along the recorded
// sequence. The new knot goes to the error-weighted mean parameter of the interval's pixels,
// kept within its middle half, so that splits home in on where the error is (a colour edge)
// rather than only bisecting.
#pragma once

#include <utility>
#include <vector>

#include "converters/colors.h"
#include "converters/grid.h"
#include "converters/region.h"
#include "converters/tri_mesh.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

struct RefineOptions {
    double maxError = 2.0;     // target E, 0–255 units (docs/design.md §6)
    int maxPatches = 400;      // budget: no split may exceed it
    int candidates = 1;        // splits tried per step, best estimated first (each try is a
                               // grid, a render and a fit)
    int maxTries = 8;          // candidates tried per step before giving up (when none improves)
    // Batches: a step splits every interval whose score is at least batchFraction of the best
    // one, in rank order, while the patch count stays within batchGrowth times the current one
    // (batchGrowth 1: one split per step, the paper's sequence). A batch that does not lower E
    // falls back to single splits.
    double batchGrowth = 1.4;
    double batchFraction = 0.25;
    // A batch that reaches the target is cut to its shortest prefix that still does, in at
    // most this many guesses (each one more fit; E interpolated in the splits' summed scores,
    // no guess when it would save under 2 % of the batch's patches); 0: the whole batch is kept.
    int trimSteps = 4;
    double minInterval = 1.0;  // intervals shorter than this (parameter units ≈ pixels) are
                               // not split
    ColorOptions color;        // mode and solver settings of every refit
};

// One state of the sequence: the initial grid, then each accepted split.
struct RefineStep {
    int columns = 0, rows = 0, patches = 0;
    double meanAbs = 0, rmse = 0, psnr = 0;  // error figures of this mesh
    char axis = 0;       // 'u' or 'v': the interval split to get here; 0 for the initial grid
    double knot = 0;     // the inserted knot, parameter units (the first, for a batch)
    std::vector<std::pair<char, double>> splits;  // every knot inserted by this step
    double seconds = 0;  // wall time spent to get here from the previous step
};

struct RefineResult {
    GradientMesh mesh;  // the last (and best) mesh, coloured
    FitError error;
    std::vector<RefineStep> steps;
    bool reachedTarget = false;  // E ≤ maxError
};

// Throws what buildGrid and computeColors throw.
RefineResult refineMesh(const GridBuilder& grid, const GridOptions& initial, const RgbaImage& image,
                        const Region& region, const RefineOptions& options = {});
RefineResult refineMesh(const TriMesh& mesh, const ParamMap& map, const GridOptions& initial,
                        const RgbaImage& image, const Region& region,
                        const RefineOptions& options = {});

}  // namespace gm
