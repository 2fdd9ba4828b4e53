// Exact evaluation of a Ferguson patch (paper §3): F(s,t) = S·C·Q·Cᵀ·Tᵀ per component.
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

struct PatchPoint {
    Vec2 pos;         // pixels
    Vec3 col;         // sRGB 0–1
    Vec2 posS, posT;  // Jacobian columns: d pos / ds, d pos / dt (local parameters)
};

// s, t ∈ [0,1] local to the patch.
PatchPoint evaluatePatch(const PatchHermite& patch, double s, double t);
PatchPoint evaluatePatch(const GradientMesh& mesh, int i, int j, double s, double t);

// Cubic Hermite basis values h[0..3] (value at 0, value at 1, slope at 0, slope at 1) and
// their derivatives.
void hermiteBasis(double s, double h[4]);
void hermiteBasisDerivative(double s, double dh[4]);

// One quantity of a patch from basis values along s (hs) and t (ht): the sum over its four
// corners of value(c)·hs[a]·ht[b] + slopeS(c)·hs[2+a]·ht[b] + slopeT(c)·hs[a]·ht[2+b] (zero
// twists). With a basis derivative in place of hs or ht it is the partial derivative along s
// or t; `get*` pick the quantity (pos, posS, posT or col, colS, colT) from a corner.
template <class T, class Get, class GetS, class GetT>
T hermiteSum(const PatchHermite& p, const double hs[4], const double ht[4], Get value, GetS slopeS,
             GetT slopeT) {
    T r{};
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
            const HermiteCorner& c = p.corner[a][b];
            r = r + (hs[a] * ht[b]) * value(c) + (hs[2 + a] * ht[b]) * slopeS(c) +
                (hs[a] * ht[2 + b]) * slopeT(c);
        }
    return r;
}

// The colour of a patch at basis values hs (along s) and ht (along t).
inline Vec3 hermiteColor(const PatchHermite& p, const double hs[4], const double ht[4]) {
    return hermiteSum<Vec3>(
        p, hs, ht, [](const HermiteCorner& c) { return c.col; },
        [](const HermiteCorner& c) { return c.colS; }, [](const HermiteCorner& c) { return c.colT; });
}

}  // namespace gm
