#include <catch2/catch.hpp>

#include "meshcore/bezier_patch.h"
#include "meshcore/evaluate.h"
#include "meshcore/synthetic_meshes.h"

using namespace gm;

namespace {
// A 1×1 mesh on the square [0,10]², affine, with chosen colours.
GradientMesh square() {
    GradientMesh m(1, 1);
    for (int j = 0; j <= 1; ++j)
        for (int i = 0; i <= 1; ++i) {
            Node& n = m.node(i, j);
            n.pos = {10.0 * i, 10.0 * j};
            n.posU = {10, 0};
            n.posV = {0, 10};
        }
    return m;
}
}  // namespace

TEST_CASE("hermite basis has the textbook values", "[evaluate]") {
    double h[4];
    hermiteBasis(0.5, h);
    CHECK(h[0] == Approx(0.5));
    CHECK(h[1] == Approx(0.5));
    CHECK(h[2] == Approx(0.125));
    CHECK(h[3] == Approx(-0.125));
    hermiteBasis(0.25, h);
    CHECK(h[1] == Approx(0.15625));  // 3/16 - 2/64
}

TEST_CASE("evaluation matches hand-computed values", "[evaluate]") {
    GradientMesh m = square();
    m.node(1, 0).col = {1, 0, 0};
    m.node(1, 1).col = {1, 0, 0};
    // Red follows h1(s): 0.15625 at s = 0.25 whatever t is.
    PatchPoint p = evaluatePatch(m, 0, 0, 0.25, 0.7);
    CHECK(p.col.r == Approx(0.15625));
    CHECK(p.col.g == Approx(0.0));
    CHECK(p.pos.x == Approx(2.5));
    CHECK(p.pos.y == Approx(7.0));
    CHECK(p.posS.x == Approx(10.0));
    CHECK(p.posS.y == Approx(0.0).margin(1e-12));
    CHECK(p.posT.y == Approx(10.0));

    // A u-derivative of green at node (0,0) adds h2(s)·h0(t)·Δu·colU.
    m.u = {0, 2};  // Δu = 2 scales the global derivatives
    m.node(0, 0).colU = {0, 0.5, 0};
    for (Node& n : m.nodes) n.posU = {5, 0};  // keep the geometry: 5 px per unit of u
    p = evaluatePatch(m, 0, 0, 0.5, 0.5);
    CHECK(p.col.g == Approx(0.125 * 0.5 * 2 * 0.5));  // h2(.5)·h0(.5)·Δu·0.5
    CHECK(p.pos.x == Approx(5.0));
    CHECK(p.posS.x == Approx(10.0));
}

TEST_CASE("colour is C1 across a shared patch edge in the global parameter", "[evaluate]") {
    GradientMesh m = makeCurvedMesh(2, 1, 0, 0, 100, 50, 1.0, 7);
    m.u = {0, 0.3, 1.0};  // unequal intervals: derivatives are global, patches rescale them
    const double du0 = 0.3, du1 = 0.7, h = 1e-6;
    for (double t : {0.0, 0.3, 0.8}) {
        const Vec3 left1 = evaluatePatch(m, 0, 0, 1.0, t).col;
        const Vec3 left0 = evaluatePatch(m, 0, 0, 1.0 - h, t).col;
        const Vec3 right0 = evaluatePatch(m, 1, 0, 0.0, t).col;
        const Vec3 right1 = evaluatePatch(m, 1, 0, h, t).col;
        for (int c = 0; c < 3; ++c) {
            CHECK(left1[c] == Approx(right0[c]).margin(1e-12));
            const double dl = (left1[c] - left0[c]) / h / du0;
            const double dr = (right1[c] - right0[c]) / h / du1;
            CHECK(dl == Approx(dr).margin(1e-4));
        }
    }
}

TEST_CASE("hole outline is smooth through the slit ends (the ±d rule)", "[evaluate][slit]") {
    const GradientMesh m = makeHoledMesh(2, 0, 0, 200, 300);
    REQUIRE(m.slits.size() == 2);
    for (const Slit& s : m.slits) {
        // Left end: the upper arc is the bottom edge of patch (i0, row-1), the lower arc the top
        // edge of patch (i0, row); both leave the end node at s = 0.
        const PatchPoint up = evaluatePatch(m, s.i0, s.row - 1, 0.0, 1.0);
        const PatchPoint low = evaluatePatch(m, s.i0, s.row, 0.0, 0.0);
        CHECK(up.pos.x == Approx(low.pos.x));
        CHECK(up.pos.y == Approx(low.pos.y));
        CHECK(norm(up.posS) > 1.0);
        CHECK(up.posS.x == Approx(-low.posS.x).margin(1e-12));
        CHECK(up.posS.y == Approx(-low.posS.y).margin(1e-12));
        // Right end: both arcs arrive at s = 1.
        const PatchPoint upR = evaluatePatch(m, s.i1 - 1, s.row - 1, 1.0, 1.0);
        const PatchPoint lowR = evaluatePatch(m, s.i1 - 1, s.row, 1.0, 0.0);
        CHECK(upR.posS.x == Approx(-lowR.posS.x).margin(1e-12));
        CHECK(upR.posS.y == Approx(-lowR.posS.y).margin(1e-12));
        // The two arcs really are apart in the middle: a hole, not a crack.
        const PatchPoint upMid = evaluatePatch(m, s.i0 + 1, s.row - 1, 0.5, 1.0);
        const PatchPoint lowMid = evaluatePatch(m, s.i0 + 1, s.row, 0.5, 0.0);
        CHECK(lowMid.pos.y - upMid.pos.y > 5.0);
    }
}

TEST_CASE("Bezier conversion is exact for position and colour", "[bezier]") {
    const GradientMesh m = makeCurvedMesh(3, 2, 10, 20, 300, 200, 1.0, 3);
    for (int j = 0; j < m.rows(); ++j)
        for (int i = 0; i < m.columns(); ++i) {
            const BezierPatch b = toBezier(m, i, j);
            for (double s : {0.0, 0.21, 0.5, 0.93, 1.0})
                for (double t : {0.0, 0.37, 0.66, 1.0}) {
                    const PatchPoint p = evaluatePatch(m, i, j, s, t);
                    const Vec2 q = bezierPosition(b, s, t);
                    const Vec3 c = bezierColor(b, s, t);
                    CHECK(q.x == Approx(p.pos.x).margin(1e-9));
                    CHECK(q.y == Approx(p.pos.y).margin(1e-9));
                    for (int k = 0; k < 3; ++k) CHECK(c[k] == Approx(p.col[k]).margin(1e-12));
                }
        }
}

TEST_CASE("Bezier sub-patches reproduce the patch exactly", "[bezier]") {
    const GradientMesh m = makeCurvedMesh(1, 1, 0, 0, 100, 80, 1.0, 4);
    const BezierPatch b = toBezier(m, 0, 0);
    const BezierPatch sub = subPatch(b, 0.2, 0.7, 0.1, 0.45);
    for (double s : {0.0, 0.3, 1.0})
        for (double t : {0.0, 0.5, 1.0}) {
            const Vec2 q = bezierPosition(sub, s, t);
            const Vec2 r = bezierPosition(b, 0.2 + 0.5 * s, 0.1 + 0.35 * t);
            CHECK(q.x == Approx(r.x).margin(1e-9));
            CHECK(q.y == Approx(r.y).margin(1e-9));
            CHECK(bezierColor(sub, s, t).g == Approx(bezierColor(b, 0.2 + 0.5 * s, 0.1 + 0.35 * t).g).margin(1e-12));
        }
}
