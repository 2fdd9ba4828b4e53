#include <catch2/catch.hpp>

#include <cmath>

#include "converters/corners.h"
#include "converters/regions.h"
#include "meshcore/error.h"
#include "shapes.h"

using namespace gm;

namespace {
constexpr double kPi = 3.14159265358979323846;

Region onlyRegion(int w, int h, const std::vector<uint8_t>& bits) {
    auto regions = extractRegions(coverageFromBits(w, h, bits));
    REQUIRE(regions.size() == 1);
    return std::move(regions[0]);
}
}  // namespace

TEST_CASE("the corners of a turned rectangle are its corners, top-left first", "[corners]") {
    const int w = 256, h = 256;
    for (double degrees : {0.0, 17.0, 25.0, 38.0, -30.0}) {
        const test::TurnedRect rect{128.3, 127.6, 170, 90, degrees * kPi / 180};
        const Region region =
            onlyRegion(w, h, test::rasterize(w, h, [&](double x, double y) { return rect.contains(x, y); }));
        const RegionCorners rc = findCorners(region);
        INFO("rotation " << degrees << " degrees");
        for (int k = 0; k < 4; ++k) {
            const Vec2 found = region.outer.points[rc.index[k]];
            INFO("corner " << k << " found at (" << found.x << ", " << found.y << "), expected ("
                           << rect.corner(k).x << ", " << rect.corner(k).y << ")");
            CHECK(norm(found - rect.corner(k)) < 1.5);
        }
        CHECK(rc.px == Approx(170).margin(3));
        CHECK(rc.py == Approx(90).margin(3));
    }
}

TEST_CASE("corners follow the loop and sides add up to the perimeter", "[corners]") {
    const int w = 200, h = 150;
    const test::TurnedRect rect{100, 75, 120, 80, 0.3};
    const Region region =
        onlyRegion(w, h, test::rasterize(w, h, [&](double x, double y) { return rect.contains(x, y); }));
    const RegionCorners rc = findCorners(region);
    // In loop order: exactly one cyclic descent among the four indices.
    int descents = 0;
    for (int k = 0; k < 4; ++k) descents += rc.index[(k + 1) % 4] < rc.index[k];
    CHECK(descents == 1);
    double perimeter = 0;
    const auto& p = region.outer.points;
    for (size_t k = 0; k < p.size(); ++k) perimeter += norm(p[(k + 1) % p.size()] - p[k]);
    CHECK(rc.sideLength[0] + rc.sideLength[1] + rc.sideLength[2] + rc.sideLength[3] ==
          Approx(perimeter));
    CHECK(rc.px == std::max(rc.sideLength[0], rc.sideLength[2]));
    CHECK(rc.py == std::max(rc.sideLength[1], rc.sideLength[3]));
}

TEST_CASE("a disk gets four roughly evenly spaced corners", "[corners]") {
    const int w = 200, h = 200;
    const Region region = onlyRegion(
        w, h, test::rasterize(w, h, [](double x, double y) { return test::inDisk(x, y, 100, 100, 80); }));
    const RegionCorners rc = findCorners(region);
    const double perimeter = 2 * kPi * 80;
    for (int k = 0; k < 4; ++k) {
        CHECK(rc.sideLength[k] > 0.18 * perimeter);
        CHECK(rc.sideLength[k] < 0.32 * perimeter);
    }
    // Top-left is the corner in the upper left quadrant.
    const Vec2 tl = region.outer.points[rc.index[0]];
    CHECK(tl.x < 100);
    CHECK(tl.y < 100);
}

TEST_CASE("a loop too small for four corners is reported", "[corners]") {
    Region region;
    region.outer.points = {{0, 0}, {1, 0}, {0, 1}};
    CHECK_THROWS_AS(findCorners(region), Error);
}

TEST_CASE("tip corners sit at the ends of thin spikes", "[corners]") {
    // A disc with four thin spikes at uneven angles: the sharpest tips are the spikes' ends,
    // where findCorners (bounding-box based) would put only some of the corners.
    const int w = 256, h = 256;
    const double angles[4] = {10, 80, 200, 260};
    auto inside = [&](double x, double y) {
        const double dx = x - 128, dy = y - 128;
        if (dx * dx + dy * dy < 40 * 40) return true;
        for (double a : angles) {
            const double c = std::cos(a * kPi / 180), s = std::sin(a * kPi / 180);
            const double along = dx * c + dy * s, across = -dx * s + dy * c;
            if (along > 0 && along < 110 && std::abs(across) < 3) return true;
        }
        return false;
    };
    const Region region = onlyRegion(w, h, test::rasterize(w, h, inside));
    const RegionCorners rc = findTipCorners(region);
    for (int k = 0; k < 4; ++k) {
        const Vec2 found = region.outer.points[rc.index[k]];
        double nearest = 1e9;
        for (double a : angles) {
            const Vec2 tip{128 + 110 * std::cos(a * kPi / 180), 128 + 110 * std::sin(a * kPi / 180)};
            nearest = std::min(nearest, norm(found - tip));
        }
        INFO("corner " << k << " at (" << found.x << ", " << found.y << ")");
        CHECK(nearest < 5);
    }
    // Distinct, in loop order.
    CHECK(rc.index[0] != rc.index[1]);
    CHECK(rc.index[1] != rc.index[2]);
    CHECK(rc.index[2] != rc.index[3]);
    double sum = 0;
    for (double s : rc.sideLength) sum += s;
    CHECK(sum > 4 * 2 * 100);  // the sides run along the spikes
}
