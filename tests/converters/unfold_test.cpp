#include "converters/unfold.h"

#include <catch2/catch.hpp>

#include "meshcore/validate.h"

using namespace gm;

namespace {

// A C×R grid of 10 px square patches with exact derivatives (10 px per unit).
GradientMesh squareGrid(int C, int R) {
    GradientMesh m(C, R);
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            Node& n = m.node(i, j);
            n.pos = {10.0 * i, 10.0 * j};
            n.posU = {10, 0};
            n.posV = {0, 10};
            n.col = {0.5, 0.5, 0.5};
        }
    return m;
}

}  // namespace

TEST_CASE("unfold: a patch folded by a wild interior derivative is mended, nothing else moves") {
    GradientMesh m = squareGrid(4, 4);
    // Turned back along its own grid line: the four patches around node (2, 2) fold.
    m.node(2, 2).posU = {-25, 4};
    m.node(1, 3).posV = {18, -12};
    const GradientMesh before = m;
    const int folded = countFoldedPatches(m);
    REQUIRE(folded >= 4);

    const UnfoldResult r = unfoldPatches(m);
    CHECK(r.before == folded);
    CHECK(r.after == 0);
    CHECK(countFoldedPatches(m) == 0);
    CHECK(r.nodesChanged > 0);
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 4; ++i) {
            const Node &a = before.node(i, j), &b = m.node(i, j);
            CHECK(a.pos == b.pos);
            CHECK(a.col == b.col);
            // Derivatives along the sides (the outline) never move.
            if (j == 0 || j == 4) CHECK(a.posU == b.posU);
            if (i == 0 || i == 4) CHECK(a.posV == b.posV);
        }
    // Corners that were not on a folded patch keep their derivatives.
    CHECK(m.node(4, 0).posU == before.node(4, 0).posU);
    CHECK(m.node(0, 4).posV == before.node(0, 4).posV);
}

TEST_CASE("unfold: a mesh that does not fold is left exactly as it is") {
    GradientMesh m = squareGrid(3, 2);
    m.node(1, 1).posU = {14, 3};  // bent but not folded
    const GradientMesh before = m;
    const UnfoldResult r = unfoldPatches(m);
    CHECK(r.before == 0);
    CHECK(r.after == 0);
    CHECK(r.nodesChanged == 0);
    CHECK(m == before);
}

TEST_CASE("unfold: a fold of the node positions themselves is not made worse") {
    GradientMesh m = squareGrid(4, 4);
    // Node (2, 2) pushed past its right neighbour: its patches' corners are out of order, which
    // no derivative mends.
    m.node(2, 2).pos = {34, 21};
    const int folded = countFoldedPatches(m);
    REQUIRE(folded > 0);
    const UnfoldResult r = unfoldPatches(m);
    CHECK(r.after <= folded);
    CHECK(countFoldedPatches(m) == r.after);
    CHECK(m.node(2, 2).pos.x == 34);
}

TEST_CASE("unfold: slit rows keep every derivative (the hole outline and its ±d ends)") {
    GradientMesh m = squareGrid(6, 6);
    Slit s;
    s.row = 4;
    s.i0 = 2;
    s.i1 = 4;
    s.below.resize(1);
    s.below[0] = m.node(3, 4);
    s.below[0].pos = {30, 44};
    m.node(3, 4).pos = {30, 36};
    s.left.posU = {10, -3};
    s.right.posU = {10, 3};
    m.slits.push_back(s);
    // Beside the slit ends the Jacobian vanishes (the hole outline turns there): folds by the
    // count, not to be mended. A wild derivative on the slit row stays too.
    m.node(3, 4).posU = {12, 0};
    const int structural = countFoldedPatches(m);
    // A fold away from the slit.
    m.node(2, 1).posV = {0, -30};
    const GradientMesh before = m;
    REQUIRE(countFoldedPatches(m) == structural + 4);
    const UnfoldResult r = unfoldPatches(m);
    CHECK(r.after == structural);
    CHECK(m.node(2, 1).posV.y >= 0);
    for (int j = 3; j <= 5; ++j)
        for (int i = 1; i <= 5; ++i) {
            CHECK(m.node(i, j).posU == before.node(i, j).posU);
            CHECK(m.node(i, j).posV == before.node(i, j).posV);
        }
    CHECK(m.slits[0] == before.slits[0]);
    CHECK(validateMesh(m).empty());
}
