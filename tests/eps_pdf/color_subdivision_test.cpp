#include "meshcore/color_subdivision.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

using namespace gm;

namespace {

// Largest deviation, over a dense grid, of a piece's colour from the bilinear interpolation of
// its corner colours (max over channels, 0–1 units).
double sampledBilinearDeviation(const BezierPatch& p, int n = 40) {
    double worst = 0;
    for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
            const double s = double(i) / n, t = double(j) / n;
            const Vec3 c = bezierColor(p, s, t);
            const Vec3 lin = (1 - s) * (1 - t) * p.c[0][0] + s * (1 - t) * p.c[3][0] +
                             (1 - s) * t * p.c[0][3] + s * t * p.c[3][3];
            for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::fabs(c[ch] - lin[ch]));
        }
    }
    return worst;
}

BezierPatch squarePatch() {
    BezierPatch p;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) p.p[a][b] = {10.0 * a, 10.0 * b};
    return p;
}

BezierPatch randomPatch(std::mt19937& rng, double amplitude) {
    std::uniform_real_distribution<double> U(0, 1), J(-2, 2);
    BezierPatch p = squarePatch();
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            p.p[a][b] = p.p[a][b] + Vec2{J(rng), J(rng)};
            p.c[a][b] = {amplitude * U(rng), amplitude * U(rng), amplitude * U(rng)};
        }
    return p;
}

}  // namespace

TEST_CASE("a patch with bilinear colour needs no subdivision", "[color_subdivision]") {
    BezierPatch p = squarePatch();
    const Vec3 c00{1, 0, 0}, c30{0, 1, 0}, c03{0, 0, 1}, c33{1, 1, 1};
    // A bilinear function in bicubic Bernstein form has its values at (a/3, b/3) as coefficients.
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            const double s = a / 3.0, t = b / 3.0;
            p.c[a][b] =
                (1 - s) * (1 - t) * c00 + s * (1 - t) * c30 + (1 - s) * t * c03 + s * t * c33;
        }
    CHECK(colorSubdivisionCount(p, 0.5 / 255) == 1);
    CHECK(colorSubdivisionCount(p, 1e-6) == 1);
}

TEST_CASE("strongly cubic colour is split until every piece is within tolerance",
          "[color_subdivision]") {
    BezierPatch p = squarePatch();
    // Smoothstep from black to white along s, a bump along t: far from bilinear.
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            const double along = (a >= 2) ? 1.0 : 0.0;
            const double bump = (b == 1 || b == 2) ? 0.6 : 0.0;
            p.c[a][b] = {along, bump, 0.5 * along + 0.3 * bump};
        }
    const double tol = 0.5 / 255;
    REQUIRE(sampledBilinearDeviation(p) > 0.05);
    const int k = colorSubdivisionCount(p, tol);
    CHECK(k > 1);
    CHECK(k < 64);
    for (const BezierPatch& piece : subdivideUniform(p, k))
        CHECK(sampledBilinearDeviation(piece) <= tol);
    // k is close to the smallest that works: one less fails when sampled.
    double worstBelow = 0;
    for (const BezierPatch& piece : subdivideUniform(p, k - 1))
        worstBelow = std::max(worstBelow, sampledBilinearDeviation(piece));
    CHECK(worstBelow > 0.8 * tol);
}

TEST_CASE("random patches: every piece within tolerance, k never grows with the tolerance",
          "[color_subdivision]") {
    std::mt19937 rng(11);
    const double tolerances[] = {0.25 / 255, 0.5 / 255, 1.0 / 255, 2.0 / 255, 8.0 / 255, 0.1};
    for (int trial = 0; trial < 60; ++trial) {
        const BezierPatch p = randomPatch(rng, trial % 2 ? 0.3 : 1.0);
        int previous = 1 << 30;
        for (double tol : tolerances) {
            const int k = colorSubdivisionCount(p, tol);
            CHECK(k <= previous);
            previous = k;
            if (trial < 15 && k < 64) {
                for (const BezierPatch& piece : subdivideUniform(p, k))
                    CHECK(sampledBilinearDeviation(piece, 16) <= tol);
            }
        }
    }
}

TEST_CASE("subdivideUniform pieces reproduce the original patch exactly", "[color_subdivision]") {
    std::mt19937 rng(5);
    const BezierPatch p = randomPatch(rng, 1.0);
    for (int k : {1, 2, 3, 5}) {
        const std::vector<BezierPatch> pieces = subdivideUniform(p, k);
        REQUIRE(pieces.size() == static_cast<size_t>(k * k));
        for (int b = 0; b < k; ++b) {
            for (int a = 0; a < k; ++a) {
                const BezierPatch& piece = pieces[static_cast<size_t>(b * k + a)];
                for (double ls : {0.0, 0.3, 0.71, 1.0}) {
                    for (double lt : {0.0, 0.45, 1.0}) {
                        const double s = (a + ls) / k, t = (b + lt) / k;
                        const Vec2 x0 = bezierPosition(p, s, t), x1 = bezierPosition(piece, ls, lt);
                        const Vec3 c0 = bezierColor(p, s, t), c1 = bezierColor(piece, ls, lt);
                        CHECK(std::fabs(x0.x - x1.x) < 1e-9);
                        CHECK(std::fabs(x0.y - x1.y) < 1e-9);
                        for (int ch = 0; ch < 3; ++ch) CHECK(std::fabs(c0[ch] - c1[ch]) < 1e-9);
                    }
                }
            }
        }
        // Neighbours share their edge control points bit for bit (no cracks after writing).
        for (int b = 0; b < k; ++b)
            for (int a = 0; a + 1 < k; ++a)
                for (int e = 0; e < 4; ++e)
                    CHECK(pieces[static_cast<size_t>(b * k + a)].p[3][e] ==
                          pieces[static_cast<size_t>(b * k + a + 1)].p[0][e]);
    }
}
