#include "meshcore/color_rule.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "meshcore/gradient_mesh.h"
#include "meshcore/split_legacy.h"

using namespace gm;

namespace {

// A C×R mesh whose node (i,j) sits at (x[i], y[j]) with the given knots; colours zero.
GradientMesh lattice(const std::vector<double>& x, const std::vector<double>& y,
                     const std::vector<double>& u, const std::vector<double>& v) {
    const int C = static_cast<int>(x.size()) - 1, R = static_cast<int>(y.size()) - 1;
    GradientMesh m(C, R);
    m.u = u;
    m.v = v;
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            Node& n = m.node(i, j);
            n.pos = {x[i], y[j]};
            n.posU = {10, 0};
            n.posV = {0, 10};
        }
    return m;
}

std::vector<double> iota(int n, double step) {
    std::vector<double> r;
    for (int k = 0; k <= n; ++k) r.push_back(step * k);
    return r;
}

void setRow(GradientMesh& m, int j, int channel, const std::vector<double>& values) {
    for (int i = 0; i <= m.columns(); ++i) m.node(i, j).col[channel] = values[i];
}

// One slit on row 2 of a 4×4 mesh, columns 1..3 (one interior column, 2), opened into a hole.
GradientMesh slitMesh(bool symmetric) {
    // Non-uniform v knots, rows at y = 15 v (chord per unit v is 15 px on every column).
    GradientMesh m =
        lattice({0, 20, 40, 60, 80}, {0, 15, 37.5, 45, 60}, iota(4, 1.0), {0, 1, 2.5, 3, 4});
    Slit s;
    s.row = 2;
    s.i0 = 1;
    s.i1 = 3;
    s.below.resize(1);
    m.node(2, 2).pos = {40, 32.5};
    s.below[0] = m.node(2, 2);
    s.below[0].pos = {40, 42.5};
    s.left.posU = {0, -10};
    s.right.posU = {0, 10};
    // Red: linear in v along columns (through the cut row) around a peak at the slit ends; the
    // copies are below the ends' value, so the slit ends are extrema along both row lines.
    const double h[5] = {0.2, 0.6, 0.3, 0.6, 0.2};
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i) {
            Node& n = m.node(i, j);
            n.col = {h[i] + 0.05 * (m.v[j] - 2.5), 0.4 + 0.1 * m.v[j], 0.3};
        }
    s.below[0].col = {0.35, 0.65, 0.3};
    if (!symmetric) {
        // Generic colours: the ends are no longer extrema and the cut row is not linear.
        m.node(1, 2).col = {0.45, 0.7, 0.1};
        m.node(3, 2).col = {0.5, 0.2, 0.9};
        m.node(0, 2).col.r = 0.9;
        m.node(4, 1).col.g = 0.05;
        s.below[0].col = {0.55, 0.1, 0.6};
    }
    m.slits.push_back(s);
    return m;
}

// The legacy pieces of slitMesh, cut by hand (rows 0..2 with the main copies, rows 2..4 with the
// below copy), slit-end kinks as corner tangents. Derivatives are copied from the whole.
std::vector<GradientMesh> cutSlitMesh(const GradientMesh& m) {
    const Slit& s = m.slits[0];
    GradientMesh up(4, 2), down(4, 2);
    up.u = down.u = m.u;
    up.v = {m.v[0], m.v[1], m.v[2]};
    down.v = {m.v[2], m.v[3], m.v[4]};
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 4; ++i) {
            up.node(i, j) = m.node(i, j);
            down.node(i, j) = m.node(i, j + 2);
        }
    down.node(2, 0) = s.below[0];
    up.tangents.push_back({s.i0, 1, 0, 1, s.left.posU, s.left.colU});
    up.tangents.push_back({s.i1 - 1, 1, 1, 1, s.right.posU, s.right.colU});
    down.tangents.push_back({s.i0, 0, 0, 0, -s.left.posU, -s.left.colU});
    down.tangents.push_back({s.i1 - 1, 0, 1, 0, -s.right.posU, -s.right.colU});
    return {up, down};
}

// A 3×2 mesh whose corners lie on an affine lattice of non-uniform knots (chord per unit knot
// the same on both sides of every node), with uneven colours; zero derivatives.
GradientMesh affineLattice() {
    const std::vector<double> u{0, 0.7, 1.5, 3.0}, v{0, 1.2, 2.0};
    std::vector<double> x, y;
    for (double k : u) x.push_back(30 + 80 * k);
    for (double k : v) y.push_back(20 + 90 * k);
    GradientMesh m = lattice(x, y, u, v);
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 3; ++i)
            m.node(i, j).col = {std::fmod(0.37 * i + 0.61 * j, 1.0), 0.1 * i * j,
                                (i == 1) ? 0.9 : 0.2};
    return m;
}

double diff(Vec3 a, Vec3 b) {
    return std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b)});
}

}  // namespace

TEST_CASE("1-D row: Catmull-Rom slopes, extrema, clamping and parabolic ends", "[color_rule]") {
    // Chords 10 px per unit u: colU = 10 × Inkscape's per-pixel slope.
    GradientMesh m = lattice(iota(4, 10), {0, 10}, iota(4, 1), {0, 1});
    setRow(m, 0, 0, {0.0, 0.1, 0.3, 0.4, 0.8});   // monotone
    setRow(m, 0, 1, {0.0, 0.01, 0.5, 0.6, 0.6});  // clamped to 3 × the left secant; flat run
    setRow(m, 0, 2, {0.2, 0.5, 0.3, 0.3, 0.1});   // a peak, then plateaus
    setRow(m, 1, 0, {0.0, 0.5, 0.55, 0.6, 0.6});  // clamped to 3 × the right secant
    applyColorRule(m);
    // Monotone: secants (per px) .01 .02 .01 .04; interior means .015 .015 .025;
    // ends 2·.01 − .015 = .005 and 2·.04 − .025 = .055.
    CHECK(m.node(0, 0).colU.r == Approx(0.05));
    CHECK(m.node(1, 0).colU.r == Approx(0.15));
    CHECK(m.node(2, 0).colU.r == Approx(0.15));
    CHECK(m.node(3, 0).colU.r == Approx(0.25));
    CHECK(m.node(4, 0).colU.r == Approx(0.55));
    // Secants .001 .049 .01 0: node 1 mean .025 > 3·.001 → .003; node 2 mean .0295 < .03 stays;
    // node 3 mean .005 > 3·0 → 0 (a plateau is not a strict extremum but clamps to 0);
    // first end 2·.001 − .003 = −.001 (Inkscape's parabola may overshoot); last end 0.
    CHECK(m.node(0, 0).colU.g == Approx(-0.01));
    CHECK(m.node(1, 0).colU.g == Approx(0.03));
    CHECK(m.node(2, 0).colU.g == Approx(0.295));
    CHECK(m.node(3, 0).colU.g == Approx(0.0).margin(1e-15));
    CHECK(m.node(4, 0).colU.g == Approx(0.0).margin(1e-15));
    // Peak at node 1 → 0; plateaus → 0; ends 2·.03 − 0 and 2·(−.02) − 0.
    CHECK(m.node(1, 0).colU.b == 0.0);
    CHECK(m.node(2, 0).colU.b == 0.0);
    CHECK(m.node(3, 0).colU.b == 0.0);
    CHECK(m.node(0, 0).colU.b == Approx(0.6));
    CHECK(m.node(4, 0).colU.b == Approx(-0.4));
    // Secants .05 .005 .005 0: node 1 mean .0275 > 3·.005 → .015; node 2 → .005; node 3 → 0.
    CHECK(m.node(1, 1).colU.r == Approx(0.15));
    CHECK(m.node(2, 1).colU.r == Approx(0.05));
    CHECK(m.node(0, 1).colU.r == Approx(0.85));  // 2·.05 − .015 = .085
    // Row 1 has no green or blue: zero derivatives there.
    CHECK(m.node(2, 1).colU.g == 0.0);
    CHECK(followsColorRule(m));
}

TEST_CASE("slopes scale by chord over parameter interval; one patch has Inkscape's ends",
          "[color_rule]") {
    SECTION("interior node: total chord over total knot interval") {
        // Chords 10 and 20 px, knot intervals 0.5 and 2: red 0, .2, .6 → secants .02 .02, g = .02.
        GradientMesh m = lattice({0, 10, 30}, {0, 10}, {0, 0.5, 2.5}, {0, 1});
        setRow(m, 0, 0, {0.0, 0.2, 0.6});
        applyColorRule(m);
        CHECK(m.node(1, 0).colU.r == Approx(0.02 * 30 / 2.5));
        CHECK(m.node(0, 0).colU.r == Approx(0.02 * 10 / 0.5));  // ends: their own patch only
        CHECK(m.node(2, 0).colU.r == Approx(0.02 * 20 / 2.0));
    }
    SECTION("single patch along a direction: first end 2δ, last end 0") {
        GradientMesh m = lattice({0, 10}, {0, 8}, {0, 1}, {0, 2});
        m.node(1, 0).col.r = 0.5;  // along u: 0 → .5 over 10 px
        m.node(0, 1).col.g = 0.4;  // along v: 0 → .4 over 8 px
        applyColorRule(m);
        CHECK(m.node(0, 0).colU.r == Approx(2 * 0.05 * 10 / 1));
        CHECK(m.node(1, 0).colU.r == 0.0);
        CHECK(m.node(0, 0).colV.g == Approx(2 * 0.05 * 8 / 2));
        CHECK(m.node(0, 1).colV.g == 0.0);
    }
    SECTION("degenerate chords give zero slopes") {
        GradientMesh m = lattice({0, 10, 10}, {0, 10}, iota(2, 1), {0, 1});
        setRow(m, 0, 0, {0.0, 0.2, 0.6});
        applyColorRule(m);
        CHECK(m.node(1, 0).colU.r == 0.0);
        CHECK(m.node(2, 0).colU.r == 0.0);
        CHECK(std::isfinite(m.node(0, 0).colU.r));
    }
}

TEST_CASE("directions are independent and cross derivatives stay zero", "[color_rule]") {
    GradientMesh m = lattice({0, 10, 25, 30}, {0, 12, 20}, {0, 1, 2, 2.5}, {0, 1, 3});
    const double red[4] = {0.1, 0.4, 0.5, 0.9};
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 3; ++i) m.node(i, j).col = {red[i], 0.2 + 0.3 * j, 0.5};
    applyColorRule(m);
    for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 3; ++i) {
            const Node& n = m.node(i, j);
            CHECK(n.colV.r == 0.0);  // red varies only along u
            CHECK(n.colU.g == 0.0);  // green only along v
            CHECK(n.colU.b == 0.0);
            CHECK(n.colV.b == 0.0);
            CHECK(n.colU.r == m.node(i, 0).colU.r);
        }
    // Twists are not part of the representation: patch corners carry only colS and colT, and a
    // constant colour gives exactly zero everywhere.
    GradientMesh flat = lattice({0, 10}, {0, 10}, {0, 1}, {0, 1});
    for (Node& n : flat.nodes) n.col = {0.3, 0.3, 0.3};
    applyColorRule(flat);
    for (const Node& n : flat.nodes) {
        CHECK(n.colU == Vec3{});
        CHECK(n.colV == Vec3{});
    }
}

TEST_CASE("followsColorRule and colorRuleDeviation", "[color_rule]") {
    GradientMesh m = slitMesh(false);
    m.tangents.push_back({0, 0, 1, 0, {5, 0}, {1, 1, 1}});
    CHECK_FALSE(followsColorRule(m));  // zero derivatives and an arbitrary tangent
    applyColorRule(m);
    CHECK(followsColorRule(m));
    CHECK(colorRuleDeviation(m) == 0.0);

    GradientMesh p = m;
    p.node(3, 1).colV.g += 0.01;
    CHECK(colorRuleDeviation(p) == Approx(0.01));
    CHECK_FALSE(followsColorRule(p));
    CHECK(followsColorRule(p, 0.011));

    p = m;
    p.slits[0].right.colU.b -= 0.02;
    CHECK(colorRuleDeviation(p) == Approx(0.02));
    p = m;
    p.slits[0].below[0].colU.r += 0.03;
    CHECK(colorRuleDeviation(p) == Approx(0.03));
    p = m;
    p.tangents[0].colU.g += 0.04;
    CHECK(colorRuleDeviation(p) == Approx(0.04));
    p = m;
    p.node(0, 0).colU.r = std::nan("");
    CHECK(std::isnan(colorRuleDeviation(p)));
    CHECK_FALSE(followsColorRule(p, 1e9));
}

TEST_CASE("slit mesh: the lines Inkscape sees in the legacy pieces", "[color_rule]") {
    GradientMesh m = slitMesh(false);
    applyColorRule(m);
    const Slit& s = m.slits[0];
    // The main copy at (2,2) ends the column line rows 0..2; the below copy starts rows 2..4.
    // Column 2 chords: 15, 17.5 above (the main copy is raised by 5 px), 2.5, 15 below.
    auto red = [&](int j) { return m.node(2, j).col.r; };
    {
        const double d0 = (red(1) - red(0)) / 15, d1 = (red(2) - red(1)) / 17.5;
        double g1 = 0.5 * (d0 + d1);
        if ((red(0) < red(1)) == (red(1) < red(2))) {
            if (std::fabs(g1) > std::fabs(3 * d0)) g1 = 3 * d0;
            if (std::fabs(g1) > std::fabs(3 * d1)) g1 = 3 * d1;
        } else {
            g1 = 0;
        }
        const double gEnd = 2 * d1 - g1;
        CHECK(m.node(2, 2).colV.r == Approx(gEnd * 17.5 / (m.v[2] - m.v[1])));
    }
    {
        const double c0 = s.below[0].col.r, c1 = red(3), c2 = red(4);
        const double d0 = (c1 - c0) / 2.5, d1 = (c2 - c1) / 15;
        double g1 = 0.5 * (d0 + d1);
        if ((c0 < c1) == (c1 < c2)) {
            if (std::fabs(g1) > std::fabs(3 * d0)) g1 = 3 * d0;
            if (std::fabs(g1) > std::fabs(3 * d1)) g1 = 3 * d1;
        } else {
            g1 = 0;
        }
        const double gStart = 2 * d0 - g1;
        CHECK(s.below[0].colV.r == Approx(gStart * 2.5 / (m.v[3] - m.v[2])));
    }
    // Slit end d: the minimax of +d ≈ t_above/Δu and −d ≈ t_below/Δu.
    {
        // Left end (1,2): above line 0, 1, copy(2) ; below line 0, 1, below(2). Chord left 20,
        // right √(20² + 5²) on both sides.
        const double L = 20, Lr = std::sqrt(425.0);
        auto g = [&](double c0, double c1, double c2) {
            const double d0 = (c1 - c0) / L, d1 = (c2 - c1) / Lr;
            if ((c0 < c1 && c1 > c2) || (c0 > c1 && c1 < c2)) return 0.0;
            double r = 0.5 * (d0 + d1);
            if (std::fabs(r) > std::fabs(3 * d0)) r = 3 * d0;
            if (std::fabs(r) > std::fabs(3 * d1)) r = 3 * d1;
            return r;
        };
        for (int c = 0; c < 3; ++c) {
            const double gA = g(m.node(0, 2).col[c], m.node(1, 2).col[c], m.node(2, 2).col[c]);
            const double gB = g(m.node(0, 2).col[c], m.node(1, 2).col[c], s.below[0].col[c]);
            CHECK(s.left.colU[c] == Approx((gA * Lr - gB * Lr) / 2).margin(1e-12));
            CHECK(m.node(1, 2).colU[c] == Approx((gA + gB) / 2 * L).margin(1e-12));
        }
    }
    // Rows away from the slit are untouched by it: row 0 equals the same mesh without a slit
    // whose row-2 colours are the above copies'.
    GradientMesh plain = m;
    plain.slits.clear();
    applyColorRule(plain);
    for (int i = 0; i <= 4; ++i) {
        CHECK(diff(plain.node(i, 0).colU, m.node(i, 0).colU) < 1e-15);
        CHECK(diff(plain.node(i, 0).colV, m.node(i, 0).colV) < 1e-15);
    }
}

TEST_CASE("split then rule equals rule then split where the representation allows",
          "[color_rule]") {
    SECTION("slit ends at extrema and colours linear across the cut row: identical") {
        GradientMesh whole = slitMesh(true);
        applyColorRule(whole);
        std::vector<GradientMesh> a = cutSlitMesh(whole);
        std::vector<GradientMesh> b = cutSlitMesh(whole);
        for (GradientMesh& piece : b) applyColorRule(piece);
        for (size_t k = 0; k < 2; ++k) {
            CHECK(followsColorRule(a[k], 1e-12));
            for (size_t n = 0; n < a[k].nodes.size(); ++n) {
                CHECK(diff(a[k].nodes[n].colU, b[k].nodes[n].colU) < 1e-12);
                CHECK(diff(a[k].nodes[n].colV, b[k].nodes[n].colV) < 1e-12);
            }
            for (size_t t = 0; t < a[k].tangents.size(); ++t)
                CHECK(diff(a[k].tangents[t].colU, b[k].tangents[t].colU) < 1e-12);
        }
    }
    SECTION("the same through splitIntoLegacyMeshes") {
        GradientMesh whole = slitMesh(true);
        applyColorRule(whole);
        const std::vector<GradientMesh> pieces = splitIntoLegacyMeshes(whole);
        REQUIRE(pieces.size() == 2);
        for (const GradientMesh& piece : pieces) CHECK(colorRuleDeviation(piece) < 1e-12);
        whole = slitMesh(false);
        applyColorRule(whole);
        double worst = 0;
        for (const GradientMesh& piece : splitIntoLegacyMeshes(whole))
            worst = std::max(worst, colorRuleDeviation(piece));
        CHECK(worst > 0.01);
    }
    SECTION("generic colours: differences only where one value serves two pieces") {
        GradientMesh whole = slitMesh(false);
        applyColorRule(whole);
        std::vector<GradientMesh> a = cutSlitMesh(whole);
        std::vector<GradientMesh> b = cutSlitMesh(whole);
        for (GradientMesh& piece : b) applyColorRule(piece);
        bool someDiffer = false;
        for (size_t k = 0; k < 2; ++k) {
            const int cutRow = (k == 0) ? 2 : 0;
            for (int j = 0; j <= 2; ++j)
                for (int i = 0; i <= 4; ++i) {
                    const Node& na = a[k].node(i, j);
                    const Node& nb = b[k].node(i, j);
                    // On the cut row only the slit copies (column 2) must agree: the slit
                    // ends' colU and colV serve both pieces, and so does colU at the row's
                    // ends, whose parabolic slope uses their neighbour's, the slit end's.
                    if (j != cutRow || i == 2) {
                        CHECK(diff(na.colU, nb.colU) < 1e-12);
                        CHECK(diff(na.colV, nb.colV) < 1e-12);
                    }
                    someDiffer = someDiffer || diff(na.colU, nb.colU) > 1e-9 ||
                                 diff(na.colV, nb.colV) > 1e-9;
                }
        }
        CHECK(someDiffer);
    }
}

TEST_CASE("bicubicExportDeviation: exact when chord per parameter matches on both sides",
          "[color_rule]") {
    SECTION("affine corner lattice with non-uniform knots") {
        GradientMesh m = affineLattice();
        CHECK(bicubicExportDeviation(m) > 0.01);  // zero derivatives are not Inkscape's
        applyColorRule(m);
        CHECK(bicubicExportDeviation(m) < 1e-12);
    }
    SECTION("unequal chord per parameter: equal and opposite errors on the two sides") {
        // As above: chords 10, 20 over unit knots, g = .02 → colU .3, local targets .2 and .4.
        GradientMesh m = lattice({0, 10, 30}, {0, 10}, iota(2, 1), {0, 1});
        setRow(m, 0, 0, {0.0, 0.2, 0.6});
        setRow(m, 1, 0, {0.0, 0.2, 0.6});
        applyColorRule(m);
        CHECK(m.node(1, 0).colU.r == Approx(0.3));
        CHECK(bicubicExportDeviation(m) == Approx(0.1));
    }
    SECTION("legacy pieces: slit-end tangents let both sides of a slit end be exact") {
        // Move the slit copies back onto the row: every chord per parameter is then equal
        // (20 px per unit u, 15 px per unit v), so each piece after the rule is exact, tangents
        // included, although its row-2 colours differ on the two sides of each slit end.
        GradientMesh whole = slitMesh(false);
        whole.node(2, 2).pos = {40, 37.5};
        whole.slits[0].below[0].pos = {40, 37.5};
        for (GradientMesh& piece : cutSlitMesh(whole)) {
            CHECK(bicubicExportDeviation(piece) > 0.01);
            applyColorRule(piece);
            CHECK(followsColorRule(piece));
            CHECK(bicubicExportDeviation(piece) < 1e-12);
        }
        // The whole mesh cannot be: one colU at each slit end serves both pieces.
        applyColorRule(whole);
        double worst = 0;
        for (const GradientMesh& piece : cutSlitMesh(whole))
            worst = std::max(worst, bicubicExportDeviation(piece));
        CHECK(worst > 0.01);
    }
}

TEST_CASE("bicubic model: each patch corner gets Inkscape's slope, whatever the knots",
          "[color_rule][bicubic]") {
    // Unequal chords (10, 20 px over unit knots): the global-parameter rule must compromise at
    // the middle node (local slopes .3 and .3 against Inkscape's .2 and .4); the model gives
    // each patch its own.
    GradientMesh m = lattice({0, 10, 30}, {0, 10}, iota(2, 1), {0, 1});
    setRow(m, 0, 0, {0.0, 0.2, 0.6});
    setRow(m, 1, 0, {0.0, 0.2, 0.6});
    m.colorModel = ColorModel::Bicubic;
    const PatchHermite left = patchHermite(m, 0, 0), right = patchHermite(m, 1, 0);
    // g at the middle node = mean of secants .02 and .02 = .02 per px; local = g * chord.
    CHECK(left.corner[1][0].colS.r == Approx(0.2));
    CHECK(right.corner[0][0].colS.r == Approx(0.4));
    CHECK(left.corner[0][0].colT.r == Approx(0.0));  // rows equal: no slope along v
    // Stored slopes are ignored by the model.
    m.node(1, 0).colU = {5, 5, 5};
    CHECK(patchHermite(m, 1, 0).corner[0][0].colS.r == Approx(0.4));
}

TEST_CASE("bicubic model: where the global rule is exact, the two agree", "[color_rule][bicubic]") {
    GradientMesh rule = affineLattice();
    GradientMesh model = rule;
    model.colorModel = ColorModel::Bicubic;
    applyColorRule(rule);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) {
            const PatchHermite a = patchHermite(rule, i, j), b = patchHermite(model, i, j);
            for (int c = 0; c < 4; ++c) {
                CHECK(diff(a.corner[c / 2][c % 2].colS, b.corner[c / 2][c % 2].colS) < 1e-12);
                CHECK(diff(a.corner[c / 2][c % 2].colT, b.corner[c / 2][c % 2].colT) < 1e-12);
            }
        }
}

TEST_CASE("bicubic model: a slit mesh's patches are those of its hole-free pieces",
          "[color_rule][bicubic]") {
    for (bool symmetric : {true, false}) {
        GradientMesh whole = slitMesh(symmetric);
        whole.colorModel = ColorModel::Bicubic;
        const std::vector<GradientMesh> pieces = splitIntoLegacyMeshes(whole);
        REQUIRE(pieces.size() == 2);
        for (int j = 0; j < whole.rows(); ++j)
            for (int i = 0; i < whole.columns(); ++i) {
                const GradientMesh& piece = pieces[j < 2 ? 0 : 1];
                const PatchHermite a = patchHermite(whole, i, j),
                                   b = patchHermite(piece, i, j < 2 ? j : j - 2);
                for (int c = 0; c < 4; ++c) {
                    const HermiteCorner &x = a.corner[c / 2][c % 2], &y = b.corner[c / 2][c % 2];
                    CHECK(diff(x.col, y.col) == 0);
                    CHECK(diff(x.colS, y.colS) < 1e-12);
                    CHECK(diff(x.colT, y.colT) < 1e-12);
                }
            }
    }
}
