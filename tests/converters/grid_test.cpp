#include "converters/grid.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "meshcore/error.h"
#include "meshcore/evaluate.h"
#include "meshcore/validate.h"
#include "synthetic_region.h"

using namespace gm;

namespace {

Vec2 affine(double u, double v) { return {10 + 1.5 * u + 0.3 * v, 20 + 0.2 * u + 1.2 * v}; }

// Smallest Jacobian determinant over a 6×6 sample of every patch's interior (at a slit end
// the Jacobian vanishes: the hole's outline turns there).
double minJacobian(const GradientMesh& m) {
    double worst = 1e300;
    for (int j = 0; j < m.rows(); ++j)
        for (int i = 0; i < m.columns(); ++i)
            for (int a = 0; a <= 5; ++a)
                for (int b = 0; b <= 5; ++b) {
                    const PatchPoint p = evaluatePatch(m, i, j, (a + 0.5) / 6.0, (b + 0.5) / 6.0);
                    worst = std::min(worst, p.posS.x * p.posT.y - p.posS.y * p.posT.x);
                }
    return worst;
}

// A slit domain: [0,100]², slit v = 50 from u = 30 to 70, opened in the image into a hole of
// half-height g(u) (a semi-ellipse), fading away from the slit row.
struct SlitDomain {
    TriMesh tri;
    ParamMap map;
    static double g(double u) { return 0.3 * std::sqrt(std::max(0.0, (u - 30) * (70 - u))); }
    static Vec2 image(double u, double v, bool below) {
        const double w = std::max(0.0, 1 - std::abs(v - 50) / 50);
        return {20 + 2 * u, 20 + 2 * (v + (below ? 1 : -1) * g(u) * w)};
    }
};

SlitDomain makeSlitDomain() {
    SlitDomain d;
    const int n = 20;  // lattice spacing 5
    d.map.px = d.map.py = 100;
    std::vector<int> id((n + 1) * (n + 1)), idBelow((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double u = 5.0 * i, v = 5.0 * j;
            id[j * (n + 1) + i] = static_cast<int>(d.tri.vertices.size());
            d.tri.vertices.push_back(SlitDomain::image(u, v, v > 50));
            d.map.uv.push_back({u, v});
            idBelow[j * (n + 1) + i] = id[j * (n + 1) + i];
            if (j == 10 && i > 6 && i < 14) {  // the slit's lower side: its own vertices
                idBelow[j * (n + 1) + i] = static_cast<int>(d.tri.vertices.size());
                d.tri.vertices.push_back(SlitDomain::image(u, v, true));
                d.map.uv.push_back({u, v});
            }
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            // Cells just below the slit row use the lower-side copies on their top edge.
            const std::vector<int>& top = (j == 10) ? idBelow : id;
            const int a = top[j * (n + 1) + i], b = top[j * (n + 1) + i + 1];
            const int c = id[(j + 1) * (n + 1) + i + 1], e = id[(j + 1) * (n + 1) + i];
            d.tri.triangles.push_back({a, b, c});
            d.tri.triangles.push_back({a, c, e});
        }
    return d;
}

}  // namespace

TEST_CASE("knots are uniform between the required ones", "[grid]") {
    ParamMap map;
    map.px = 100;
    map.py = 60;
    GridOptions o;
    o.columns = 4;
    o.rows = 3;
    o.extraU = {10};
    std::vector<double> u, v;
    chooseKnots(map, o, u, v);
    REQUIRE(u.size() == 5);
    CHECK(u[0] == 0);
    CHECK(u[1] == Approx(10));
    CHECK(u[2] == Approx(40));
    CHECK(u[3] == Approx(70));
    CHECK(u[4] == 100);
    REQUIRE(v.size() == 4);
    CHECK(v[1] == Approx(20));

    SECTION("from a target patch size") {
        GridOptions t;
        t.targetPatchSize = 20;
        chooseKnots(map, t, u, v);
        CHECK(u.size() == 6);
        CHECK(v.size() == 4);
    }
    SECTION("explicit knots keep the required ones") {
        GridOptions e;
        e.knotsU = {0, 50, 100};
        e.extraU = {25};
        chooseKnots(map, e, u, v);
        CHECK(u == std::vector<double>{0, 25, 50, 100});
    }
    SECTION("explicit knots must span the rectangle") {
        GridOptions e;
        e.knotsU = {0, 50};
        CHECK_THROWS_AS(chooseKnots(map, e, u, v), Error);
    }
}

TEST_CASE("the grid of an affine map reproduces the affine geometry exactly", "[grid]") {
    const auto s = gmtest::makeSynthetic(200, 150, 16, 12, affine, 400, 300);
    GridOptions o;
    o.columns = 5;
    o.rows = 4;
    o.extraU = {37.3};
    const GradientMesh m = buildGrid(s.tri, s.map, o);
    REQUIRE(validateMesh(m).empty());
    REQUIRE(m.columns() == 5);
    REQUIRE(m.rows() == 4);
    CHECK(std::find(m.u.begin(), m.u.end(), 37.3) != m.u.end());
    for (int j = 0; j <= m.rows(); ++j)
        for (int i = 0; i <= m.columns(); ++i) {
            const Node& n = m.node(i, j);
            const Vec2 e = affine(m.u[i], m.v[j]);
            CHECK(n.pos.x == Approx(e.x).margin(1e-9));
            CHECK(n.pos.y == Approx(e.y).margin(1e-9));
            CHECK(n.posU.x == Approx(1.5).margin(1e-9));
            CHECK(n.posU.y == Approx(0.2).margin(1e-9));
            CHECK(n.posV.x == Approx(0.3).margin(1e-9));
            CHECK(n.posV.y == Approx(1.2).margin(1e-9));
        }
    // Inside patches too: the bicubic of an affine map is the map.
    for (int j = 0; j < m.rows(); ++j)
        for (int i = 0; i < m.columns(); ++i) {
            const double s0 = 0.3, t0 = 0.7;
            const Vec2 p = evaluatePatch(m, i, j, s0, t0).pos;
            const Vec2 e =
                affine(m.u[i] + s0 * (m.u[i + 1] - m.u[i]), m.v[j] + t0 * (m.v[j + 1] - m.v[j]));
            CHECK(p.x == Approx(e.x).margin(1e-9));
            CHECK(p.y == Approx(e.y).margin(1e-9));
        }
}

TEST_CASE("the outline of a disk's grid stays within 1 px of the circle", "[grid]") {
    const double R = 200, P = 400;
    const auto s = gmtest::makeSynthetic(P, P, 64, 64, gmtest::diskMap(P, 256, 256, R), 512, 512);
    for (int cells : {4, 8, 16}) {
        GridOptions o;
        o.columns = o.rows = cells;
        const GradientMesh m = buildGrid(s.tri, s.map, o);
        REQUIRE(validateMesh(m).empty());
        double worst = 0;
        const int C = m.columns(), Rw = m.rows();
        for (int k = 0; k <= 50; ++k) {
            const double f = k / 50.0;
            for (int i = 0; i < C; ++i) {
                for (const Vec2 p :
                     {evaluatePatch(m, i, 0, f, 0).pos, evaluatePatch(m, i, Rw - 1, f, 1).pos})
                    worst = std::max(worst, std::abs(std::hypot(p.x - 256, p.y - 256) - R));
            }
            for (int j = 0; j < Rw; ++j) {
                for (const Vec2 p :
                     {evaluatePatch(m, 0, j, 0, f).pos, evaluatePatch(m, C - 1, j, 1, f).pos})
                    worst = std::max(worst, std::abs(std::hypot(p.x - 256, p.y - 256) - R));
            }
        }
        INFO(cells << "x" << cells << " grid: outline off the circle by " << worst << " px");
        CHECK(worst < 1.0);
        CHECK(minJacobian(m) > 0);  // no fold
    }
}

TEST_CASE("boundary nodes land exactly on the region outline", "[grid]") {
    const double P = 400;
    const auto s = gmtest::makeSynthetic(P, P, 64, 64, gmtest::diskMap(P, 256, 256, 200), 512, 512);
    GridOptions o;
    o.columns = o.rows = 7;
    const GradientMesh m = buildGrid(s.tri, s.map, o);
    // Every boundary node lies on a segment of the outer loop.
    auto onOutline = [&](Vec2 p) {
        double best = 1e300;
        const auto& pts = s.region.outer.points;
        for (size_t k = 0; k < pts.size(); ++k) {
            const Vec2 a = pts[k], b = pts[(k + 1) % pts.size()];
            const Vec2 ab = b - a;
            const double f = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
            best = std::min(best, norm(p - (a + f * ab)));
        }
        return best;
    };
    for (int i = 0; i <= m.columns(); ++i) {
        CHECK(onOutline(m.node(i, 0).pos) < 1e-9);
        CHECK(onOutline(m.node(i, m.rows()).pos) < 1e-9);
    }
    for (int j = 0; j <= m.rows(); ++j) {
        CHECK(onOutline(m.node(0, j).pos) < 1e-9);
        CHECK(onOutline(m.node(m.columns(), j).pos) < 1e-9);
    }
}

TEST_CASE("slit nodes are located from above and from below", "[grid]") {
    const SlitDomain d = makeSlitDomain();
    REQUIRE(countFlippedTriangles(d.tri, d.map) == 0);
    GridOptions o;
    o.columns = 10;
    o.rows = 4;
    o.slits = {{50, 30, 70}};
    const GradientMesh m = buildGrid(d.tri, d.map, o);
    REQUIRE(validateMesh(m).empty());
    REQUIRE(m.slits.size() == 1);
    const Slit& s = m.slits[0];
    CHECK(m.v[s.row] == Approx(50));
    CHECK(m.u[s.i0] == Approx(30));
    CHECK(m.u[s.i1] == Approx(70));
    for (int i = s.i0 + 1; i < s.i1; ++i) {
        const Vec2 above = SlitDomain::image(m.u[i], 50, false);
        const Vec2 below = SlitDomain::image(m.u[i], 50, true);
        CHECK(m.node(i, s.row).pos.y == Approx(above.y).margin(1e-9));
        CHECK(s.below[i - s.i0 - 1].pos.y == Approx(below.y).margin(1e-9));
        CHECK(s.below[i - s.i0 - 1].pos.y > m.node(i, s.row).pos.y + 1);
    }
    // The hole's ends turn smoothly: the upper side leaves the left end upward (−y) and
    // reaches the right end coming down (+y); the lower side mirrors it through ±d.
    CHECK(s.left.posU.y < 0);
    CHECK(s.right.posU.y > 0);
    CHECK(minJacobian(m) > 0);
}

TEST_CASE("bad maps are rejected", "[grid]") {
    auto s = gmtest::makeSynthetic(10, 10, 2, 2, affine, 40, 40);
    ParamMap wrong = s.map;
    wrong.uv.pop_back();
    CHECK_THROWS_AS(GridBuilder(s.tri, wrong), Error);
    GridOptions o;
    o.slits = {{0, 2, 5}};
    CHECK_THROWS_AS(buildGrid(s.tri, s.map, o), Error);
}

TEST_CASE("node derivatives are shortened where knot intervals are uneven, so patches do not fold", "[grid][folds]") {
    // Along v the map crawls (0.2 px per unit) up to v = 10, then runs (2.2 px per unit): the
    // derivative shared at v = 10 fits the long interval and is ten times too long for the
    // short one, whose edges then loop.
    auto f = [](double u, double v) {
        return Vec2{20 + u, 20 + (v < 10 ? 0.2 * v : 2 + 2.2 * (v - 10))};
    };
    const auto s = gmtest::makeSynthetic(100, 100, 20, 200, f, 160, 260);
    GridOptions o;
    o.knotsU = {0, 50, 100};
    o.knotsV = {0, 10, 100};
    o.tangentLimit = 0;
    const GradientMesh loose = buildGrid(s.tri, s.map, o);
    o.tangentLimit = 1.5;
    const GradientMesh limited = buildGrid(s.tri, s.map, o);
    INFO("folded without the limit: " << countFoldedPatches(loose) << ", with: "
                                      << countFoldedPatches(limited));
    CHECK(countFoldedPatches(loose) > 0);
    CHECK(countFoldedPatches(limited) == 0);
    CHECK(validateMesh(limited).empty());
}
