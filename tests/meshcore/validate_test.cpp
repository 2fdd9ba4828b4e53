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
