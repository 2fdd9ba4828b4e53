// Boundary fidelity (converters/boundary.h): knots go where the outline needs them.
#include "converters/boundary.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "meshcore/validate.h"
#include "synthetic_region.h"

using namespace gm;

namespace {
// A 300 × 100 rectangle whose top side has a narrow bump `height` px high centred at u = `at`
// (and optionally a second one); the bumps fade out towards the bottom side.
gmtest::MapFn bumps(double at, double height, double at2 = 0, double height2 = 0) {
    return [=](double u, double v) {
        const double bump = height * std::exp(-std::pow((u - at) / 6.0, 2)) +
                            height2 * std::exp(-std::pow((u - at2) / 6.0, 2));
        return Vec2{50 + u, 80 + v - (1 - v / 100.0) * bump};
    };
}
}  // namespace

TEST_CASE("a new boundary knot goes where the edge strays most, not to the middle", "[grid][boundary]") {
    // Initial knots 0, 75, 150, 225, 300: the bump at u = 100 lies in [75, 150], whose middle
    // is 112.5.
    const auto s = gmtest::makeSynthetic(300, 100, 300, 20, bumps(100, 30), 400, 200);
    const GridBuilder grid(s.tri, s.map);
    GridOptions go;
    go.columns = 4;
    go.rows = 2;
    BoundaryFitOptions bf;
    bf.maxRounds = 1;
    const BoundaryFitResult r = fitBoundary(grid, go, bf);
    REQUIRE(r.addedU >= 1);
    double nearest = 1e9;
    for (double k : go.knotsU)
        if (k > 75 && k < 150) nearest = std::min(nearest, std::abs(k - 100));
    INFO("knots along u: " << go.knotsU.size() << ", nearest to the bump " << nearest);
    CHECK(nearest < 4);
    // Run to the end: the outline is followed within the tolerance.
    bf.maxRounds = 40;
    const BoundaryFitResult all = fitBoundary(grid, go, bf);
    CHECK(all.maxDeviation <= bf.tolerance);
    CHECK(validateMesh(grid.build(go)).empty());
}

TEST_CASE("a budget too small for the whole outline goes to its worst part first", "[grid][boundary]") {
    // Two bumps: 30 px and 3 px high. With room for only a few knots, the big bump must get
    // them: what is left is at most about the small bump's height.
    const auto s = gmtest::makeSynthetic(300, 100, 300, 20, bumps(137, 30, 240, 3), 400, 200);
    const GridBuilder grid(s.tri, s.map);
    GridOptions go;
    go.columns = 4;
    go.rows = 1;
    BoundaryFitOptions bf;
    bf.maxPatches = 7;  // three more knots along u
    const BoundaryFitResult r = fitBoundary(grid, go, bf);
    INFO(r.addedU << " knots along u, " << r.maxDeviation << " px left");
    CHECK(r.addedU <= 3);
    CHECK(r.maxDeviation < 3.5);
}
