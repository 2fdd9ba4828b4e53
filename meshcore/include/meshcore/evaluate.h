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

}  // namespace gm
