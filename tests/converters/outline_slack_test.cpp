// outline_slack.h and its use by traceFlatShape: a flat shape's outline beneath later regions
// strays from its jagged border, clear of what must show.
#include "outline_slack.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "converters/convert_segments.h"
#include "converters/flat_regions.h"
#include "meshcore/render.h"

using namespace gm;

namespace {

constexpr int kW = 60, kH = 40;

std::vector<uint8_t> maskWhere(bool (*inside)(int x, int y)) {
    std::vector<uint8_t> m(static_cast<size_t>(kW) * kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) m[static_cast<size_t>(y) * kW + x] = inside(x, y);
    return m;
}

// A region whose right side zigzags (2 px in and out every third row), and a band drawn later
// over that side, 8 px wide.
bool ownPixel(int x, int y) { return x >= 5 && y >= 5 && y < 35 && x < 29 + 2 * ((y / 3) % 2); }
bool underPixel(int x, int y) { return x >= 27 && x < 35 && y >= 2 && y < 38; }

}  // namespace

TEST_CASE("an outline has room beneath a later region, away from what must show",
          "[flat][slack]") {
    const std::vector<uint8_t> own = maskWhere(ownPixel), under = maskWhere(underPixel);
    const OutlineSlack slack = hiddenOutlineSlack(own, under, kW, kH, 2);
    // In the band: as much room as asked for 4 px from the region's shown pixels and from the
    // band's far side; less nearer them (less a margin of 1.5 px).
    CHECK(slack.at({31.5, 20.5}) == 2);
    CHECK(slack.at({29.5, 20.5}) == Approx(1.5));
    // Where the region borders pixels that show (its left side, the band's far edge): none.
    CHECK(slack.at({4.5, 20.5}) == 0);
    CHECK(slack.at({34.5, 20.5}) == 0);
    CHECK(slack.at({-1, 5}) == 0);
    CHECK(OutlineSlack{}.at({10, 10}) == 0);
}

TEST_CASE("a flat shape's outline beneath a later region takes fewer curves, covering the same",
          "[flat][slack]") {
    const std::vector<uint8_t> own = maskWhere(ownPixel), under = maskWhere(underPixel);
    RgbaImage image(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const bool in = ownPixel(x, y);
            float* px = image.at(x, y);
            px[0] = in ? 0.8f : 0.1f, px[1] = 0.3f, px[2] = in ? 0.2f : 0.7f, px[3] = 1;
        }
    Region region;
    region.width = kW, region.height = kH, region.mask = own;
    for (uint8_t v : own) region.pixelCount += v;
    FlatOptions tight, slack;
    tight.hiddenReach = 0;
    slack.hiddenReach = 1.5;
    const Vec3 col{0.8, 0.3, 0.2};
    const FlatShape a = traceFlatShape(image, region, col, 1, under, tight);
    const FlatShape b = traceFlatShape(image, region, col, 1, under, slack);
    size_t pointsA = 0, pointsB = 0;
    for (const auto& p : a.subpaths) pointsA += p.size();
    for (const auto& p : b.subpaths) pointsB += p.size();
    WARN("staircase under a band: " << pointsA / 3 << " cubics tight, " << pointsB / 3
                                    << " with room");
    CHECK(pointsB * 2 <= pointsA);
    // Drawn, the roomy shape covers the pixels of the region that show as the tight one does
    // (to a tenth: their visible sides are fitted alike, within half a pixel), and paints what
    // must stay as it is no more than it does.
    Document doc;
    doc.width = kW, doc.height = kH;
    auto coverOf = [&](const FlatShape& shape) {
        doc.shapes = {shape};
        return renderDocument(doc, RenderOptions{}).image;
    };
    const RgbaImage coverA = coverOf(a), coverB = coverOf(b);
    float leakA = 0, leakB = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const float alphaA = coverA.at(x, y)[3], alphaB = coverB.at(x, y)[3];
            if (ownPixel(x, y) && !underPixel(x, y) && alphaB < std::min(0.9f, alphaA - 0.1f))
                FAIL_CHECK("pixel " << x << "," << y << " covered " << alphaB << ", tight "
                                    << alphaA);
            if (!ownPixel(x, y) && !underPixel(x, y))
                leakA = std::max(leakA, alphaA), leakB = std::max(leakB, alphaB);
        }
    CHECK(leakB <= std::max(0.25f, leakA + 0.02f));
}

TEST_CASE("coarse flat shapes lie on a tenth-pixel grid, their straight sides still lines",
          "[flat][convert]") {
    // A rectangle and a disc on a backdrop, traced at --max-error 8: the outlines' tolerance
    // (0.5 px × 8/3) puts their points on a 0.1 px grid; the rectangle's sides stay lines.
    RgbaImage image(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const bool box = x >= 6 && x < 26 && y >= 8 && y < 30;
            const bool disc = std::hypot(x + 0.5 - 42, y + 0.5 - 20) < 10;
            float* px = image.at(x, y);
            px[0] = box ? 0.9f : disc ? 0.1f : 0.95f;
            px[1] = box ? 0.2f : disc ? 0.5f : 0.95f;
            px[2] = box ? 0.2f : disc ? 0.9f : 0.9f;
            px[3] = 1;
        }
    SegmentConvertOptions options;
    options.convert.maxError = 8;
    const Document doc = convertSegmented(image, options, "box and disc");
    REQUIRE(doc.shapes.size() >= 3);
    int lines = 0;
    for (const FlatShape& s : doc.shapes)
        for (const std::vector<Vec2>& path : s.subpaths) {
            for (size_t k = 0; k < path.size(); ++k) {
                const bool anchor = k % 3 == 0;
                const Vec2 p = path[k];
                if (anchor) {
                    CHECK(std::fabs(p.x * 10 - std::round(p.x * 10)) < 1e-6);
                    CHECK(std::fabs(p.y * 10 - std::round(p.y * 10)) < 1e-6);
                }
            }
            for (size_t m = 0; 3 * m < path.size(); ++m) {
                const Vec2 a = path[3 * m], b = path[(3 * m + 3) % path.size()];
                lines += norm(path[3 * m + 1] - (a + (1.0 / 3) * (b - a))) < 1e-9;
            }
        }
    CHECK(lines >= 4);
}
