#include "meshcore/color_subdivision.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace gm {

namespace {

// One colour channel of a bicubic in Bernstein form: q[a][b], a along s, b along t.
using Scalar44 = double[4][4];

// de Casteljau split of a cubic at 1/2 into its left and right halves.
void splitHalf(const double q[4], double left[4], double right[4]) {
    const double a0 = 0.5 * (q[0] + q[1]), a1 = 0.5 * (q[1] + q[2]), a2 = 0.5 * (q[2] + q[3]);
    const double b0 = 0.5 * (a0 + a1), b1 = 0.5 * (a1 + a2);
    const double m = 0.5 * (b0 + b1);
    left[0] = q[0];
    left[1] = a0;
    left[2] = b0;
    left[3] = m;
    right[0] = m;
    right[1] = b1;
    right[2] = a2;
    right[3] = q[3];
}

// The blossom of the cubic with Bernstein coefficients q at (x1, x2, x3).
double blossom(const double q[4], double x1, double x2, double x3) {
    double a[3], b[2];
    for (int k = 0; k < 3; ++k) a[k] = (1 - x1) * q[k] + x1 * q[k + 1];
    for (int k = 0; k < 2; ++k) b[k] = (1 - x2) * a[k] + x2 * a[k + 1];
    return (1 - x3) * b[0] + x3 * b[1];
}
// Coefficients of the cubic q restricted to [lo, hi], reparameterised to [0,1].
void restrictCubic(const double q[4], double lo, double hi, double out[4]) {
    out[0] = blossom(q, lo, lo, lo);
    out[1] = blossom(q, lo, lo, hi);
    out[2] = blossom(q, lo, hi, hi);
    out[3] = blossom(q, hi, hi, hi);
}

// True when |d| ≤ tol everywhere on [0,1]², for a bicubic d in Bernstein form.
//
// The Bernstein coefficients bound the polynomial (convex hull property), and the corner
// coefficients are values of it. When the bound is inconclusive the polynomial is split at the
// midpoints and each quarter tested again; after `depth` levels an inconclusive piece counts as
// failing. One level already makes the bound tight for the dominant quadratic error term
// (s(1−s) has coefficients 0, 1/4, 1/4, 0 on each half), so the result is the true answer up to
// a small margin on the safe side, and never accepts a deviation above tol.
bool withinTolerance(const Scalar44& d, double tol, int depth) {
    double bound = 0;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) bound = std::max(bound, std::fabs(d[a][b]));
    if (bound <= tol) return true;
    const double corners = std::max(std::max(std::fabs(d[0][0]), std::fabs(d[3][0])),
                                    std::max(std::fabs(d[0][3]), std::fabs(d[3][3])));
    if (corners > tol || depth == 0) return false;
    // Split along s (each t-row of coefficients), then along t.
    double left[4][4], right[4][4];
    for (int b = 0; b < 4; ++b) {
        const double q[4] = {d[0][b], d[1][b], d[2][b], d[3][b]};
        double l[4], r[4];
        splitHalf(q, l, r);
        for (int a = 0; a < 4; ++a) {
            left[a][b] = l[a];
            right[a][b] = r[a];
        }
    }
    for (const auto* half : {&left, &right}) {
        double lower[4][4], upper[4][4];
        for (int a = 0; a < 4; ++a) splitHalf((*half)[a], lower[a], upper[a]);
        if (!withinTolerance(lower, tol, depth - 1)) return false;
        if (!withinTolerance(upper, tol, depth - 1)) return false;
    }
    return true;
}

// The deviation of a piece's colour (coefficients c) from the bilinear interpolation of its
// corner values, in Bernstein form. A bilinear function degree-elevated to bicubic has as its
// coefficients its own values at (a/3, b/3).
void bilinearDeviation(const Scalar44& c, Scalar44& d) {
    const double c00 = c[0][0], c30 = c[3][0], c03 = c[0][3], c33 = c[3][3];
    for (int a = 0; a < 4; ++a) {
        const double s = a / 3.0;
        for (int b = 0; b < 4; ++b) {
            const double t = b / 3.0;
            const double lin =
                (1 - s) * (1 - t) * c00 + s * (1 - t) * c30 + (1 - s) * t * c03 + s * t * c33;
            d[a][b] = c[a][b] - lin;
        }
    }
}

constexpr int kRefineDepth = 5;

// True when every piece of the k×k split of channel q is within tol of its bilinear colour.
bool channelPasses(const Scalar44& q, int k, double tol) {
    std::vector<double> strips(static_cast<size_t>(k) * 16);  // [piece a][a'][b]
    for (int a = 0; a < k; ++a) {
        const double s0 = static_cast<double>(a) / k, s1 = static_cast<double>(a + 1) / k;
        for (int b = 0; b < 4; ++b) {
            const double row[4] = {q[0][b], q[1][b], q[2][b], q[3][b]};
            double r[4];
            restrictCubic(row, s0, s1, r);
            for (int aa = 0; aa < 4; ++aa) strips[static_cast<size_t>(a) * 16 + aa * 4 + b] = r[aa];
        }
    }
    for (int b = 0; b < k; ++b) {
        const double t0 = static_cast<double>(b) / k, t1 = static_cast<double>(b + 1) / k;
        for (int a = 0; a < k; ++a) {
            Scalar44 piece, dev;
            for (int aa = 0; aa < 4; ++aa)
                restrictCubic(&strips[static_cast<size_t>(a) * 16 + aa * 4], t0, t1, piece[aa]);
            bilinearDeviation(piece, dev);
            if (!withinTolerance(dev, tol, kRefineDepth)) return false;
        }
    }
    return true;
}

}  // namespace

int colorSubdivisionCount(const BezierPatch& patch, double tolerance, int maxK) {
    assert(maxK >= 1);
    Scalar44 channel[3];
    for (int ch = 0; ch < 3; ++ch)
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) channel[ch][a][b] = patch.c[a][b][ch];
    // Candidates are tried in increasing order, and whether k passes only gets easier as the
    // tolerance grows, so the result never increases with the tolerance. Most patches pass at
    // k = 1 after one 16-coefficient test per channel.
    for (int k = 1; k < maxK; ++k) {
        bool ok = true;
        for (int ch = 0; ch < 3 && ok; ++ch) ok = channelPasses(channel[ch], k, tolerance);
        if (ok) return k;
    }
    return maxK;
}

std::pair<int, int> exactColorPieces(const BezierPatch& patch, double tolerance, double minPiece,
                                     int maxK) {
    assert(maxK >= 1);
    // The control polygon's longest run along s and along t bounds the patch's extent that way.
    double along[2] = {0, 0};
    for (int e = 0; e < 4; ++e) {
        double ls = 0, lt = 0;
        for (int k = 0; k < 3; ++k) {
            ls += norm(patch.p[k + 1][e] - patch.p[k][e]);
            lt += norm(patch.p[e][k + 1] - patch.p[e][k]);
        }
        along[0] = std::max(along[0], ls);
        along[1] = std::max(along[1], lt);
    }
    int cap[2] = {maxK, maxK};
    if (minPiece > 0)
        for (int d = 0; d < 2; ++d)
            cap[d] = static_cast<int>(std::clamp(std::ceil(along[d] / minPiece), 1.0, double(maxK)));
    const int k = colorSubdivisionCount(patch, tolerance, std::max(cap[0], cap[1]));
    return {std::min(k, cap[0]), std::min(k, cap[1])};
}

std::vector<BezierPatch> subdivideGrid(const BezierPatch& patch, int ks, int kt) {
    assert(ks >= 1 && kt >= 1);
    std::vector<BezierPatch> pieces;
    pieces.reserve(static_cast<size_t>(ks) * kt);
    // Shared edges come from identical computations (the same blossom arguments), so
    // neighbouring pieces meet bit-exactly.
    for (int b = 0; b < kt; ++b) {
        const double t0 = static_cast<double>(b) / kt, t1 = static_cast<double>(b + 1) / kt;
        for (int a = 0; a < ks; ++a) {
            const double s0 = static_cast<double>(a) / ks, s1 = static_cast<double>(a + 1) / ks;
            pieces.push_back(ks == 1 && kt == 1 ? patch : subPatch(patch, s0, s1, t0, t1));
        }
    }
    return pieces;
}

std::vector<BezierPatch> subdivideUniform(const BezierPatch& patch, int k) {
    return subdivideGrid(patch, k, k);
}

}  // namespace gm
