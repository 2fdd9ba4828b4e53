// The Bicubic colour model (ColorModel::Bicubic): colour slopes of every patch computed from
// node colours and corner positions by the SVG 2 `type="bicubic"` rule, exactly as Inkscape
// computes them (the rule itself is stated in color_rule.h, "WHAT INKSCAPE DOES").
//
// Unlike applyColorRule, which stores one compromise slope per node in global parameters, the
// model gives each patch corner the local slope Inkscape gives it: g·L, with g the slope of the
// corner's line and L the chord of the patch's edge at that corner. So a Bicubic mesh written
// as one SVG patch per mesh patch renders in Inkscape exactly as here (up to Inkscape's own
// 8×8 bilinear subdivision of each patch), whatever its knots.
//
// Lines, as Inkscape sees the hole-free pieces of a slit mesh (splitIntoLegacyMeshes):
//  - u-lines (along a row): one per row, seen by the patches on both sides, except that a row
//    holding a slit is two lines: the one above (main copies) and the one below (`below`
//    copies inside slits);
//  - v-lines (along a column): cut at every row that holds a slit, each band its own line,
//    starting at the `below` copy where the column crosses a slit interior.
//
// Given the current colours, the rule is linear in them (its limiter and extremum tests pick a
// branch per corner and channel): every slope is a combination of at most three node-copy
// colours along its line. The fit uses that form as the model's exact Jacobian.
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

// One channel's local slope at one patch corner along s or t: Σ weight[k] · (colour of node
// copy copy[k]), count ≤ 3 terms. Node copies are numbered as GradientMesh::nodes, then every
// slit's `below` copies in slit order.
struct RuleSlope {
    int count = 0;
    int copy[3] = {0, 0, 0};
    double weight[3] = {0, 0, 0};
};

// Everything the model makes of one patch: each corner's node copy and, per channel, the
// linear forms of its local slopes along s (u) and t (v).
struct PatchColorRule {
    int copy[2][2] = {{0, 0}, {0, 0}};
    RuleSlope s[3][2][2], t[3][2][2];  // [channel][a][b]
};

// Puts `mesh` in the Bicubic model: sets colorModel and zeroes every stored colour slope (node
// copies, slit ends, corner tangents), which the model ignores, so that files store zeros.
void useBicubicModel(GradientMesh& mesh);

// The rule's linear forms for patch (i,j) at the mesh's current colours.
PatchColorRule bicubicPatchRule(const GradientMesh& mesh, int i, int j);

// The local colour slopes (per unit of the patch's s and t) the model gives patch (i,j).
void bicubicPatchSlopes(const GradientMesh& mesh, int i, int j, Vec3 colS[2][2],
                        Vec3 colT[2][2]);

}  // namespace gm
