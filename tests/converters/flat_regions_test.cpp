// Flat regions of whole images (flat_regions.h): the flat-colour test, the Bézier fit of an
// outline, and a flat drawing converted into flat shapes.
#include "converters/flat_regions.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <set>

#include "converters/convert_segments.h"
#include "converters/regions.h"
#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/render.h"
#include "meshcore/synthetic_meshes.h"
#include "meshcore/validate.h"

using namespace gm;

namespace {

Vec2 cubicAt(const std::vector<Vec2>& path, size_t k, double t) {
    const size_t n = path.size();
    const Vec2 a = path[k], b = path[k + 1], c = path[k + 2], d = path[(k + 3) % n];
    const double u = 1 - t;
    return (u * u * u) * a + (3 * u * u * t) * b + (3 * u * t * t) * c + (t * t * t) * d;
}

// The largest distance from a polygon vertex to the curves (dense samples).
double worstDistance(const std::vector<Vec2>& polygon, const std::vector<Vec2>& path) {
    std::vector<Vec2> samples;
    for (size_t k = 0; k < path.size(); k += 3)
        for (int s = 0; s < 200; ++s) samples.push_back(cubicAt(path, k, s / 200.0));
    double worst = 0;
    for (const Vec2& p : polygon) {
        double best = INFINITY;
        for (const Vec2& q : samples) best = std::min(best, norm(p - q));
        worst = std::max(worst, best);
    }
    return worst;
}

// A flat drawing: three anti-aliased rings and a square on white, drawn by our renderer.
RgbaImage flatDrawing() {
    Document d;
    d.width = 220;
    d.height = 160;
    d.shapes.push_back(makeFlatRing(60, 60, 45, 25, {0.9, 0.1, 0.1}));
    d.shapes.push_back(makeFlatRing(155, 60, 45, 25, {0.1, 0.7, 0.2}));
    d.shapes.push_back(makeFlatRing(107, 110, 40, 22, {0.1, 0.2, 0.9}));
    RgbaImage img = renderDocument(d).image;
    compositeOver(img, {1, 1, 1, 1});
    return img;
}

}  // namespace

TEST_CASE("a circle's polygon becomes a few cubics within half a pixel", "[flat]") {
    std::vector<Vec2> circle;
    for (int k = 0; k < 240; ++k) {
        const double a = 2 * M_PI * k / 240;
        circle.push_back({100 + 40 * std::cos(a), 80 + 40 * std::sin(a)});
    }
    const std::vector<Vec2> path = fitClosedCubics(circle, 0.5);
    REQUIRE(path.size() % 3 == 0);
    CHECK(path.size() / 3 <= 8);
    CHECK(worstDistance(circle, path) <= 0.5);
}

TEST_CASE("a square's polygon keeps its corners as four lines", "[flat]") {
    const std::vector<Vec2> square = {{10, 10}, {50, 10}, {50, 50}, {10, 50}};
    const std::vector<Vec2> path = fitClosedCubics(square, 0.5);
    REQUIRE(path.size() == 12);
    for (size_t k = 0; k < 4; ++k) CHECK(path[3 * k] == square[k]);
    CHECK(worstDistance(square, path) <= 1e-9);
}

TEST_CASE("one colour is flat within the error target; a gradient is not", "[flat]") {
    const int W = 60, H = 40;
    RgbaImage flat(W, H), ramp(W, H);
    Region all;
    all.width = W, all.height = H;
    all.mask.assign(W * H, 1);
    all.pixelCount = W * H;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float noise = ((x * 7 + y * 13) % 3 - 1) / 255.0f;
            float* p = flat.at(x, y);
            p[0] = 0.4f + noise, p[1] = 0.5f, p[2] = 0.6f, p[3] = 1;
            float* q = ramp.at(x, y);
            q[0] = 0.2f + 0.4f * x / W, q[1] = 0.5f, q[2] = 0.6f, q[3] = 1;
        }
    const FlatFit a = fitFlatColour(flat, all, 3.0);
    CHECK(a.flat);
    CHECK(a.col.r == Approx(0.4).margin(1.0 / 255));
    CHECK(a.interior.meanAbs < 1);
    CHECK_FALSE(fitFlatColour(ramp, all, 3.0).flat);
}

TEST_CASE("a flat drawing converts into flat shapes and a far smaller SVG", "[flat][convert]") {
    const RgbaImage image = flatDrawing();
    SegmentConvertOptions options;
    SegmentConvertReport withFlat, withoutFlat;
    const Document flatDoc = convertSegmented(image, options, "rings", &withFlat);
    options.flatShapes = false;
    const Document meshDoc = convertSegmented(image, options, "rings", &withoutFlat);
    CHECK(validateDocument(flatDoc).empty());
    CHECK(withFlat.flatRegions >= 4);  // the background and the three rings
    // Every region flat: the first becomes the backdrop over the whole canvas, in place of
    // the base mesh, and there is no mesh at all.
    CHECK(withFlat.flatBackdrop);
    CHECK(flatDoc.meshes.empty());
    REQUIRE(flatDoc.shapes.size() == static_cast<size_t>(withFlat.flatRegions));
    CHECK(flatDoc.shapes.front().subpaths ==
          std::vector<std::vector<Vec2>>{canvasRectangle(image.width, image.height, {}).subpaths});
    CHECK(withoutFlat.flatRegions == 0);
    WriteOptions write;
    write.svgScript = "none";
    const size_t flatBytes = encodeSvg(flatDoc, write).size();
    const size_t meshBytes = encodeSvg(meshDoc, write).size();
    INFO("SVG " << flatBytes << " vs " << meshBytes << " bytes; E "
                << withFlat.convert.error.meanAbs << " vs " << withoutFlat.convert.error.meanAbs);
    CHECK(flatBytes * 5 < meshBytes);
    CHECK(withFlat.convert.error.meanAbs <= withoutFlat.convert.error.meanAbs + 0.3);
    CHECK(withFlat.convert.error.meanAbs <= 1.5);
}

TEST_CASE("a drawing of flat shapes holds no mesh, and its outlines coarsen with the target",
          "[flat][convert]") {
    // thin_lines.png: lines and rings 2-4 px wide on three flat panels. Every region is flat,
    // so the first panel is the backdrop and there is no mesh (nor mesh script); every line
    // and ring is a stroke; a coarser --max-error loosens the fit.
    const RgbaImage drawing = readImage(std::string(GRADMESH_SAMPLES) + "/thin_lines.png");
    WriteOptions write;
    SegmentConvertOptions options;
    SegmentConvertReport fine, coarse;
    const Document fineDoc = convertSegmented(drawing, options, "thin_lines", &fine);
    const std::string fineSvg = encodeSvg(fineDoc, write);
    options.convert.maxError = 8;
    const size_t coarseBytes =
        encodeSvg(convertSegmented(drawing, options, "thin_lines", &coarse), write).size();
    WARN("thin_lines: E 3: " << fineSvg.size() << " B, PSNR " << fine.convert.error.psnr
                             << " dB; E 8: " << coarseBytes << " B, "
                             << coarse.convert.error.psnr << " dB");
    CHECK(fine.flatBackdrop);
    CHECK(fineDoc.meshes.empty());
    CHECK(fineSvg.find("<script") == std::string::npos);
    // The 18 lines and rings, each a stroke (two pieces of one line may share one).
    std::set<std::string> strokedColours;
    for (const FlatShape& shape : fineDoc.shapes)
        if (shape.stroked())
            strokedColours.insert(std::to_string(std::lround(shape.col.r * 255)) + "," +
                                  std::to_string(std::lround(shape.col.g * 255)) + "," +
                                  std::to_string(std::lround(shape.col.b * 255)) + "/" +
                                  std::to_string(std::lround(shape.strokeWidth)));
    CHECK(strokedColours.size() >= 15);
    CHECK(fineSvg.size() < 6000);
    CHECK(fine.convert.error.psnr > 38);
    CHECK(coarseBytes < fineSvg.size() * 0.95);
    CHECK(coarse.convert.error.meanAbs < 2);
}
