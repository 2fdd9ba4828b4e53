// flat_residue.h: blobs that a flat trace's regions miss become regions of their own on top.
#include "converters/flat_residue.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "converters/convert_segments.h"
#include "formats/raster.h"
#include "meshcore/render.h"

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

TEST_CASE("a drawing's missed blobs become flat shapes of their colour, where they pay",
          "[flat][residue]") {
    // The drawing paints the white and the first disc; the other two discs are missed.
    const RgbaImage image = bubbles();
    std::vector<Vec3> painted(static_cast<size_t>(kW) * kH, kWhite);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (inDisc(x, y, 15, 15, 5)) painted[static_cast<size_t>(y) * kW + x] = kPink;
    const std::vector<Region> regions{whole()};
    const std::vector<FlatShape> shapes =
        residueShapes(image, regions, 1, painted, 3, 1000, FlatOptions{});
    REQUIRE(shapes.size() == 2);
    for (const FlatShape& shape : shapes) {
        CHECK(shape.col.r == Approx(kPink.r).margin(0.01));
        CHECK(shape.col.g == Approx(kPink.g).margin(0.01));
        CHECK(shape.subpaths.size() == 1);
        CHECK_FALSE(shape.graded());
    }
    // The disc's outline lies about its edge: 5 px from its centre.
    for (const Vec2& p : shapes[0].subpaths[0])
        CHECK(std::hypot(p.x - 40, p.y - 30) == Approx(5).margin(1.5));
    CHECK(residueShapes(image, regions, 1, painted, 3, 1e6, FlatOptions{}).empty());
    // The drawing's own error raises the limits: painted in grey, E is about 50, and the
    // discs differ from it by less than three times that. With limits from E 3 alone, the
    // whole canvas would be one blob.
    const std::vector<Vec3> grey(painted.size(), kWhite * 0.8);
    CHECK(residueShapes(image, regions, 1, grey, 3, 1000, FlatOptions{}).empty());
}

TEST_CASE("a shaded image's meshes get flat shapes on top for the specks they miss",
          "[flat][residue][convert]") {
    // A smooth ramp with small saturated specks: the meshes of a small budget smooth them
    // away; a flat shape each brings them back, drawn above every mesh.
    RgbaImage image(96, 72);
    const auto speck = [](int x, int y) {
        for (const auto& c : {std::pair{20.0, 20.0}, {70.0, 25.0}, {45.0, 55.0}})
            if (inDisc(x, y, c.first, c.second, 2.2)) return true;
        return false;
    };
    for (int y = 0; y < 72; ++y)
        for (int x = 0; x < 96; ++x) {
            float* px = image.at(x, y);
            const Vec3 ramp{0.2 + 0.6 * x / 96.0, 0.3 + 0.4 * y / 72.0, 0.5};
            const Vec3 c = speck(x, y) ? Vec3{0.95, 0.1, 0.1} : ramp;
            for (int k = 0; k < 3; ++k) px[k] = static_cast<float>(c[k]);
            px[3] = 1;
        }
    SegmentConvertOptions options;
    options.totalPatches = 40;
    SegmentConvertReport with, without;
    const Document doc = convertSegmented(image, options, "specks", &with);
    options.residue = false;
    const Document bare = convertSegmented(image, options, "specks", &without);
    WARN("specks: " << with.residueRegions << " residue shapes, PSNR " << with.convert.error.psnr
                    << " dB against " << without.convert.error.psnr << " dB without");
    CHECK(with.residueRegions >= 1);
    CHECK(without.residueRegions == 0);
    const size_t added = static_cast<size_t>(with.residueRegions);
    REQUIRE(doc.shapes.size() >= added);
    for (size_t k = doc.shapes.size() - added; k < doc.shapes.size(); ++k)
        CHECK(doc.shapes[k].layer == doc.meshes.size());
    CHECK(with.convert.error.psnr > without.convert.error.psnr + 1);
    // The specks' pixels: drawn much closer to red than without the shapes.
    const auto speckError = [&](const Document& d) {
        const RgbaImage drawn = renderDocument(d, RenderOptions{}).image;
        double sum = 0;
        for (int y = 0; y < 72; ++y)
            for (int x = 0; x < 96; ++x)
                if (speck(x, y))
                    for (int k = 0; k < 3; ++k) sum += std::fabs(drawn.at(x, y)[k] - image.at(x, y)[k]);
        return sum;
    };
    CHECK(speckError(doc) < 0.6 * speckError(bare));
}
