// flat_residue.h: blobs that a flat trace's regions miss become regions of their own on top.
#include "converters/flat_residue.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "converters/convert_segments.h"
#include "formats/raster.h"

using namespace gm;

namespace {

constexpr int kW = 80, kH = 60;
const Vec3 kWhite{0.98, 0.98, 0.97}, kPink{0.95, 0.6, 0.65};

bool inDisc(int x, int y, double cx, double cy, double r) {
    return std::hypot(x + 0.5 - cx, y + 0.5 - cy) < r;
}

// White, with three pink discs of radius 5 and a pink speck of two pixels.
RgbaImage bubbles() {
    RgbaImage image(kW, kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const bool pink = inDisc(x, y, 15, 15, 5) || inDisc(x, y, 40, 30, 5) ||
                              inDisc(x, y, 62, 45, 5) || (y == 50 && (x == 10 || x == 11));
            const Vec3 c = pink ? kPink : kWhite;
            float* px = image.at(x, y);
            for (int k = 0; k < 3; ++k) px[k] = static_cast<float>(c[k]);
            px[3] = 1;
        }
    return image;
}

Region whole() {
    Region r;
    r.width = kW, r.height = kH;
    r.mask.assign(static_cast<size_t>(kW) * kH, 1);
    r.pixelCount = kW * kH;
    return r;
}

}  // namespace

TEST_CASE("blobs a region's paint misses become regions on top, where they pay",
          "[flat][residue]") {
    const RgbaImage image = bubbles();
    auto white = [](size_t, size_t) { return kWhite; };
    std::vector<Region> regions{whole()};
    size_t firstInk = 1;
    CHECK(addResidueRegions(image, regions, firstInk, white, 3, 1000) == 3);
    REQUIRE(regions.size() == 4);
    CHECK(firstInk == 4);
    for (size_t k = 1; k < 4; ++k) CHECK(regions[k].pixelCount == Approx(78).margin(6));
    CHECK(regions[1].mask[static_cast<size_t>(15) * kW + 15]);
    CHECK_FALSE(regions[1].mask[static_cast<size_t>(50) * kW + 10]);  // the speck stays
    // At a high enough price per byte, none pays.
    std::vector<Region> dear{whole()};
    size_t dearInk = 1;
    CHECK(addResidueRegions(image, dear, dearInk, white, 3, 1e6) == 0);
    CHECK(dear.size() == 1);
}

TEST_CASE("residue regions come before the ink lines, and ink pixels are left",
          "[flat][residue]") {
    const RgbaImage image = bubbles();
    // An ink line over the first disc: its pixels are the ink's, not the background's.
    Region ink;
    ink.width = kW, ink.height = kH;
    ink.mask.assign(static_cast<size_t>(kW) * kH, 0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (inDisc(x, y, 15, 15, 7)) ink.mask[static_cast<size_t>(y) * kW + x] = 1;
    std::vector<Region> regions{whole(), ink};
    size_t firstInk = 1;
    auto white = [](size_t, size_t) { return kWhite; };
    CHECK(addResidueRegions(image, regions, firstInk, white, 3, 1000) == 2);
    REQUIRE(regions.size() == 4);
    CHECK(firstInk == 3);
    CHECK(regions[3].mask == ink.mask);  // still last
}

TEST_CASE("a flat trace draws the details its regions miss", "[flat][residue][convert]") {
    // HappyFish.jpg at --total-patches 0: the bubbles and the fins' other colours, which the
    // segmentation merged into the regions around them.
    const RgbaImage image = readImage(std::string(GRADMESH_SAMPLES) + "/HappyFish.jpg");
    SegmentConvertOptions options;
    options.totalPatches = 0;
    options.flatOnly = true;
    options.convert.maxError = 8;
    SegmentConvertReport with, without;
    convertSegmented(image, options, "HappyFish.jpg", &with);
    options.residue = false;
    convertSegmented(image, options, "HappyFish.jpg", &without);
    WARN("HappyFish at E 8, flat: " << with.residueRegions << " residue regions, PSNR "
                                   << with.convert.error.psnr << " dB against "
                                   << without.convert.error.psnr << " dB without");
    CHECK(with.residueRegions >= 3);
    CHECK(without.residueRegions == 0);
    CHECK(with.convert.error.psnr > without.convert.error.psnr + 0.3);
}
