#include "meshcore/evaluate.h"

namespace gm {

void hermiteBasis(double s, double h[4]) {
    const double s2 = s * s, s3 = s2 * s;
    h[0] = 1 - 3 * s2 + 2 * s3;
    h[1] = 3 * s2 - 2 * s3;
    h[2] = s - 2 * s2 + s3;
    h[3] = s3 - s2;
}

void hermiteBasisDerivative(double s, double dh[4]) {
    const double s2 = s * s;
    dh[0] = -6 * s + 6 * s2;
    dh[1] = 6 * s - 6 * s2;
    dh[2] = 1 - 4 * s + 3 * s2;
    dh[3] = 3 * s2 - 2 * s;
}

PatchPoint evaluatePatch(const PatchHermite& p, double s, double t) {
    double hs[4], ht[4], dhs[4], dht[4];
    hermiteBasis(s, hs);
    hermiteBasis(t, ht);
    hermiteBasisDerivative(s, dhs);
    hermiteBasisDerivative(t, dht);
    auto pos = [](const HermiteCorner& c) { return c.pos; };
    auto posS = [](const HermiteCorner& c) { return c.posS; };
    auto posT = [](const HermiteCorner& c) { return c.posT; };
    auto col = [](const HermiteCorner& c) { return c.col; };
    auto colS = [](const HermiteCorner& c) { return c.colS; };
    auto colT = [](const HermiteCorner& c) { return c.colT; };
    PatchPoint r;
    r.pos = hermiteSum<Vec2>(p, hs, ht, pos, posS, posT);
    r.col = hermiteSum<Vec3>(p, hs, ht, col, colS, colT);
    r.posS = hermiteSum<Vec2>(p, dhs, ht, pos, posS, posT);
    r.posT = hermiteSum<Vec2>(p, hs, dht, pos, posS, posT);
    return r;
}

PatchPoint evaluatePatch(const GradientMesh& mesh, int i, int j, double s, double t) {
    return evaluatePatch(patchHermite(mesh, i, j), s, t);
}

}  // namespace gm
