// flat_strokes.h and thin_on_top.h: thin flat regions traced as strokes along their
// centrelines, drawn after the other regions, and the regions of one colour they parted merged.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "converters/flat_strokes.h"
#include "meshcore/geometry.h"
#include "meshcore/render.h"
#include "thin_on_top.h"

using namespace gm;

namespace {

constexpr int kW = 80, kH = 60;
const Vec3 kBackground{0.9, 0.88, 0.85}, kInk{0.1, 0.15, 0.4};

// The drawing of `line` (a stroked shape) in kInk on kBackground, anti-aliased by our renderer,
// and the region of the pixels it covers at least half.
struct Drawn {
    RgbaImage image;
    Region region;
};

Drawn draw(const FlatShape& line) {
    Document doc;
    doc.width = kW, doc.height = kH;
    FlatShape ink = line;
    ink.col = kInk;
    doc.shapes = {ink};
    RenderOptions options;
    options.threads = 1;
    const RgbaImage cover = renderDocument(doc, options).image;
    Drawn d;
    d.image = RgbaImage(kW, kH);
    d.region.width = kW, d.region.height = kH;
    d.region.mask.assign(static_cast<size_t>(kW) * kH, 0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const float a = cover.at(x, y)[3];
            float* px = d.image.at(x, y);
            for (int c = 0; c < 3; ++c)
                px[c] = static_cast<float>(a * kInk[c] + (1 - a) * kBackground[c]);
            px[3] = 1;
            if (a >= 0.5f) {
                d.region.mask[static_cast<size_t>(y) * kW + x] = 1;
                ++d.region.pixelCount;
            }
        }
    return d;
}

Vec2 cubicAt(const std::vector<Vec2>& path, size_t m, double t) {
    const double u = 1 - t;
    return (u * u * u) * path[3 * m] + (3 * u * u * t) * path[3 * m + 1] +
           (3 * u * t * t) * path[3 * m + 2] + (t * t * t) * path[3 * m + 3];
}

// The furthest the centreline strays from the polyline `truth`.
double furthestFrom(const std::vector<Vec2>& path, const std::vector<Vec2>& truth) {
    double worst = 0;
    for (size_t m = 0; 3 * m + 3 < path.size(); ++m)
        for (int k = 0; k <= 20; ++k) {
            const Vec2 p = cubicAt(path, m, k / 20.0);
            double nearest = INFINITY;
            for (size_t s = 0; s + 1 < truth.size(); ++s)
                nearest = std::min(nearest, pointSegmentDistance(p, truth[s], truth[s + 1]));
            worst = std::max(worst, nearest);
        }
    return worst;
}

FlatShape strokeAlong(std::vector<Vec2> polyline, double width) {
    FlatShape s;
    s.strokeWidth = width;
    std::vector<Vec2> path{polyline.front()};
    for (size_t k = 0; k + 1 < polyline.size(); ++k) {
        const Vec2 a = polyline[k], b = polyline[k + 1];
        path.insert(path.end(), {a + (1.0 / 3) * (b - a), a + (2.0 / 3) * (b - a), b});
    }
    s.subpaths = {path};
    return s;
}

}  // namespace

TEST_CASE("a thin line converts to one stroke along its centreline", "[flat][strokes]") {
    const std::vector<Vec2> truth{{10, 12}, {40, 40}, {70, 18}};
    const Drawn d = draw(strokeAlong(truth, 3));
    const std::vector<uint8_t> none(static_cast<size_t>(kW) * kH, 0);
    const std::vector<FlatShape> strokes = traceStrokes(d.image, d.region, kInk, none);
    REQUIRE(strokes.size() == 1);
    REQUIRE(strokes[0].subpaths.size() == 1);
    const std::vector<Vec2>& path = strokes[0].subpaths[0];
    CHECK(path.size() % 3 == 1);
    CHECK(std::fabs(strokes[0].strokeWidth - 3) < 0.25);
    CHECK(furthestFrom(path, truth) < 0.3);
    // The ends are where the line's round caps end; the corner stays a corner.
    CHECK(norm(path.front() - truth.front()) + norm(path.back() - truth.back()) < 1.5);
    WARN("line: width " << strokes[0].strokeWidth << ", " << (path.size() - 1) / 3
                        << " cubics, off by at most " << furthestFrom(path, truth) << " px");
}

TEST_CASE("a thin ring converts to one closed stroke", "[flat][strokes]") {
    std::vector<Vec2> circle;
    for (int k = 0; k <= 48; ++k)
        circle.push_back(Vec2{40, 30} + 18 * Vec2{std::cos(k * M_PI / 24), std::sin(k * M_PI / 24)});
    const Drawn d = draw(strokeAlong(circle, 2.5));
    const std::vector<uint8_t> none(static_cast<size_t>(kW) * kH, 0);
    const std::vector<FlatShape> strokes = traceStrokes(d.image, d.region, kInk, none);
    REQUIRE(strokes.size() == 1);
    REQUIRE(strokes[0].subpaths.size() == 1);
    const std::vector<Vec2>& path = strokes[0].subpaths[0];
    CHECK(path.front() == path.back());  // closed
    CHECK(std::fabs(strokes[0].strokeWidth - 2.5) < 0.25);
    CHECK(furthestFrom(path, circle) < 0.3);
}

TEST_CASE("a thick or small region stays filled", "[flat][strokes]") {
    const std::vector<uint8_t> none(static_cast<size_t>(kW) * kH, 0);
    const Drawn thick = draw(strokeAlong({{20, 30}, {60, 30}}, 12));
    CHECK(traceStrokes(thick.image, thick.region, kInk, none).empty());
    const Drawn speck = draw(strokeAlong({{20, 30}, {21, 30}}, 2));
    CHECK(traceStrokes(speck.image, speck.region, kInk, none).empty());
}

TEST_CASE("a line whose strokes would miss its pixels stays filled", "[flat][strokes]") {
    // A wedge: 1 px wide at one end, 7 at the other; no single width draws it.
    Region wedge;
    wedge.width = kW, wedge.height = kH;
    wedge.mask.assign(static_cast<size_t>(kW) * kH, 0);
    RgbaImage image(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double half = 0.5 + 3.0 * (x - 10) / 60.0;
            const bool in = x >= 10 && x < 70 && std::fabs(y + 0.5 - 30) <= half;
            wedge.mask[static_cast<size_t>(y) * kW + x] = in;
            wedge.pixelCount += in;
            const Vec3 c = in ? kInk : kBackground;
            float* px = image.at(x, y);
            for (int k = 0; k < 3; ++k) px[k] = static_cast<float>(c[k]);
            px[3] = 1;
        }
    const std::vector<uint8_t> none(static_cast<size_t>(kW) * kH, 0);
    CHECK(traceStrokes(image, wedge, kInk, none).empty());
}

namespace {

Region regionWhere(bool (*inside)(int, int)) {
    Region r;
    r.width = kW, r.height = kH;
    r.mask.assign(static_cast<size_t>(kW) * kH, 0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (inside(x, y)) {
                r.mask[static_cast<size_t>(y) * kW + x] = 1;
                ++r.pixelCount;
            }
    return r;
}

double radiusAt(int x, int y) { return std::hypot(x + 0.5 - 40, y + 0.5 - 30); }

}  // namespace

TEST_CASE("a ring drawn on top lets the panel and its inside become one region",
          "[flat][strokes]") {
    // Drawing order: panel (around the ring), ring, inside, a dot of another colour (ink).
    std::vector<Region> regions{
        regionWhere([](int x, int y) { return radiusAt(x, y) > 21; }),
        regionWhere([](int x, int y) { return radiusAt(x, y) >= 18 && radiusAt(x, y) <= 21; }),
        regionWhere([](int x, int y) { return radiusAt(x, y) < 18 && radiusAt(x, y) >= 3; }),
        regionWhere([](int x, int y) { return radiusAt(x, y) < 3; })};
    CHECK(regionThickness(regions[1]) <= 4.5);
    CHECK(regionThickness(regions[0]) > 10);
    const std::vector<char> thin{0, 1, 0, 0};
    size_t firstInk = 3;
    const size_t firstThin = liftThinRegions(regions, firstInk, thin);
    REQUIRE(firstThin == 2);
    CHECK(regions[2].pixelCount > 0);
    CHECK(regionThickness(regions[2]) <= 4.5);  // the ring, now after the inside
    const std::vector<char> flat{1, 1, 1, 1};
    const std::vector<Vec3> colours{kBackground, kBackground, kInk, kInk};
    const size_t inside = regions[1].pixelCount, panel = regions[0].pixelCount;
    CHECK(mergeAcrossThin(regions, firstThin, firstInk, flat, colours, 0.01) == 1);
    REQUIRE(regions.size() == 3);
    CHECK(regions[0].pixelCount == static_cast<int>(panel + inside));
    CHECK(firstInk == 2);  // the ink dot moved down with the merge
}
