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

// The patch at (s, t) and the piece at its own (ls, lt): the same position and colour.
void checkSamePoint(const BezierPatch& p, double s, double t, const BezierPatch& piece, double ls,
                    double lt) {
    const Vec2 x0 = bezierPosition(p, s, t), x1 = bezierPosition(piece, ls, lt);
    const Vec3 c0 = bezierColor(p, s, t), c1 = bezierColor(piece, ls, lt);
    CHECK(std::fabs(x0.x - x1.x) < 1e-9);
    CHECK(std::fabs(x0.y - x1.y) < 1e-9);
    for (int ch = 0; ch < 3; ++ch) CHECK(std::fabs(c0[ch] - c1[ch]) < 1e-9);
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
                        checkSamePoint(p, s, t, piece, ls, lt);
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

namespace {

// squarePatch scaled to w x h pixels with random colour of the given amplitude.
BezierPatch sizedPatch(std::mt19937& rng, double w, double h, double amplitude) {
    BezierPatch p = randomPatch(rng, amplitude);
    for (auto& row : p.p)
        for (Vec2& q : row) q = {q.x * w / 30.0, q.y * h / 30.0};
    return p;
}

}  // namespace

TEST_CASE("exactColorPieces: no piece shorter than minPiece, else colorSubdivisionCount",
          "[color_subdivision]") {
    std::mt19937 rng(17);
    const double tol = 0.5 / 255;
    for (int trial = 0; trial < 40; ++trial) {
        // From 4 px (a whole image's small patches) to 300 px, elongated either way.
        const double w = 4.0 * std::pow(75.0, (trial % 8) / 7.0), h = trial % 3 ? w : w / 6;
        const BezierPatch p = sizedPatch(rng, w, h, trial % 2 ? 0.3 : 1.0);
        const int k = colorSubdivisionCount(p, tol);
        INFO("patch " << w << " x " << h << " px, k " << k);
        // No limit: the uniform count.
        CHECK(exactColorPieces(p, tol, 0) == std::make_pair(k, k));
        for (double minPiece : {0.5, 1.0, 2.0}) {
            const auto [ks, kt] = exactColorPieces(p, tol, minPiece);
            CHECK(ks <= k);
            CHECK(kt <= k);
            // Each piece at least minPiece long: the control polygon's longest run along s (t)
            // bounds the patch's extent that way.
            double runS = 0, runT = 0;
            for (int e = 0; e < 4; ++e) {
                double ls = 0, lt = 0;
                for (int q = 0; q < 3; ++q) {
                    ls += norm(p.p[q + 1][e] - p.p[q][e]);
                    lt += norm(p.p[e][q + 1] - p.p[e][q]);
                }
                runS = std::max(runS, ls);
                runT = std::max(runT, lt);
            }
            CHECK(ks <= std::max(1.0, std::ceil(runS / minPiece)));
            CHECK(kt <= std::max(1.0, std::ceil(runT / minPiece)));
            CHECK(ks >= std::min<double>(k, std::ceil(runS / minPiece)));
            CHECK(kt >= std::min<double>(k, std::ceil(runT / minPiece)));
            // Where the limit does not bind, colour is exact.
            if (ks == k && kt == k && k < 64)
                for (const BezierPatch& piece : subdivideGrid(p, ks, kt))
                    CHECK(sampledBilinearDeviation(piece, 16) <= tol);
        }
    }
    // A 4 x 4 px patch with far-from-bilinear colour: the uniform count would cut it into pieces
    // of a fraction of a pixel; at most 4 (and at least 3: its polygon is ~4 px) each way.
    BezierPatch tiny = squarePatch();
    for (auto& row : tiny.p)
        for (Vec2& q : row) q = (4.0 / 30.0) * q;
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
            tiny.c[a][b] = {(a + b) % 2 ? 1.0 : 0.0, a == 1 ? 1.0 : 0.0, 0.5};
    REQUIRE(colorSubdivisionCount(tiny, tol) > 8);
    const auto [ks, kt] = exactColorPieces(tiny, tol, 1.0);
    CHECK(ks == 4);
    CHECK(kt == 4);
    // 40 x 2 px: many pieces along s, at most 2 along t.
    BezierPatch thin = tiny;
    for (auto& row : thin.p)
        for (Vec2& q : row) q = {q.x * 10, q.y / 2};
    const auto [ts, tt] = exactColorPieces(thin, tol, 1.0);
    CHECK(ts == colorSubdivisionCount(thin, tol));
    CHECK(tt == 2);
}

TEST_CASE("subdivideGrid pieces reproduce the original patch exactly, ks and kt apart",
          "[color_subdivision]") {
    std::mt19937 rng(23);
    const BezierPatch p = randomPatch(rng, 1.0);
    for (auto [ks, kt] : {std::pair{1, 3}, std::pair{4, 2}, std::pair{3, 3}}) {
        const std::vector<BezierPatch> pieces = subdivideGrid(p, ks, kt);
        REQUIRE(pieces.size() == static_cast<size_t>(ks * kt));
        for (int b = 0; b < kt; ++b)
            for (int a = 0; a < ks; ++a) {
                const BezierPatch& piece = pieces[static_cast<size_t>(b * ks + a)];
                for (double ls : {0.0, 0.4, 1.0})
                    for (double lt : {0.0, 0.6, 1.0}) {
                        const double s = (a + ls) / ks, t = (b + lt) / kt;
                        checkSamePoint(p, s, t, piece, ls, lt);
                    }
                if (a + 1 < ks)
                    for (int e = 0; e < 4; ++e)
                        CHECK(piece.p[3][e] == pieces[static_cast<size_t>(b * ks + a + 1)].p[0][e]);
                if (b + 1 < kt)
                    for (int e = 0; e < 4; ++e)
                        CHECK(piece.p[e][3] ==
                              pieces[static_cast<size_t>((b + 1) * ks + a)].p[e][0]);
            }
    }
}
