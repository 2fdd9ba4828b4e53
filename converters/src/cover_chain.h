// One side of a grid's parameter rectangle as a chain of boundary edges fitted one-sided to the
// region's outline (GridOptions::outlineCover): the curve covers the outline's tips without
// straying farther from it than the plain least-squares fit does.
#pragma once

#include <functional>
#include <vector>

#include "meshcore/geometry.h"

namespace gm {

struct CoverChain {
    std::vector<Vec2> pos;         // node positions
    std::vector<Vec2> derivative;  // node derivatives
    std::vector<Vec2> plainPos, plainDerivative;  // the plain fit's
    // Per edge: knot interval, the outline densely sampled, curve samples of the deviation
    // measure, and the deviation bound.
    std::vector<double> delta;
    std::vector<std::vector<Vec2>> outline;
    std::vector<int> steps;
    std::vector<double> bound;

    // Two-sided deviation of edge k with end nodes (a, da), (b, db), as boundary.cpp measures it.
    double deviation(int k, Vec2 a, Vec2 da, Vec2 b, Vec2 db) const;
};

// The chain of N = delta.size() edges between the outline points P[0..N] (P[0] and P[N] are the
// rectangle's corners and stay put). Unknowns per node k: its derivative D_k (pixels per unit)
// and an offset s_k along the outline's outward normal ν_k. Edge k is
// h0·(P_k + s_k·ν_k) + h1·(P_k+1 + s_k+1·ν_k+1) + Δ_k·(h2·D_k + h3·D_k+1).
//
// Round 0 is DerivativeFit's least-squares fit (the outline at parameters `tau` of each edge,
// a slight pull toward the chord, offsets 0). Later rounds add stiff penalties, linearised at
// the current curve: every dense outline point more than `cover` outside the curve is pulled to
// within cover/2 of it, and the curve is kept within each edge's bound of the outline (the plain
// fit's two-sided deviation on that edge, at least `slack`), both ways; derivatives longer than
// `tangentLimit` times their edges' chord per unit are penalised. Penalties are soft, so a last
// pass blends each node back toward the plain fit until no edge strays farther than its bound:
// covering the outline's tips never makes an edge's outline deviation worse than the plain
// fit's (or than slack). `outline(k, t)` is the outline point of edge k at t ∈ [0, 1];
// inside[k] a point inside the region near edge k (it orients the normals).
CoverChain fitCoverChain(const std::vector<Vec2>& P, const std::vector<double>& delta,
                         const std::function<Vec2(int, double)>& outline,
                         const std::vector<Vec2>& inside, const std::vector<double>& tau,
                         double cover, double slack, double tangentLimit);

}  // namespace gm
