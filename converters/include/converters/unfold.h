// Part of pipeline stage 6, grid: folded patches mended. A patch folds where the Jacobian of
// its position changes sign: its grid lines cross, it paints over itself or a neighbour, and a
// renderer shows a dark wedge with hairline cracks where the fit's colours for the hidden and
// the visible sheet disagree. Folds come from node derivatives (tangent handles) fitted along
// iso-curves that bend sharply between two close grid lines; the node positions themselves are
// nearly always in order. Each folded patch's corner derivatives are pulled, step by step,
// toward the chord of their grid line (the central difference of the neighbouring nodes) and
// then shortened, until the patch no longer folds; a step is kept only where it lowers the
// number of folded patches around it (3×3). Node positions never move, nor the derivatives that
// shape the mesh's outline (along the rectangle's sides), nor anything at a slit: a patch beside
// a slit end has a vanishing Jacobian by design (the hole outline turns there), and moving its
// corners would swing it over the hole. Runs at the end of every GridBuilder::build.
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

struct UnfoldOptions {
    int samples = 6;    // Jacobian samples per patch side, as countFoldedPatches
    int maxSteps = 6;   // per node: 1–4 blend toward the chord (1/2, 3/4, 7/8, all), then halve
    int maxPasses = 12;
};

struct UnfoldResult {
    int before = 0, after = 0;  // folded patches
    int nodesChanged = 0;
};

UnfoldResult unfoldPatches(GradientMesh& mesh, const UnfoldOptions& options = {});

}  // namespace gm
