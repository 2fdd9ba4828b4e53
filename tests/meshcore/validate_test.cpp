#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "meshcore/synthetic_meshes.h"
#include "meshcore/validate.h"

using namespace gm;
using Catch::Matchers::Contains;

TEST_CASE("synthetic meshes are valid", "[validate]") {
    CHECK(validateMesh(makeCurvedMesh(5, 4, 0, 0, 100, 100)).empty());
    CHECK(validateMesh(makeHoledMesh(3, 0, 0, 100, 300)).empty());
    CHECK(validateDocument(makeDemoDocument()).empty());
}

TEST_CASE("validation names each broken invariant", "[validate]") {
    GradientMesh m = makeHoledMesh(2, 0, 0, 100, 200);
    SECTION("knots") {
        m.u[2] = m.u[1];
        CHECK_THAT(validateMesh(m), Contains("strictly increasing"));
    }
    SECTION("node count") {
        m.nodes.pop_back();
        CHECK_THAT(validateMesh(m), Contains("node count"));
    }
    SECTION("NaN") {
        m.node(2, 2).colV.g = std::numeric_limits<double>::quiet_NaN();
        CHECK_THAT(validateMesh(m), Contains("non-finite"));
    }
    SECTION("slit on the border row") {
        m.slits[0].row = 0;
        CHECK_THAT(validateMesh(m), Contains("not an interior row"));
    }
    SECTION("slit outside the columns") {
        m.slits[0].i1 = m.columns();
        CHECK_THAT(validateMesh(m), Contains("not inside"));
    }
    SECTION("split node count") {
        m.slits[0].below.pop_back();
        CHECK_THAT(validateMesh(m), Contains("split nodes"));
    }
    SECTION("touching slits on one row") {
        Slit extra = m.slits[0];
        m.slits.push_back(extra);
        CHECK_THAT(validateMesh(m), Contains("touches"));
    }
    SECTION("tangent break outside") {
        m.tangents.push_back({m.columns(), 0, 0, 0, {}, {}});
        CHECK_THAT(validateMesh(m), Contains("outside the grid"));
    }
    SECTION("canvas") {
        Document d;
        d.width = 0;
        d.height = 10;
        CHECK_THAT(validateDocument(d), Contains("canvas"));
    }
}

TEST_CASE("folded patches are counted", "[validate][folds]") {
    GradientMesh m = makeCurvedMesh(5, 4, 0, 0, 100, 100);
    CHECK(countFoldedPatches(m) == 0);
    CHECK(countFoldedPatches(makeHoledMesh(3, 0, 0, 100, 300)) == 0);
    // Drag one interior node across its right neighbour: the patches around it fold.
    Node& n = m.node(2, 2);
    n.pos = m.node(4, 2).pos + Vec2{5, 0};
    const int folded = countFoldedPatches(m);
    CHECK(folded >= 2);
    CHECK(folded <= 8);
    // A patch whose u tangents point backwards (a loop along its edges) folds too.
    GradientMesh l = makeCurvedMesh(1, 1, 0, 0, 100, 100);
    for (Node& k : l.nodes) k.posU = -3.0 * k.posU;
    CHECK(countFoldedPatches(l) == 1);
}

TEST_CASE("folded area is the inverted sheets' area in pixels", "[validate][folds]") {
    // A bilinear 1×1 patch over a 40×30 rectangle: Jacobian constant, area 1200.
    auto square = [](double w, double h) {
        GradientMesh m(1, 1);
        m.u = {0, 1};
        m.v = {0, 1};
        for (int j = 0; j <= 1; ++j)
            for (int i = 0; i <= 1; ++i) {
                Node& n = m.node(i, j);
                n.pos = {i * w, j * h};
                n.posU = {w, 0};
                n.posV = {0, h};
            }
        return m;
    };
    CHECK(foldedArea(square(40, 30)) == 0.0);
    CHECK(foldedArea(makeCurvedMesh(5, 4, 0, 0, 100, 100)) == 0.0);
    // Mirrored in x: the whole patch is inverted.
    GradientMesh mirrored = square(40, 30);
    for (Node& n : mirrored.nodes) {
        n.pos.x = -n.pos.x;
        n.posU.x = -n.posU.x;
    }
    CHECK(foldedArea(mirrored) == Approx(1200.0).epsilon(1e-9));
    // One interior node dragged across its neighbour: some area inverts, less than the mesh's.
    GradientMesh m = makeCurvedMesh(5, 4, 0, 0, 100, 100);
    m.node(2, 2).pos = m.node(4, 2).pos + Vec2{5, 0};
    const double area = foldedArea(m);
    CHECK(area > 10.0);
    CHECK(area < 100.0 * 100.0);
}
