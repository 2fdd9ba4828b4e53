// Flat shapes (FlatShape) in the renderer: anti-aliased coverage, holes, strokes, paint order
// among the meshes, samples, validation.
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

// A stroke along the straight line a-b (one cubic, its handles at the thirds).
FlatShape strokeLine(Vec2 a, Vec2 b, double width) {
    FlatShape s;
    s.col = {0.2, 0.4, 0.6};
    s.strokeWidth = width;
    s.subpaths = {{a, a + (1.0 / 3) * (b - a), a + (2.0 / 3) * (b - a), b}};
    return s;
}

// A stroke along the circle of radius r about c: four cubics from (cx + r, cy) back to it.
FlatShape strokeCircle(Vec2 c, double r, double width) {
    constexpr double kappa = 0.5522847498307936;
    const Vec2 dirs[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    FlatShape s;
    s.col = {0.9, 0.5, 0.1};
    s.strokeWidth = width;
    std::vector<Vec2> path;
    for (int k = 0; k < 4; ++k) {
        const Vec2 a = dirs[k], b = dirs[(k + 1) % 4];
        path.insert(path.end(),
                    {c + r * a, c + r * a + (kappa * r) * b, c + r * b + (kappa * r) * a});
    }
    path.push_back(path.front());
    s.subpaths = {path};
    return s;
}

Document canvasWith(const FlatShape& shape, int width, int height) {
    Document doc;
    doc.width = width;
    doc.height = height;
    doc.shapes.push_back(shape);
    return doc;
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

TEST_CASE("a stroked straight line covers its width with round caps", "[render][flat][stroke]") {
    const double w = 3, length = 30;
    const Document doc = canvasWith(strokeLine({10, 10.5}, {40, 10.5}, w), 60, 30);
    REQUIRE(validateDocument(doc).empty());
    const RgbaImage img = renderDocument(doc).image;
    // Rows 9 to 11 lie within the stroke between the caps; the colour is the shape's.
    for (int y = 9; y <= 11; ++y)
        for (int x = 10; x < 40; ++x) REQUIRE(img.at(x, y)[3] == 1.0f);
    CHECK(img.at(25, 10)[2] == Approx(0.6).margin(1e-6));
    // Pixels whose centres lie farther than w/2 + 1 from the centreline stay empty.
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const double cx = x + 0.5, cy = y + 0.5;
            const double dx = std::max({10 - cx, cx - 40, 0.0}), dy = cy - 10.5;
            if (std::hypot(dx, dy) > w / 2 + 1) REQUIRE(img.at(x, y)[3] == 0.0f);
        }
    // The body and two half-disc caps.
    const double area = w * length + M_PI * w * w / 4;
    CHECK(std::fabs(coveredArea(img) - area) < 0.02 * area);
    // Half a pixel of the edge row: the rows beside the body are empty, the caps half covered.
    CHECK(img.at(25, 8)[3] == 0.0f);
    CHECK(img.at(41, 10)[3] > 0.2f);
    CHECK(img.at(41, 10)[3] < 0.8f);
}

TEST_CASE("a thin or diagonal stroke covers its area", "[render][flat][stroke]") {
    for (double w : {0.5, 1.5, 2.25, 8.0}) {
        INFO("width " << w);
        const Vec2 a{12.3, 20.7}, b{71.9, 55.2};
        const RgbaImage img = renderDocument(canvasWith(strokeLine(a, b, w), 90, 80)).image;
        const double area = w * norm(b - a) + M_PI * w * w / 4;
        CHECK(std::fabs(coveredArea(img) - area) < 0.02 * area);
        float most = 0;
        for (float v : img.pixels) most = std::max(most, v);
        if (w < 1) CHECK(most <= w * std::sqrt(2.0) + 1e-6);
    }
}

TEST_CASE("a closed stroke is a ring without caps or gap", "[render][flat][stroke]") {
    const Vec2 c{50, 49.5};
    const double r = 30, w = 4;
    const RgbaImage img = renderDocument(canvasWith(strokeCircle(c, r, w), 100, 100)).image;
    // Four cubics are within 3e-4 of the circle: the ring's area.
    const double area = 2 * M_PI * r * w;
    CHECK(std::fabs(coveredArea(img) - area) < 0.01 * area);
    CHECK(img.at(50, 50)[3] == 0.0f);  // nothing is filled
    CHECK(img.at(80, 49)[3] == 1.0f);  // on the ring where it closes
    // Where it closes looks like anywhere else: the pixels across the ring at its start (right)
    // and at its opposite side (left) are mirror images.
    for (int d = -4; d <= 4; ++d) {
        const float right = img.at(80 + d, 49)[3], left = img.at(19 - d, 49)[3];
        CHECK(right == Approx(left).margin(0.02));
    }
}

TEST_CASE("a stroke without antialiasing is opaque or empty", "[render][flat][stroke]") {
    RenderOptions o;
    o.antialias = false;
    const Document doc = canvasWith(strokeCircle({40, 40}, 25, 3.5), 80, 80);
    const RgbaImage img = renderDocument(doc, o).image;
    for (size_t k = 3; k < img.pixels.size(); k += 4)
        REQUIRE((img.pixels[k] == 0.0f || img.pixels[k] == 1.0f));
    const double area = 2 * M_PI * 25 * 3.5;
    CHECK(std::fabs(coveredArea(img) - area) < 0.04 * area);
}

TEST_CASE("a stroke's opacity and scale, and the samples it covers", "[render][flat][stroke]") {
    Document doc = makeFlatDocument();
    FlatShape line = strokeLine({20, 30}, {200, 30}, 6);
    line.alpha = 0.5;
    line.layer = 2;
    doc.shapes.push_back(line);
    FlatShape opaque = strokeLine({20, 150}, {200, 150}, 6);
    opaque.layer = 2;
    doc.shapes.push_back(opaque);
    REQUIRE(validateDocument(doc).empty());
    RenderOptions o;
    o.wantSamples = true;
    o.scale = 2;
    const RenderResult r = renderDocument(doc, o);
    const size_t w = static_cast<size_t>(r.image.width);
    // Half-opaque over the mesh: the mesh keeps its sample; the opaque stroke takes it away.
    CHECK(r.samples[60 * w + 80].mesh == 0);
    CHECK(r.image.at(80, 60)[2] != Approx(0.6).margin(1e-3));
    CHECK(r.samples[300 * w + 380].mesh == -1);
    CHECK(r.image.at(380, 300)[2] == Approx(0.6).margin(1e-6));
    // At scale 2 the stroke is 12 output pixels wide: rows 294 to 305 are inside.
    CHECK(r.samples[294 * w + 380].mesh == -1);
    CHECK(r.samples[305 * w + 380].mesh == -1);
    CHECK(r.samples[292 * w + 380].mesh != -1);
    CHECK(r.samples[307 * w + 380].mesh != -1);
}

TEST_CASE("a stroke's centreline counts and width are validated", "[validate][flat][stroke]") {
    Document doc = canvasWith(strokeLine({1, 2}, {30, 4}, 2), 40, 40);
    REQUIRE(validateDocument(doc).empty());
    doc.shapes[0].subpaths[0].pop_back();  // 3 points: a filled shape's count
    CHECK(validateDocument(doc).find("3n + 1") != std::string::npos);
    doc.shapes[0].subpaths[0] = {{1, 2}};  // n = 0
    CHECK(validateDocument(doc).find("3n + 1") != std::string::npos);
    doc = canvasWith(strokeLine({1, 2}, {30, 4}, 2), 40, 40);
    for (double width : {-1.0, double(NAN), 2e4, double(INFINITY)}) {
        doc.shapes[0].strokeWidth = width;
        CHECK(validateDocument(doc).find("stroke width") != std::string::npos);
    }
    // A filled shape keeps its own rule: 3n + 1 points are not a closed outline.
    doc = canvasWith(strokeLine({1, 2}, {30, 4}, 2), 40, 40);
    doc.shapes[0].strokeWidth = 0;
    CHECK(validateDocument(doc).find("multiple of 3") != std::string::npos);
}

namespace {

// A rectangle of 39 × 30 pixels, its left side halfway across pixel column 2, painted with a
// three-stop gradient along x whose axis ends inside it (both ends pad).
FlatShape gradedSquare() {
    FlatShape s;
    s.subpaths = {polygonAsCubics({{2.5, 2}, {41.5, 2}, {41.5, 32}, {2.5, 32}})};
    s.gradient.from = {12, 0};
    s.gradient.to = {32, 0};
    s.gradient.stops = {{0, {1, 0, 0}}, {0.25, {0, 1, 0}}, {1, {0, 0, 1}}};
    s.col = {0.3, 0.4, 0.3};
    return s;
}

}  // namespace

TEST_CASE("a graded shape paints its gradient's colour at each pixel centre",
          "[render][flat][gradient]") {
    const FlatShape s = gradedSquare();
    const LinearGradient& g = s.gradient;
    CHECK(g.colourAt({0, 0}) == Vec3{1, 0, 0});   // padded before the axis
    CHECK(g.colourAt({12, 5}) == Vec3{1, 0, 0});
    CHECK(g.colourAt({17, 9}) == Vec3{0, 1, 0});  // offset 0.25
    CHECK(g.colourAt({24.5, 0}).g == Approx(0.5));
    CHECK(g.colourAt({24.5, 0}).b == Approx(0.5));
    CHECK(g.colourAt({99, 0}) == Vec3{0, 0, 1});  // padded after
    const RenderResult r = renderDocument(canvasWith(s, 44, 34), RenderOptions{});
    for (int x = 3; x < 41; ++x)
        for (int y : {3, 17, 30}) {
            const Vec3 want = g.colourAt({x + 0.5, y + 0.5});
            const float* px = r.image.at(x, y);
            CHECK(px[0] == Approx(want.r).margin(1e-6));
            CHECK(px[1] == Approx(want.g).margin(1e-6));
            CHECK(px[2] == Approx(want.b).margin(1e-6));
            CHECK(px[3] == Approx(1));
        }
    // On the outline the gradient's colour at the pixel centre, with the coverage as alpha.
    const float* edge = r.image.at(2, 10);
    CHECK(edge[3] == Approx(0.5).margin(1e-3));
    CHECK(edge[0] == Approx(1).margin(1e-6));
    // At scale 2 the colour follows the canvas point of each output pixel.
    RenderOptions o;
    o.scale = 2;
    const RenderResult big = renderDocument(canvasWith(s, 44, 34), o);
    CHECK(big.image.at(49, 20)[1] == Approx(g.colourAt({24.75, 10.25}).g).margin(1e-6));
}

TEST_CASE("a gradient's stops, offsets and ends are validated", "[validate][flat][gradient]") {
    Document doc = canvasWith(gradedSquare(), 44, 34);
    REQUIRE(validateDocument(doc).empty());
    auto problem = [&](auto change) {
        Document d = doc;
        change(d.shapes[0].gradient);
        return validateDocument(d);
    };
    CHECK(problem([](LinearGradient& g) { g.stops.resize(1); }).find("stops") != std::string::npos);
    CHECK(problem([](LinearGradient& g) { g.stops.resize(17, g.stops.back()); })
              .find("stops") != std::string::npos);
    CHECK(problem([](LinearGradient& g) { g.stops[1].offset = 0; }).find("increase") !=
          std::string::npos);
    CHECK(problem([](LinearGradient& g) { g.stops.back().offset = 0.9; }).find("0 to 1") !=
          std::string::npos);
    CHECK(problem([](LinearGradient& g) { g.stops[2].col.b = 1.5; }).find("colour") !=
          std::string::npos);
    CHECK(problem([](LinearGradient& g) { g.stops[1].offset = NAN; }).find("increase") !=
          std::string::npos);
    CHECK(problem([](LinearGradient& g) { g.to = g.from; }).find("same point") != std::string::npos);
    CHECK(problem([](LinearGradient& g) { g.to.x = NAN; }).find("limit") != std::string::npos);
    CHECK(problem([](LinearGradient& g) { g.from.y = 1e8; }).find("limit") != std::string::npos);
    doc.shapes[0].strokeWidth = 2;
    doc.shapes[0].subpaths[0].push_back(doc.shapes[0].subpaths[0].front());
    CHECK(validateDocument(doc).find("stroke painted with a gradient") != std::string::npos);
}
