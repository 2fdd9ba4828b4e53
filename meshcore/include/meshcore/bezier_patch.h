// Conversion of a Ferguson patch to a bicubic tensor-product Bézier patch, and exact
// subdivision of such patches (used by the vector writers for exact colour).
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

// Control points p[a][b], a along s (u), b along t (v); p[0][0] is corner (0,0).
// Colour is the same bicubic polynomial, in Bézier form, so colours are exact too.
struct BezierPatch {
    Vec2 p[4][4];
    Vec3 c[4][4];
};

// Exact: b10 = P00 + posS/3, b20 = P10 − posS/3, likewise along t; zero twist interior
// b11 = b10 + b01 − b00 and its mirror images.
BezierPatch toBezier(const PatchHermite& patch);
BezierPatch toBezier(const GradientMesh& mesh, int i, int j);

// The sub-patch over [s0,s1] x [t0,t1] ⊆ [0,1]², exact (de Casteljau / blossoming).
BezierPatch subPatch(const BezierPatch& patch, double s0, double s1, double t0, double t1);

// Evaluate a Bézier patch (position and colour) at (s,t).
Vec2 bezierPosition(const BezierPatch& patch, double s, double t);
Vec3 bezierColor(const BezierPatch& patch, double s, double t);

}  // namespace gm
