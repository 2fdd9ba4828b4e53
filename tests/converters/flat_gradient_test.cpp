// flat_gradient.h and its use in convertSegmented: flat regions whose colour runs across them
// painted with linear gradients.
#include "converters/flat_gradient.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "../support/gradient_shapes.h"
#include "converters/convert_segments.h"
#include "formats/raster.h"
#include "meshcore/render.h"

using namespace gm;

namespace {

// An image of w × h pixels coloured by `colour(x, y)` at each pixel centre.
template <class F>
RgbaImage imageOf(int w, int h, F colour) {
    RgbaImage image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Vec3 c = colour(x + 0.5, y + 0.5);
            float* px = image.at(x, y);
            for (int k = 0; k < 3; ++k) px[k] = static_cast<float>(c[k]);
            px[3] = 1;
        }
    return image;
}

std::vector<size_t> allPixels(const RgbaImage& image) {
    std::vector<size_t> at(static_cast<size_t>(image.width) * image.height);
    for (size_t k = 0; k < at.size(); ++k) at[k] = k;
    return at;
}

Region wholeRegion(const RgbaImage& image) {
    Region r;
    r.width = image.width, r.height = image.height;
    r.mask.assign(static_cast<size_t>(r.width) * r.height, 1);
    r.pixelCount = r.width * r.height;
    return r;
}

// A little deterministic noise, ±amplitude.
double noise(double x, double y, double amplitude) {
    return amplitude * std::sin(12.9898 * x + 78.233 * y) * std::cos(4.1414 * x - 2.7182 * y);
}

}  // namespace

TEST_CASE("a ramp's gradient runs along the ramp with its end colours", "[flat][gradient]") {
    // Red to blue along the direction (3, 4)/5, over a 60 × 40 image.
    const Vec2 dir{0.6, 0.8};
    const RgbaImage image = imageOf(60, 40, [&](double x, double y) {
        const double t = std::clamp((dot({x, y}, dir) - 10) / 40, 0.0, 1.0);
        return Vec3{0.9 - 0.8 * t, 0.2, 0.1 + 0.8 * t};
    });
    const std::vector<size_t> at = allPixels(image);
    GradientFitOptions options;
    options.errorPerByte = 10;
    const LinearGradient g = fitPayingGradient(image, at, Vec3{0.5, 0.2, 0.5}, options);
    REQUIRE(g.stops.size() >= 2);
    const Vec2 axis = g.to - g.from;
    CHECK(std::fabs(dot(axis, dir)) / norm(axis) > 0.999);
    // The fit's colours within 2/255 at every pixel.
    double worst = 0;
    for (size_t k : at) {
        const Vec2 p{double(k % 60) + 0.5, double(k / 60) + 0.5};
        const float* px = image.at(static_cast<int>(k % 60), static_cast<int>(k / 60));
        const Vec3 c = g.colourAt(p);
        for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::fabs(c[ch] - px[ch]));
    }
    CHECK(worst * 255 < 2.5);
    CHECK(gradientFitError(image, at, g).meanAbs < 1);
}

TEST_CASE("a gradient is kept only when the error it wins back pays for its bytes",
          "[flat][gradient]") {
    const RgbaImage flat = imageOf(40, 30, [](double x, double y) {
        return Vec3{0.4 + noise(x, y, 0.01), 0.5, 0.6};
    });
    CHECK(fitPayingGradient(flat, allPixels(flat), Vec3{0.4, 0.5, 0.6}).stops.empty());
    // A gentle ramp of 20/255 over the image: worth a gradient at a low price per byte, not at
    // a high one.
    const RgbaImage ramp = imageOf(40, 30, [](double x, double) {
        return Vec3{0.4 + 20.0 / 255 * x / 40, 0.5, 0.6};
    });
    const Vec3 mean{0.4 + 10.0 / 255, 0.5, 0.6};
    GradientFitOptions cheap, dear;
    cheap.errorPerByte = 10;
    dear.errorPerByte = 1e5;
    const LinearGradient kept = fitPayingGradient(ramp, allPixels(ramp), mean, cheap);
    CHECK(kept.stops.size() == 2);  // a straight ramp needs no more
    CHECK(fitPayingGradient(ramp, allPixels(ramp), mean, dear).stops.empty());
    // A ramp that bends (dark, bright, dark) takes a middle stop.
    const RgbaImage bent = imageOf(40, 30, [](double x, double) {
        const double t = x / 40;
        return Vec3{0.1 + 0.8 * (1 - std::fabs(2 * t - 1)), 0.3, 0.3};
    });
    CHECK(fitPayingGradient(bent, allPixels(bent), Vec3{0.5, 0.3, 0.3}, cheap).stops.size() >= 3);
}

TEST_CASE("a shaded region that a gradient fits is graded; texture is not", "[flat][gradient]") {
    const RgbaImage ramp = imageOf(50, 50, [](double x, double y) {
        return Vec3{0.2 + 0.6 * y / 50, 0.7 - 0.5 * y / 50, 0.3 + noise(x, y, 0.002)};
    });
    const LinearGradient g = fitGradedRegion(ramp, wholeRegion(ramp), 3);
    REQUIRE(g.stops.size() == 2);
    CHECK(std::fabs(norm(g.to - g.from) - 49) < 1.5);
    const RgbaImage textured = imageOf(50, 50, [](double x, double y) {
        return Vec3{0.2 + 0.6 * y / 50 + noise(x, y, 0.08), 0.5, 0.3};
    });
    CHECK(fitGradedRegion(textured, wholeRegion(textured), 3).stops.empty());
}

TEST_CASE("a drawing of graded shapes converts to graded flat shapes, not meshes",
          "[flat][gradient][convert]") {
    // The writers' test document drawn by our renderer: a flat backdrop and four shapes of
    // two- to four-stop gradients (one with a hole, one translucent over the others).
    Document drawing = gmtest::gradientTestDocument();
    const RgbaImage image = renderDocument(drawing, RenderOptions{}).image;
    SegmentConvertOptions options;
    SegmentConvertReport report;
    const Document doc = convertSegmented(image, options, "graded drawing", &report);
    int graded = 0;
    for (const FlatShape& s : doc.shapes) graded += s.graded();
    size_t meshPatches = 0;
    for (const GradientMesh& m : doc.meshes) meshPatches += static_cast<size_t>(m.patchCount());
    WARN("graded drawing: " << doc.shapes.size() << " shapes, " << graded << " graded, "
                            << doc.meshes.size() << " meshes of " << meshPatches
                            << " patches, PSNR " << report.convert.error.psnr << " dB");
    // The segmentation cuts the shapes where they overlap; the square and the diamond stay
    // whole and take gradients. Their borders with the meshes beside them stay closed: the
    // drawing is closer than without gradients, with fewer patches.
    CHECK(graded >= 2);
    options.gradients = false;
    SegmentConvertReport meshReport;
    const Document without = convertSegmented(image, options, "graded drawing", &meshReport);
    size_t withoutPatches = 0;
    for (const GradientMesh& m : without.meshes)
        withoutPatches += static_cast<size_t>(m.patchCount());
    for (const FlatShape& s : without.shapes) CHECK_FALSE(s.graded());
    WARN("without gradients: " << withoutPatches << " patches, PSNR "
                               << meshReport.convert.error.psnr << " dB");
    CHECK(meshPatches < withoutPatches);
    CHECK(report.convert.error.psnr > meshReport.convert.error.psnr);
    CHECK(report.convert.error.psnr > 34);
}

TEST_CASE("a flat trace grades the regions whose colour runs across them",
          "[flat][gradient][convert]") {
    // HappyFish.jpg is drawn with gradients: at --total-patches 0 its body, face and fins take
    // gradients, and the trace draws the image closer than one colour a region.
    const RgbaImage image = readImage(std::string(GRADMESH_SAMPLES) + "/HappyFish.jpg");
    SegmentConvertOptions options;
    options.totalPatches = 0;
    options.flatOnly = true;
    options.convert.maxError = 8;
    options.residue = false;  // what the regions miss would make up part of the difference
    SegmentConvertReport graded, plain;
    const Document doc = convertSegmented(image, options, "HappyFish.jpg", &graded);
    options.gradients = false;
    convertSegmented(image, options, "HappyFish.jpg", &plain);
    int count = 0;
    for (const FlatShape& s : doc.shapes) count += s.graded();
    WARN("HappyFish at E 8, flat: " << count << " graded shapes, PSNR " << graded.convert.error.psnr
                                    << " dB against " << plain.convert.error.psnr << " dB without");
    CHECK(doc.meshes.empty());
    CHECK(count >= 4);
    CHECK(graded.convert.error.psnr > plain.convert.error.psnr + 1);
}
