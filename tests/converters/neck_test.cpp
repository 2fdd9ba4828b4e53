// findNeck (converters/neck.h): the narrowest neck of a region and the two sides of its cut.
#include <catch2/catch.hpp>

#include <cmath>

#include "converters/neck.h"
#include "converters/regions.h"
#include "shapes.h"

using namespace gm;
using namespace gm::test;

namespace {

Region only(int w, int h, const std::function<bool(double, double)>& in) {
    const auto regions = extractRegions(coverageFromBits(w, h, rasterize(w, h, in)));
    REQUIRE(regions.size() == 1);
    return regions.front();
}

struct Sides {
    long one = 0, two = 0, outside = 0;
};
Sides count(const Region& r, const NeckCut& cut) {
    Sides s;
    for (size_t k = 0; k < cut.side.size(); ++k) {
        if (!r.mask[k]) {
            s.outside += cut.side[k] != 0;
            continue;
        }
        (cut.side[k] == 1 ? s.one : s.two) += 1;
        if (cut.side[k] == 0) s.outside += 1000000;  // a region pixel without a side
    }
    return s;
}

}  // namespace

TEST_CASE("a dumbbell's neck is its bar, and the cut gives each disc a side", "[neck]") {
    // Two discs of radius 40 joined by a bar 12 px high: the neck is a chord across the bar.
    const int w = 260, h = 120;
    const Region r = only(w, h, [](double x, double y) {
        return inDisk(x, y, 60, 60, 40) || inDisk(x, y, 200, 60, 40) ||
               (x > 90 && x < 170 && std::abs(y - 60) < 6);
    });
    const auto cut = findNeck(r);
    REQUIRE(cut);
    INFO("chord (" << cut->a.x << ", " << cut->a.y << ") - (" << cut->b.x << ", " << cut->b.y
                   << "), ratio " << cut->ratio);
    CHECK(norm(cut->b - cut->a) < 16);  // across the bar, not along it
    CHECK(cut->a.x > 90);
    CHECK(cut->a.x < 170);
    CHECK(cut->b.x > 90);
    CHECK(cut->b.x < 170);
    const Sides s = count(r, *cut);
    CHECK(s.outside == 0);
    // Each side holds one disc (and part of the bar): every pixel of the left disc on one
    // side, every pixel of the right disc on the other.
    int leftSide = 0, rightSide = 0;
    bool leftOne = true, rightOne = true;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            if (inDisk(x + .5, y + .5, 60, 60, 38)) leftSide = cut->side[k], leftOne &= cut->side[k] == leftSide;
            if (inDisk(x + .5, y + .5, 200, 60, 38)) rightSide = cut->side[k], rightOne &= cut->side[k] == rightSide;
        }
    CHECK(leftOne);
    CHECK(rightOne);
    CHECK(leftSide != rightSide);
    CHECK(s.one > 4000);
    CHECK(s.two > 4000);
}

TEST_CASE("a disc and a square have no neck", "[neck]") {
    CHECK_FALSE(findNeck(only(200, 200, [](double x, double y) { return inDisk(x, y, 100, 100, 80); })));
    CHECK_FALSE(findNeck(only(200, 200, [](double x, double y) {
        return x > 30 && x < 170 && y > 30 && y < 170;
    })));
}

TEST_CASE("the chord across a C's gap is no neck: it runs outside the region", "[neck]") {
    // A thick ring with a narrow gap: the two ends of the C are 6 px apart, far along the
    // outline, but the chord between them crosses the background.
    const Region r = only(240, 240, [](double x, double y) {
        const double d = std::hypot(x - 120, y - 120);
        return d > 50 && d < 100 && !(x > 120 && std::abs(y - 120) < 3);
    });
    const auto cut = findNeck(r);
    if (cut) {
        // Whatever is found lies inside the ring: its chord's midpoint is a region pixel.
        const Vec2 m = 0.5 * (cut->a + cut->b);
        INFO("chord (" << cut->a.x << ", " << cut->a.y << ") - (" << cut->b.x << ", " << cut->b.y << ")");
        CHECK(r.mask[static_cast<size_t>(m.y) * 240 + static_cast<size_t>(m.x)]);
        CHECK(norm(cut->b - cut->a) > 20);
    }
}

TEST_CASE("a neck that would leave one side under minShare is not taken", "[neck]") {
    // A disc with a small knob on a stalk: the stalk is a neck, but the knob is tiny.
    const Region r = only(240, 200, [](double x, double y) {
        return inDisk(x, y, 100, 100, 70) || inDisk(x, y, 205, 100, 12) ||
               (x > 160 && x < 200 && std::abs(y - 100) < 4);
    });
    CHECK_FALSE(findNeck(r));
    NeckOptions loose;
    loose.minShare = 0.02;
    const auto cut = findNeck(r, loose);
    REQUIRE(cut);
    CHECK(cut->a.x > 165);
}
