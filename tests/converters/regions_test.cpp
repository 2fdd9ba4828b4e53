#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "converters/regions.h"
#include "meshcore/error.h"
#include "shapes.h"

using namespace gm;
using gm::test::inDisk;
using gm::test::rasterize;

namespace {
constexpr double kPi = 3.14159265358979323846;

std::vector<const Polygon*> loopsOf(const Region& r) {
    std::vector<const Polygon*> loops = {&r.outer};
    for (const auto& h : r.holes) loops.push_back(&h);
    return loops;
}
}  // namespace

TEST_CASE("polygonSignedArea is positive for loops clockwise on screen", "[regions]") {
    Polygon square{{{0, 0}, {2, 0}, {2, 3}, {0, 3}}};
    CHECK(polygonSignedArea(square) == Approx(6));
    std::reverse(square.points.begin(), square.points.end());
    CHECK(polygonSignedArea(square) == Approx(-6));
}

TEST_CASE("an annulus is one region with one hole of the analytic areas", "[regions]") {
    const int w = 256, h = 256;
    const auto bits = rasterize(w, h, [](double x, double y) {
        return inDisk(x, y, 128, 128, 100) && !inDisk(x, y, 128, 128, 40);
    });
    const auto regions = extractRegions(coverageFromBits(w, h, bits));
    REQUIRE(regions.size() == 1);
    const Region& r = regions[0];
    REQUIRE(r.holes.size() == 1);
    CHECK(polygonSignedArea(r.outer) == Approx(kPi * 100 * 100).epsilon(0.01));
    CHECK(-polygonSignedArea(r.holes[0]) == Approx(kPi * 40 * 40).epsilon(0.01));
    CHECK(r.pixelCount == Approx(kPi * (100 * 100 - 40 * 40)).epsilon(0.01));
    CHECK(test::countLoopIntersections(loopsOf(r)) == 0);
    // Simplified, but never coarser than maxSegment.
    const auto& p = r.outer.points;
    CHECK(p.size() < 2 * kPi * 100);
    for (size_t k = 0; k < p.size(); ++k) CHECK(norm(p[(k + 1) % p.size()] - p[k]) <= RegionOptions().maxSegment + 1e-9);
}

TEST_CASE("an anti-aliased alpha edge places the loop between pixels", "[regions]") {
    // A half-plane x < 20.3 with exact coverage in the boundary column.
    RgbaImage img(40, 30);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) img.at(x, y)[3] = x < 20 ? 1.f : (x == 20 ? 0.3f : 0.f);
    RegionOptions opts;
    opts.smoothing = 0;
    const auto regions = extractRegions(coverageFromAlpha(img), opts);
    REQUIRE(regions.size() == 1);
    double maxX = 0;
    for (const Vec2 q : regions[0].outer.points) maxX = std::max(maxX, q.x);
    CHECK(maxX == Approx(20.3).margin(0.1));
}

TEST_CASE("small holes are filled, large ones kept", "[regions]") {
    const int w = 160, h = 160;
    auto bits = rasterize(w, h, [](double x, double y) { return inDisk(x, y, 80, 80, 70); });
    for (auto [hx, hy] : {std::pair{50, 50}, std::pair{100, 60}, std::pair{60, 110}})
        for (int y = hy; y < hy + 2; ++y)
            for (int x = hx; x < hx + 2; ++x) bits[y * w + x] = 0;  // 4-pixel noise holes
    for (int y = 75; y < 85; ++y)
        for (int x = 95; x < 105; ++x) bits[y * w + x] = 0;  // a real 100-pixel hole
    RegionOptions opts;
    opts.minHole = 16;
    const auto regions = extractRegions(coverageFromBits(w, h, bits), opts);
    REQUIRE(regions.size() == 1);
    CHECK(regions[0].holes.size() == 1);
    CHECK(-polygonSignedArea(regions[0].holes[0]) == Approx(100).epsilon(0.1));
    CHECK(regions[0].mask[51 * w + 51] == 1);
    CHECK(regions[0].mask[80 * w + 100] == 0);
    opts.minHole = 1;
    CHECK(extractRegions(coverageFromBits(w, h, bits), opts)[0].holes.size() == 4);
}

TEST_CASE("two blobs are two regions, largest first; tiny ones are dropped", "[regions]") {
    const int w = 200, h = 100;
    const auto bits = rasterize(w, h, [](double x, double y) {
        return inDisk(x, y, 50, 50, 30) || inDisk(x, y, 150, 50, 40) || inDisk(x, y, 100, 10, 2);
    });
    RegionOptions opts;
    opts.minArea = 20;
    const auto regions = extractRegions(coverageFromBits(w, h, bits), opts);
    REQUIRE(regions.size() == 2);
    CHECK(polygonSignedArea(regions[0].outer) == Approx(kPi * 40 * 40).epsilon(0.01));
    CHECK(polygonSignedArea(regions[1].outer) == Approx(kPi * 30 * 30).epsilon(0.01));
    CHECK(regions[0].mask[50 * w + 50] == 0);
    CHECK(regions[1].mask[50 * w + 50] == 1);
}

TEST_CASE("squares touching at a corner are one region with a simple outline", "[regions]") {
    const int w = 80, h = 80;
    const auto bits = rasterize(w, h, [](double x, double y) {
        return (x > 10 && x < 30 && y > 10 && y < 30) || (x > 30 && x < 50 && y > 30 && y < 50) ||
               (x > 50 && x < 70 && y > 10 && y < 30);  // a second pinch, at (50, 30)
    });
    const auto regions = extractRegions(coverageFromBits(w, h, bits));
    REQUIRE(regions.size() == 1);
    CHECK(regions[0].holes.empty());
    CHECK(regions[0].pixelCount == 1200);
    CHECK(polygonSignedArea(regions[0].outer) > 0);
    CHECK(test::countLoopIntersections(loopsOf(regions[0])) == 0);
}

TEST_CASE("a hole pinched against the outline stays a separate simple loop", "[regions]") {
    // A square ring whose hole touches the outer background only diagonally.
    const int w = 40, h = 40;
    auto bits = rasterize(w, h, [](double x, double y) { return x > 5 && x < 35 && y > 5 && y < 35; });
    for (int y = 15; y < 25; ++y)
        for (int x = 15; x < 25; ++x) bits[y * w + x] = 0;
    // A diagonal chain of background pixels from the hole towards the outside.
    for (int k = 0; k < 10; ++k) bits[(14 - k) * w + (14 - k)] = 0;
    const auto regions = extractRegions(coverageFromBits(w, h, bits));
    REQUIRE(regions.size() == 1);
    CHECK(regions[0].holes.size() == 1);
    CHECK(test::countLoopIntersections(loopsOf(regions[0])) == 0);
}

TEST_CASE("regions touching the image border are closed along it", "[regions]") {
    const int w = 100, h = 60;
    const auto bits = rasterize(w, h, [](double x, double y) { return x < 40 || y > 50; });
    const auto regions = extractRegions(coverageFromBits(w, h, bits));
    REQUIRE(regions.size() == 1);
    const auto& p = regions[0].outer.points;
    double minX = 1e9, minY = 1e9, maxX = -1e9, maxY = -1e9;
    for (const Vec2 q : p) {
        minX = std::min(minX, q.x), maxX = std::max(maxX, q.x);
        minY = std::min(minY, q.y), maxY = std::max(maxY, q.y);
    }
    CHECK(minX == Approx(0).margin(1e-9));
    CHECK(minY == Approx(0).margin(1e-9));
    CHECK(maxX == Approx(100).margin(1e-9));
    CHECK(maxY == Approx(60).margin(1e-9));
    CHECK(polygonSignedArea(regions[0].outer) == Approx(40 * 60 + 60 * 10).epsilon(0.01));
    CHECK(test::countLoopIntersections({&regions[0].outer}) == 0);
}

TEST_CASE("a label map gives one region per label component", "[regions]") {
    const int w = 60, h = 40;
    std::vector<int> labels(w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) labels[y * w + x] = x < 20 ? 7 : (x < 40 ? 3 : 7);
    const auto regions = extractRegionsFromLabels(w, h, labels);
    REQUIRE(regions.size() == 3);
    double total = 0;
    int sevens = 0;
    for (const auto& r : regions) {
        total += polygonSignedArea(r.outer);
        sevens += r.label == 7;
        CHECK(r.pixelCount == 800);
    }
    CHECK(sevens == 2);
    CHECK(total == Approx(w * h).epsilon(0.002));
}

TEST_CASE("a mask image is object where it is white and opaque", "[regions]") {
    RgbaImage mask(30, 20);
    for (int y = 5; y < 15; ++y)
        for (int x = 5; x < 25; ++x) std::fill(mask.at(x, y), mask.at(x, y) + 4, 1.f);
    const auto regions = extractRegions(coverageFromMaskImage(mask));
    REQUIRE(regions.size() == 1);
    CHECK(regions[0].pixelCount == 200);
}

TEST_CASE("bad masks are reported", "[regions]") {
    const std::vector<uint8_t> empty(100, 0);
    CHECK_THROWS_AS(extractRegions(coverageFromBits(10, 10, empty)), Error);
    CHECK_THROWS_WITH(extractRegions(coverageFromBits(10, 10, empty)), Catch::Contains("empty"));
    CHECK_THROWS_AS(coverageFromBits(10, 10, std::vector<uint8_t>(99, 1)), Error);
    CHECK_THROWS_AS(extractRegions(Coverage{0, 0, {}}), Error);
    CHECK_THROWS_AS(extractRegionsFromLabels(4, 4, std::vector<int>(16, -1)), Error);
    CHECK_THROWS_WITH(requireMaskMatchesImage(RgbaImage(10, 10), RgbaImage(10, 11), "m.png"),
                      Catch::Contains("m.png") && Catch::Contains("10x11"));
    CHECK_NOTHROW(requireMaskMatchesImage(RgbaImage(10, 10), RgbaImage(10, 10), "m.png"));
}

TEST_CASE("a one-pixel object is dropped by minArea, or traced as a tiny loop", "[regions]") {
    std::vector<uint8_t> bits(100, 0);
    bits[5 * 10 + 5] = 1;
    CHECK_THROWS_WITH(extractRegions(coverageFromBits(10, 10, bits)),
                      Catch::Contains("minimum area"));
    RegionOptions opts;
    opts.minArea = 1;
    const auto regions = extractRegions(coverageFromBits(10, 10, bits), opts);
    REQUIRE(regions.size() == 1);
    CHECK(regions[0].outer.points.size() == 4);
    CHECK(polygonSignedArea(regions[0].outer) > 0);
}
