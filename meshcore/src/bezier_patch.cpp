#include "meshcore/bezier_patch.h"

namespace gm {

namespace {
template <class T>
void hermiteToBezier(const PatchHermite& h, T (&p)[4][4], T HermiteCorner::*val,
                     T HermiteCorner::*ds, T HermiteCorner::*dt) {
    const HermiteCorner& c00 = h.corner[0][0];
    const HermiteCorner& c10 = h.corner[1][0];
    const HermiteCorner& c01 = h.corner[0][1];
    const HermiteCorner& c11 = h.corner[1][1];
    p[0][0] = c00.*val;
    p[3][0] = c10.*val;
    p[0][3] = c01.*val;
    p[3][3] = c11.*val;
    // Edges: one third of the scaled derivative from each corner.
    p[1][0] = c00.*val + (1.0 / 3) * (c00.*ds);
    p[2][0] = c10.*val - (1.0 / 3) * (c10.*ds);
    p[1][3] = c01.*val + (1.0 / 3) * (c01.*ds);
    p[2][3] = c11.*val - (1.0 / 3) * (c11.*ds);
    p[0][1] = c00.*val + (1.0 / 3) * (c00.*dt);
    p[0][2] = c01.*val - (1.0 / 3) * (c01.*dt);
    p[3][1] = c10.*val + (1.0 / 3) * (c10.*dt);
    p[3][2] = c11.*val - (1.0 / 3) * (c11.*dt);
    // Zero twist at each corner.
    p[1][1] = p[1][0] + p[0][1] - p[0][0];
    p[2][1] = p[2][0] + p[3][1] - p[3][0];
    p[1][2] = p[0][2] + p[1][3] - p[0][3];
    p[2][2] = p[3][2] + p[2][3] - p[3][3];
}

// The blossom of a cubic with Bézier coefficients q at (x1, x2, x3).
template <class T>
T blossom(const T q[4], double x1, double x2, double x3) {
    T a[3], b[2];
    for (int k = 0; k < 3; ++k) a[k] = (1 - x1) * q[k] + x1 * q[k + 1];
    for (int k = 0; k < 2; ++k) b[k] = (1 - x2) * a[k] + x2 * a[k + 1];
    return (1 - x3) * b[0] + x3 * b[1];
}

// Coefficients of the same cubic restricted to [lo, hi], reparameterised to [0,1].
template <class T>
void restrict1(const T q[4], double lo, double hi, T out[4]) {
    out[0] = blossom(q, lo, lo, lo);
    out[1] = blossom(q, lo, lo, hi);
    out[2] = blossom(q, lo, hi, hi);
    out[3] = blossom(q, hi, hi, hi);
}

template <class T>
void restrict2(const T (&in)[4][4], double s0, double s1, double t0, double t1, T (&out)[4][4]) {
    T tmp[4][4];
    for (int b = 0; b < 4; ++b) {  // along s for each t-row of coefficients
        T q[4] = {in[0][b], in[1][b], in[2][b], in[3][b]}, r[4];
        restrict1(q, s0, s1, r);
        for (int a = 0; a < 4; ++a) tmp[a][b] = r[a];
    }
    for (int a = 0; a < 4; ++a) restrict1(tmp[a], t0, t1, out[a]);
}

template <class T>
T evaluate2(const T (&p)[4][4], double s, double t) {
    T col[4];
    for (int a = 0; a < 4; ++a) col[a] = blossom(p[a], t, t, t);
    return blossom(col, s, s, s);
}
}  // namespace

BezierPatch toBezier(const PatchHermite& patch) {
    BezierPatch b;
    hermiteToBezier(patch, b.p, &HermiteCorner::pos, &HermiteCorner::posS, &HermiteCorner::posT);
    hermiteToBezier(patch, b.c, &HermiteCorner::col, &HermiteCorner::colS, &HermiteCorner::colT);
    return b;
}

BezierPatch toBezier(const GradientMesh& mesh, int i, int j) {
    return toBezier(patchHermite(mesh, i, j));
}

BezierPatch subPatch(const BezierPatch& patch, double s0, double s1, double t0, double t1) {
    BezierPatch out;
    restrict2(patch.p, s0, s1, t0, t1, out.p);
    restrict2(patch.c, s0, s1, t0, t1, out.c);
    return out;
}

Vec2 bezierPosition(const BezierPatch& patch, double s, double t) {
    return evaluate2(patch.p, s, t);
}

Vec3 bezierColor(const BezierPatch& patch, double s, double t) {
    return evaluate2(patch.c, s, t);
}

}  // namespace gm
