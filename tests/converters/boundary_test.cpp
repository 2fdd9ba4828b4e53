// Boundary fidelity (converters/boundary.h): knots go where the outline needs them.
#include "converters/boundary.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "meshcore/render.h"
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
// A 300 × 100 rectangle whose top side is a staircase: steps every 4 px, 0, 1 or 2 px high
// (as a rough mask's outline); the steps fade out towards the bottom side.
gmtest::MapFn staircase() {
    return [](double u, double v) {
        const double step = static_cast<double>((static_cast<int>(u / 4) * 7919) % 3);
        return Vec2{50 + u, 80 + v - (1 - v / 100.0) * step};
    };
}

// The region's pixels that a render of `mesh` leaves uncovered (alpha < 0.5).
int uncoveredPixels(const GradientMesh& mesh, const Region& region) {
    Document doc;
    doc.width = region.width;
    doc.height = region.height;
    doc.meshes = {mesh};
    const RgbaImage image = renderDocument(doc).image;
    int uncovered = 0;
    for (size_t k = 0; k < region.mask.size(); ++k)
        uncovered += region.mask[k] && image.pixels[4 * k + 3] < 0.5f;
    return uncovered;
}
}  // namespace

TEST_CASE("one-sided side curves go round a staircase's tips without straying farther", "[grid][boundary]") {
    // The lattice has a vertex every pixel along u, so the outline is the staircase itself.
    const auto s = gmtest::makeSynthetic(300, 100, 300, 20, staircase(), 400, 200);
    const GridBuilder grid(s.tri, s.map);
    GridOptions go;
    go.columns = 6;  // 50 px edges: far too long to follow the steps
    go.rows = 2;
    const GradientMesh plain = grid.build(go);
    const double plainDeviation = outlineDeviation(grid, plain);
    const int plainUncovered = uncoveredPixels(plain, s.region);
    // As convert does it: the same knots, each side within the plain fit's worst deviation.
    go.outlineCover = 0.1;
    go.outlineSlack = std::max(0.5, plainDeviation);
    const GradientMesh covered = grid.build(go);
    const double coveredDeviation = outlineDeviation(grid, covered);
    const int coveredUncovered = uncoveredPixels(covered, s.region);
    INFO("plain: " << plainUncovered << " px uncovered, outline " << plainDeviation
                   << " px; one-sided: " << coveredUncovered << " px, " << coveredDeviation << " px");
    CHECK(plainUncovered >= 20);
    CHECK(coveredUncovered * 4 <= plainUncovered);
    CHECK(coveredDeviation <= plainDeviation + 0.01);
    CHECK(countFoldedPatches(covered) <= countFoldedPatches(plain));
    CHECK(validateMesh(covered).empty());
    // The corners stay on the outline.
    CHECK(norm(covered.node(0, 0).pos - plain.node(0, 0).pos) < 1e-9);
    CHECK(norm(covered.node(6, 0).pos - plain.node(6, 0).pos) < 1e-9);
}

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
