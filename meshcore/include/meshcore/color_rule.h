// The colour-derivative rule that can be recomputed from node colours alone (docs/design.md §2):
// monotone cubic, the SVG 2 / Inkscape `bicubic` rule, expressed in our global parameters.
// Besides the colours it reads node positions and knots, which every format stores. A mesh
// whose colour derivatives follow it may be stored without them, and opens in Inkscape as an
// editable bicubic mesh with our colours (exactly so under the conditions below; checked against
// Inkscape 1.2.2 renders in tests/meshcore/color_rule_inkscape_test.cpp).
//
// WHAT INKSCAPE DOES (1.2, SPMeshNodeArray::bicubic, per colour channel, on a hole-free
// meshgradient). Take one line of patch corners — a meshrow's corners left to right, or a
// column's top to bottom — with colours c_0..c_N and positions P_0..P_N, chords
// L_n = |P_{n+1} − P_n| (corner-to-corner distance in user space, not the edge's arc length)
// and secants δ_n = (c_{n+1} − c_n) / L_n. The slope g_n (colour per unit of user-space length)
// at each corner is
//   interior 0 < n < N:  0 if L_{n−1} = 0 or L_n = 0; else 0 if c_n is a strict local extremum
//                        (c_{n−1} < c_n > c_{n+1} or c_{n−1} > c_n < c_{n+1}); else the
//                        Catmull-Rom-like mean (δ_{n−1} + δ_n)/2, replaced by 3δ_{n−1} if it is
//                        larger than that in magnitude, and then by 3δ_n if larger than that;
//   first  n = 0:        2δ_0 − g_1        (parabolic; 0 if L_0 = 0),
//   last   n = N:        2δ_{N−1} − g_{N−1} (parabolic; 0 if L_{N−1} = 0),
// evaluated in that order, so that with a single patch (N = 1) g_1 is still 0 when g_0 is
// computed: g_0 = 2δ_0 and g_1 = 0. Cross derivatives are zero. Each patch then gets the
// bicubic Hermite colour with zero twists whose slope at a corner, per unit of the patch's own
// parameter 0..1, is g times the chord of the patch edge along that direction at that corner;
// Inkscape samples it at a 9×9 grid (clamped to 0..1), subdivides the patch 8×8 exactly and
// renders each piece with bilinear colour.
//
// OUR RULE. Our patch (i,j) uses Δu_i·colU as its local slope, so a corner matches Inkscape iff
// Δu_i·colU = g·L for the chord L of the patch's edge. Every derivative slot (a node's colU or
// colV, a slit `below` copy's, a SlitEnd's colU, a CornerTangent's colU) serves one or two
// "sides": the patch edges along its direction that use it, each with parameter length Δ, sign
// σ (−1 only for the patch below a slit end) and Inkscape's target local slope t = g·L. The
// rule sets the slot to
//                x = Σ σ·t / Σ Δ      (sum over the distinct sides it serves),
// which equals t/(σΔ) on a side it serves alone, and otherwise is the unique value that makes
// the local-slope errors σΔx − t of its two sides equal in size and opposite in sign (the
// minimax choice). For an interior node of a hole-free mesh this is
//                colU_i = g_i · (L_{i−1} + L_i) / (Δu_{i−1} + Δu_i),
// at the ends colU_0 = g_0·L_0/Δu_0 and colU_C = g_C·L_{C−1}/Δu_{C−1}; colV likewise.
//
// The lines (what Inkscape would see in the legacy export, where a slit mesh is written as the
// hole-free pieces obtained by cutting along every row that holds a slit):
//  - u-lines: each row without slits is one line. A row with slits is two lines: the one above
//    (used by the patches above the row; main copies inside slits) and the one below (patches
//    below; `below` copies inside slits). Outside slits both have the same nodes.
//  - v-lines: each column is cut at every row that holds a slit; a segment starting at such a
//    row starts at the `below` copy where the column crosses a slit interior, and a segment
//    ending there ends at the main copy. Segments meet at cut rows as two line ends
//    (parabolic), not as an interior point.
//
// WHEN THE EDITABLE SVG EXPORT IS EXACT (one SVG patch per mesh patch, type="bicubic", our
// node colours written exactly, i.e. multiples of 1/255): Inkscape's bicubic colour then equals
// ours exactly (before its own 8×8 bilinear subdivision) iff every slot serves its sides
// exactly, which for a rule-following mesh means:
//  - at every interior node of every line, g_n = 0 or L_{n−1}/Δ_{n−1} = L_n/Δ_n (the chord per
//    unit parameter is the same on both sides; true e.g. for uniform knots and equal chords,
//    or for corners on an affine lattice of the knots, whatever the edges' curvature);
//  - at a node on a cut row outside slit interiors: the band above's end slope and the band
//    below's start slope agree, g↑·L↑/Δv↑ = g↓·L↓/Δv↓ (both sides see one colV);
//  - at a slit end: the lines above and below give the same g on the outer side (one colU
//    serves both), and g_above·L_above = −g_below·L_below on the slit side (the ±d rule); both
//    hold when both are 0, e.g. when the slit end's colour is an extremum along both lines.
//    Elsewhere the slit-end value is the minimax compromise d = (t_above − t_below)/(2Δu), 0
//    when the two sides agree. (A row end next to a slit end inherits the difference: its
//    parabolic slope uses its neighbour's.)
// bicubicExportDeviation measures how far a mesh is from that (whatever its derivatives).
//
// SPLITTING. applyColorRule then splitIntoLegacyMeshes gives the same pieces as
// splitIntoLegacyMeshes then applyColorRule on each piece (a piece's slit-end kinks are
// CornerTangents, which the rule sets like any slot) except where the whole mesh has one value
// for two sides that the pieces separate: colV of the nodes on a cut row outside slit interiors,
// and colU (node and ±d) at slit ends and at a row end next to one — exactly the places listed
// above, and equal there under the same conditions. This cannot hold in general: the
// representation stores one colV per node and ties the two slit sides by ±d.
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

// Overwrites colU/colV of every node (slit copies and slit ends included) and colU of every
// CornerTangent with the rule's values computed from the node colours, node positions and the
// knots. A slot no patch uses (a CornerTangent shadowed by a later one for the same corner)
// gets 0.
void applyColorRule(GradientMesh& mesh);

// The largest absolute difference (0–1 colour units per unit parameter, max over nodes, slit
// copies, slit ends, corner tangents and channels) between the mesh's colour derivatives and the
// rule's.
double colorRuleDeviation(const GradientMesh& mesh);

// True when the mesh's colour derivatives are the rule's to within `tolerance`.
bool followsColorRule(const GradientMesh& mesh, double tolerance = 1e-12);

// The largest difference (0–1 colour units per patch parameter, max over patch corners,
// directions and channels) between the local colour slopes the mesh's patches use and those
// Inkscape computes when the mesh (or, with slits, each of its legacy pieces) is written with
// type="bicubic" and our node colours. 0 means the editable export renders our colours up to
// Inkscape's 8×8 subdivision; otherwise the colour difference inside a patch is at most half
// this value: along each direction the two slope basis functions sum in magnitude to
// s(1−s) ≤ 1/4.
double bicubicExportDeviation(const GradientMesh& mesh);

}  // namespace gm
