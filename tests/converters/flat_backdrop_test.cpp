// flat_backdrop.h: regions of nearly the backdrop's colour that touch it join it.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "converters/convert_segments.h"
#include "flat_backdrop.h"
#include "formats/raster.h"
#include "formats/svg.h"

using namespace gm;

namespace {

constexpr int kW = 40, kH = 20;

// A region of the kW × kH canvas holding the pixels where inside(x, y).
template <class Inside>
Region regionWhere(int label, Inside inside) {
    Region r;
    r.width = kW;
    r.height = kH;
    r.label = label;
    r.mask.assign(static_cast<size_t>(kW) * kH, 0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (inside(x, y)) {
                r.mask[static_cast<size_t>(y) * kW + x] = 1;
                ++r.pixelCount;
            }
    return r;
}

bool inDisc(int x, int y, int cx, int cy, int radius) {
    return (x - cx) * (x - cx) + (y - cy) * (y - cy) <= radius * radius;
}

}  // namespace

TEST_CASE("regions of nearly the backdrop's colour that touch it join it", "[flat][segment]") {
    // Left half white (the backdrop), right half nearly white, a red disc on the border between
    // them with a nearly white speck inside it, and a nearly white ink line along the bottom.
    const auto disc = [](int x, int y) { return inDisc(x, y, 20, 10, 6); };
    const auto speck = [](int x, int y) { return inDisc(x, y, 20, 10, 1); };
    const auto ink = [](int x, int y) { return y == kH - 1; };
    std::vector<Region> regions{
        regionWhere(1, [&](int x, int y) { return x < 20 && !disc(x, y) && !ink(x, y); }),
        regionWhere(2, [&](int x, int y) { return x >= 20 && !disc(x, y) && !ink(x, y); }),
        regionWhere(3, [&](int x, int y) { return disc(x, y) && !speck(x, y); }),
        regionWhere(4, speck),
        regionWhere(5, ink)};
    const Vec3 white{1, 1, 1}, nearlyWhite{0.99, 1, 0.995}, red{0.9, 0.1, 0.1};
    const std::vector<Vec3> colours{white, nearlyWhite, red, nearlyWhite, nearlyWhite};
    const int backdropPixels = regions[0].pixelCount + regions[1].pixelCount;

    SECTION("the half joins; the speck, which does not touch it, and the ink line stay") {
        CHECK(mergeIntoBackdrop(regions, 4, colours, 0.02) == 1);
        REQUIRE(regions.size() == 4);
        CHECK(regions[0].label == 1);
        CHECK(regions[0].pixelCount == backdropPixels);
        CHECK(regions[1].label == 3);
        CHECK(regions[2].label == 4);
        CHECK(regions[3].label == 5);
    }
    SECTION("a colour further off than the tolerance stays") {
        CHECK(mergeIntoBackdrop(regions, 4, colours, 0.005) == 0);
        CHECK(regions.size() == 5);
    }
}

TEST_CASE("a flat drawing writes no shapes for the backdrop's pieces", "[flat][segment]") {
    // HappyFish at --total-patches 0: the segmentation cuts its white background in pieces; at
    // E 8 those within 8/255 of the backdrop join it and take no outline in the file.
    const RgbaImage fish = readImage(std::string(GRADMESH_SAMPLES) + "/HappyFish.jpg");
    SegmentConvertOptions o;
    o.flatOnly = true;
    o.convert.maxError = 8;
    SegmentConvertReport report;
    const Document doc = convertSegmented(fish, o, "HappyFish.jpg", &report);
    WARN("HappyFish flat at E 8: " << report.mergedIntoBackdrop << " regions joined the backdrop, "
         << doc.shapes.size() << " shapes, " << encodeSvg(doc, WriteOptions{}).size()
         << " B, PSNR " << report.convert.error.psnr << " dB");
    CHECK(report.mergedIntoBackdrop >= 1);
    CHECK(report.flatBackdrop);
    CHECK(report.convert.error.psnr > 18.0);
}
