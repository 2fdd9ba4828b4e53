// Flat shapes (FlatShape) in the renderer: anti-aliased coverage, holes, paint order among the
// meshes, samples, validation.
#include <catch2/catch.hpp>
#include <cmath>

#include "meshcore/render.h"
#include "meshcore/synthetic_meshes.h"
#include "meshcore/validate.h"

using namespace gm;

namespace {

double coveredArea(const RgbaImage& img) {
    double area = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) area += img.at(x, y)[3];
    return area;
}

}  // namespace

TEST_CASE("a flat ring renders its colour with an empty hole and exact area", "[render][flat]") {
    Document doc;
    doc.width = 200;
    doc.height = 200;
    const Vec3 red{0.8, 0.1, 0.2};
    doc.shapes.push_back(makeFlatRing(100.3, 99.6, 70, 30, red));
    REQUIRE(validateDocument(doc).empty());
    const RenderResult r = renderDocument(doc);
    // Four cubics are within 3e-4 of a circle's radius: the ring's area to a fraction of a pixel
    // per unit of outline.
    const double area = M_PI * (70.0 * 70 - 30.0 * 30);
    CHECK(std::fabs(coveredArea(r.image) - area) < 0.002 * area);
    const float* inside = r.image.at(100 + 50, 100);
    CHECK(inside[3] == 1.0f);
    CHECK(inside[0] == Approx(0.8).margin(1e-6));
    CHECK(inside[1] == Approx(0.1).margin(1e-6));
    CHECK(r.image.at(100, 100)[3] == 0.0f);  // the hole
    CHECK(r.image.at(5, 5)[3] == 0.0f);      // outside
    // Outline pixels are partly covered.
    int partial = 0;
    for (int x = 0; x < 200; ++x) {
        const float a = r.image.at(x, 100)[3];
        partial += a > 0 && a < 1;
    }
    CHECK(partial >= 2);
    CHECK(partial <= 4);
}

TEST_CASE("flat shapes paint between the meshes in their layer order", "[render][flat]") {
    const Document doc = makeFlatDocument();
    REQUIRE(validateDocument(doc).empty());
    RenderOptions o;
    o.wantSamples = true;
    const RenderResult r = renderDocument(doc, o);
    const size_t w = static_cast<size_t>(doc.width);
    // The ring's colour where only the first mesh is beneath it.
    const float* ring = r.image.at(40, 86);
    CHECK(ring[0] == Approx(0.85).margin(1e-6));
    CHECK(r.samples[86 * w + 40].mesh == -1);
    // The second mesh over the ring's right side.
    const float* over = r.image.at(145, 86);
    CHECK(over[0] != Approx(0.85).margin(1e-3));
    CHECK(r.samples[86 * w + 145].mesh == 1);
    // The ring's hole shows the first mesh.
    CHECK(r.samples[86 * w + 90].mesh == 0);
    // The square on top of all, its hole showing the ring or the first mesh.
    const float* square = r.image.at(25, 165);
    CHECK(square[2] == Approx(0.9).margin(1e-6));
    CHECK(r.samples[140 * w + 50].mesh == 0);
}

TEST_CASE("a shape's layer beyond the meshes, bad colours and bad point counts are invalid",
          "[validate][flat]") {
    Document doc = makeFlatDocument();
    doc.shapes[1].layer = 3;
    CHECK_FALSE(validateDocument(doc).empty());
    doc = makeFlatDocument();
    std::swap(doc.shapes[0].layer, doc.shapes[1].layer);
    CHECK(validateDocument(doc).find("below the shape before") != std::string::npos);
    doc = makeFlatDocument();
    doc.shapes[0].col.g = 1.5;
    CHECK_FALSE(validateDocument(doc).empty());
    doc = makeFlatDocument();
    doc.shapes[0].subpaths[0].pop_back();
    CHECK(validateDocument(doc).find("multiple of 3") != std::string::npos);
    doc = makeFlatDocument();
    doc.shapes[0].subpaths[1][4].x = NAN;
    CHECK_FALSE(validateDocument(doc).empty());
}
