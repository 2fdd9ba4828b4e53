// Flat shapes in SVG, filled and stroked: compact path data, read back by our reader, and drawn by
// Inkscape as our renderer draws them (anti-aliased borders included).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "formats/atomic_file.h"
#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "support/compare.h"
#include "support/stroke_shapes.h"
#include "svg_test_support.h"

using namespace gm;

namespace {

// E: the mean absolute difference over every pixel and channel, 0–255 units (both opaque).
double meanAbsAll(const RgbaImage& a, const RgbaImage& b) {
    double sum = 0;
    for (size_t k = 0; k < a.pixels.size(); k += 4)
        for (int c = 0; c < 3; ++c) sum += std::fabs(a.pixels[k + c] - b.pixels[k + c]);
    return 255 * sum / (3.0 * double(a.pixels.size() / 4));
}

// The flat shapes' <path> elements of an SVG text (the meshes' outlines left out).
std::string shapePaths(const std::string& text) {
    std::string paths;
    for (size_t at = text.find("<path fill="); at != std::string::npos;
         at = text.find("<path fill=", at + 1))
        paths += text.substr(at, text.find("/>", at) - at);
    return paths;
}

// Inkscape's PNG of an SVG file, over white.
RgbaImage inkscapePng(const std::string& svg, const std::string& png) {
    const std::string home = svgtest::tmpPath("inkscape-home-flat");
    std::remove(png.c_str());
    REQUIRE(gmtest::runCommand(
                "HOME=" + gmtest::quote(home) + " XDG_CONFIG_HOME=" + gmtest::quote(home) +
                " inkscape --export-type=png --export-background=white "
                "--export-background-opacity=1 --export-filename=" +
                gmtest::quote(png) + " " + gmtest::quote(svg) + " >/dev/null 2>&1") == 0);
    return readImage(png);
}

// Whether our renderer paints stroked shapes (it paints nothing for them until it does).
bool rendererPaintsStrokes() {
    const Document doc = gmtest::strokeTestDocument();
    Document strokesOnly = doc;
    strokesOnly.shapes.erase(strokesOnly.shapes.begin());
    const RgbaImage img = renderDocument(strokesOnly).image;
    for (size_t k = 3; k < img.pixels.size(); k += 4)
        if (img.pixels[k] > 0) return true;
    return false;
}

// An SVG of one stroked path with the given attributes, at line 1.
std::string strokeSvg(const std::string& attributes) {
    return "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 50 40\"><path id=\"s1\" "
           "fill=\"none\" stroke=\"#000\" " +
           attributes + " d=\"M1 2L5 5l5 0\"/></svg>";
}

}  // namespace

TEST_CASE("flat shapes are compact paths between the meshes and read back", "[svg][flat]") {
    const Document doc = makeFlatDocument();
    WriteOptions options;
    options.svgScript = "none";
    const std::string svg = encodeSvg(doc, options);
    // One plain path per shape, relative commands, the square's lines as lines along the axes
    // (the last one z's).
    CHECK(svg.find("<path fill=\"#d91a26\" d=\"M") != std::string::npos);
    CHECK(svg.find("<path fill=\"#1a4de6\" d=\"M20.25 110.5h60v60h-60zm") != std::string::npos);
    // Paint order: ring after the first mesh's outline, before the second's.
    const size_t ring = svg.find("fill=\"#d91a26\""), square = svg.find("fill=\"#1a4de6\"");
    const size_t m0 = svg.find("url(#m0)"), m1 = svg.find("url(#m1)");
    CHECK(m0 < ring);
    CHECK(ring < m1);
    CHECK(m1 < square);

    const Document back = decodeSvg(svg, ReadLimits{});
    REQUIRE(back.meshes.size() == 2);
    REQUIRE(back.shapes.size() == 2);
    for (size_t k = 0; k < 2; ++k) {
        CHECK(back.shapes[k].layer == doc.shapes[k].layer);
        REQUIRE(back.shapes[k].subpaths.size() == doc.shapes[k].subpaths.size());
        for (size_t s = 0; s < doc.shapes[k].subpaths.size(); ++s)
            REQUIRE(back.shapes[k].subpaths[s].size() == doc.shapes[k].subpaths[s].size());
        CHECK(svgtest::largestPointDistance(doc.shapes[k], back.shapes[k]) <= 0.0051);
        for (int c = 0; c < 3; ++c)
            CHECK(std::fabs(back.shapes[k].col[c] - doc.shapes[k].col[c]) <= 0.5 / 255);
    }
    // Written again, the same shape paths.
    CHECK(shapePaths(encodeSvg(back, options)) == shapePaths(svg));
}

TEST_CASE("an SVG's flat shapes are counted against ReadLimits::maxShapes", "[svg][flat]") {
    // The same limits let the document through the .gmb reader as well: more shapes than
    // meshes is no reason to refuse it.
    Document doc = makeFlatDocument();
    for (int k = 0; k < 3; ++k) doc.shapes.push_back(doc.shapes.back());
    const std::string svg = encodeSvg(doc, WriteOptions{});
    ReadLimits limits;
    limits.maxMeshes = 2;
    CHECK(decodeSvg(svg, limits, "t.svg").shapes.size() == 5);
    limits.maxShapes = 4;
    try {
        decodeSvg(svg, limits, "t.svg");
        FAIL("five shapes read under a limit of four");
    } catch (const Error& e) {
        CHECK_THAT(e.what(), Catch::Contains("5 flat shapes, over the limit of 4"));
    }
}

TEST_CASE("the SVG path reader takes absolute, relative, H/V and implicit commands",
          "[svg][flat]") {
    const std::string svg =
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 50 40\">"
        "<g transform=\"translate(5 0)\"><path style=\"fill:#ff0000\" "
        "d=\"M0 0H20V20h-20z m5 5 10 0 0 10-10 0z\"/></g>"
        "<path fill=\"#00f\" fill-opacity=\".5\" d=\"M30,30 C30,35 35,35 35,30\"/></svg>";
    const Document doc = decodeSvg(svg, ReadLimits{});
    REQUIRE(doc.shapes.size() == 2);
    CHECK(doc.meshes.empty());
    REQUIRE(doc.shapes[0].subpaths.size() == 2);
    CHECK(doc.shapes[0].subpaths[0].size() == 12);
    CHECK(doc.shapes[0].subpaths[0][3].x == Approx(25));  // translated
    CHECK(doc.shapes[0].subpaths[1][0].x == Approx(10));
    CHECK(doc.shapes[0].subpaths[1][0].y == Approx(5));
    CHECK(doc.shapes[1].alpha == Approx(0.5));
    CHECK(doc.shapes[1].col.b == 1.0);
    CHECK(doc.shapes[1].subpaths[0].size() == 6);  // the curve and the closing line

    for (const char* bad : {"M0 0 Q1 1 2 2z", "M0 0 L1", "5 5", "M0 0 L1e99 0"}) {
        const std::string text =
            "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 9 9\">"
            "<path fill=\"#000000\" d=\"" +
            std::string(bad) + "\"/></svg>";
        CHECK_THROWS_AS(decodeSvg(text, ReadLimits{}), Error);
    }
}

TEST_CASE("Inkscape draws flat shapes like our renderer", "[svg][flat][external]") {
    const Document doc = makeFlatDocument();
    const std::string svg = svgtest::tmpPath("flat_shapes.svg");
    const std::string png = svgtest::tmpPath("flat_shapes_inkscape.png");
    WriteOptions exact;
    exact.svgColors = "exact";
    writeFileAtomically(svg, encodeSvg(doc, exact));
    const RgbaImage theirs = inkscapePng(svg, png);
    REQUIRE(theirs.width == doc.width);
    REQUIRE(theirs.height == doc.height);
    const RgbaImage ours = svgtest::renderOverWhite(doc);
    writeImage(ours, svgtest::tmpPath("flat_shapes_ours.png"));
    const double e = meanAbsAll(ours, theirs);
    // The shapes alone, over white: their borders and holes, without the meshes' differences.
    Document shapesOnly = doc;
    shapesOnly.meshes.clear();
    for (FlatShape& s : shapesOnly.shapes) s.layer = 0;
    const std::string svg2 = svgtest::tmpPath("flat_shapes_only.svg");
    const std::string png2 = svgtest::tmpPath("flat_shapes_only_inkscape.png");
    writeFileAtomically(svg2, encodeSvg(shapesOnly, exact));
    const double eShapes =
        meanAbsAll(svgtest::renderOverWhite(shapesOnly), inkscapePng(svg2, png2));
    std::printf("[svg figures] Inkscape flat shapes: E %.3f with meshes, %.3f shapes alone\n", e,
                eShapes);
    CHECK(eShapes <= 0.5);
    CHECK(e <= 1.0);  // the meshes' own difference, as in the mesh tests
}

TEST_CASE("stroked shapes are round-capped paths between the meshes and read back",
          "[svg][flat][stroke]") {
    // The flat document with strokes: one after the ring (layer 1), the others on top.
    Document doc = makeFlatDocument();
    std::vector<FlatShape> strokes = gmtest::strokeTestShapes();
    strokes.erase(strokes.begin());  // the filled square
    strokes[0].layer = 1;
    doc.shapes.insert(doc.shapes.begin() + 1, strokes[0]);
    for (size_t k = 1; k < strokes.size(); ++k) {
        strokes[k].layer = 2;
        doc.shapes.push_back(strokes[k]);
    }
    doc.shapes.back().strokeWidth = 1.234;  // written to 1/100 px
    WriteOptions options;
    options.svgScript = "none";
    const std::string svg = encodeSvg(doc, options);
    // Open lines without z, closed ones with it; translucent as stroke-opacity.
    CHECK(svg.find("<path fill=\"none\" stroke=\"#b31a1a\" stroke-width=\"3\" "
                   "stroke-linecap=\"round\" stroke-linejoin=\"round\" "
                   "d=\"M15 20l30 30 30-30 30 30\"/>") != std::string::npos);
    CHECK(svg.find("<path fill=\"none\" stroke=\"#803399\" stroke-opacity=\"0.6\" "
                   "stroke-width=\"4\" stroke-linecap=\"round\" stroke-linejoin=\"round\" "
                   "d=\"M30 70l40 5-25 20zm130 45l25 15\"/>") != std::string::npos);
    CHECK(svg.find("stroke-width=\"5.5\"") != std::string::npos);
    CHECK(svg.find("stroke-width=\"2.25\"") != std::string::npos);
    CHECK(svg.find("stroke-width=\"1.23\"") != std::string::npos);
    // A file of shapes alone is SVG 1.1 with no mesh in it.
    Document strokesOnly = gmtest::strokeTestDocument();
    CHECK(encodeSvg(strokesOnly, options).find("mesh") == std::string::npos);
    // Paint order: the first stroke after the ring, before the second mesh's outline.
    CHECK(svg.find("fill=\"#d91a26\"") < svg.find("stroke=\"#b31a1a\""));
    CHECK(svg.find("stroke=\"#b31a1a\"") < svg.find("url(#m1)"));

    const Document back = decodeSvg(svg, ReadLimits{});
    REQUIRE(back.meshes.size() == 2);
    REQUIRE(back.shapes.size() == doc.shapes.size());
    for (size_t k = 0; k < doc.shapes.size(); ++k) {
        const FlatShape &a = doc.shapes[k], &b = back.shapes[k];
        INFO("shape " << k);
        CHECK(b.layer == a.layer);
        CHECK(b.stroked() == a.stroked());
        CHECK(std::fabs(b.strokeWidth - a.strokeWidth) <= 0.005);
        CHECK(std::fabs(b.alpha - a.alpha) <= 5e-5);
        for (int c = 0; c < 3; ++c) CHECK(std::fabs(b.col[c] - a.col[c]) <= 0.5 / 255);
        REQUIRE(b.subpaths.size() == a.subpaths.size());
        for (size_t s = 0; s < a.subpaths.size(); ++s) {
            REQUIRE(b.subpaths[s].size() == a.subpaths[s].size());
            if (a.stroked())  // closed stays closed (exactly), open stays open
                CHECK((b.subpaths[s].back() == b.subpaths[s].front()) ==
                      (a.subpaths[s].back() == a.subpaths[s].front()));
        }
        CHECK(svgtest::largestPointDistance(a, b) <= 0.0051);
    }
    // Written again, the same shape paths.
    CHECK(shapePaths(encodeSvg(back, options)) == shapePaths(svg));
}

TEST_CASE("the SVG reader takes strokes as FlatShape holds them", "[svg][flat][stroke]") {
    const std::string round = "stroke-linecap=\"round\" stroke-linejoin=\"round\" ";
    // Absolute, relative and implicit commands; z closes exactly, also after relative steps;
    // a path without z is open.
    const std::string svg =
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 50 40\">"
        "<path style=\"fill:none;stroke:#00f;stroke-width:2px;stroke-linecap:round;"
        "stroke-linejoin:round;stroke-opacity:.5\" d=\"M.1 .2l.3 .1-.4-.3z M10 10 20 10 20 20\"/>"
        "<path fill=\"#f00\" stroke=\"#0f0\" stroke-dasharray=\"none\" " +
        round +
        "d=\"M5 5h10v10z\"/>"
        "<g transform=\"translate(5 5) rotate(30) scale(2)\"><path fill=\"none\" stroke=\"#000\" " +
        round +
        "stroke-width=\"1.5\" d=\"M0 0c1 1 2 1 3 0\"/></g>"
        "<path fill=\"none\" stroke=\"#000\" " +
        round + "d=\"M7 7h0\"/></svg>";
    const Document doc = decodeSvg(svg, ReadLimits{});
    REQUIRE(doc.shapes.size() == 5);
    const FlatShape& a = doc.shapes[0];
    CHECK(a.strokeWidth == 2);
    CHECK(a.alpha == Approx(0.5));
    CHECK(a.col.b == 1.0);
    REQUIRE(a.subpaths.size() == 2);
    REQUIRE(a.subpaths[0].size() == 10);  // two lines and the closing one
    CHECK(a.subpaths[0].back() == a.subpaths[0].front());
    REQUIRE(a.subpaths[1].size() == 7);
    CHECK(a.subpaths[1].back().y == Approx(20));
    // A path both filled and stroked: the fill, then the stroke (default width 1), closed.
    CHECK_FALSE(doc.shapes[1].stroked());
    CHECK(doc.shapes[2].strokeWidth == 1);
    CHECK(doc.shapes[2].col.g == 1.0);
    REQUIRE(doc.shapes[2].subpaths[0].size() == 10);
    CHECK(doc.shapes[2].subpaths[0].back() == doc.shapes[2].subpaths[0].front());
    // A rotation and a uniform scale: the width scales too.
    CHECK(doc.shapes[3].strokeWidth == Approx(3));
    CHECK(doc.shapes[3].subpaths[0].back().x == Approx(5 + 6 * std::cos(M_PI / 6)));
    // A dot: a line of length 0, which round caps paint.
    REQUIRE(doc.shapes[4].subpaths[0].size() == 4);
    // Written back, the dot stays a line of length 0 (a lone moveto would paint nothing).
    Document dot;
    dot.width = dot.height = 20;
    dot.shapes = {doc.shapes[4]};
    CHECK(encodeSvg(dot, WriteOptions{}).find("d=\"M7 7h0\"") != std::string::npos);
}

TEST_CASE("the SVG reader refuses strokes that FlatShape cannot hold", "[svg][flat][stroke]") {
    const std::string round = "stroke-linecap=\"round\" stroke-linejoin=\"round\" ";
    const std::pair<std::string, std::string> cases[] = {
        {"stroke-linejoin=\"round\"", "stroke-linecap 'butt' is not supported"},
        {"stroke-linecap=\"square\" stroke-linejoin=\"round\"", "stroke-linecap 'square'"},
        {"stroke-linecap=\"round\"", "stroke-linejoin 'miter' is not supported"},
        {"style=\"stroke-linecap:round;stroke-linejoin:bevel\"", "stroke-linejoin 'bevel'"},
        {round + "stroke-dasharray=\"4 2\"", "dashed strokes are not supported"},
        {round + "style=\"stroke-dasharray:4,2\"", "dashed strokes are not supported"},
        {round + "stroke-width=\"0\"", "stroke-width '0' is not a positive number"},
        {round + "stroke-width=\"-2\"", "stroke-width '-2'"},
        {round + "stroke-width=\"1e5\"", "stroke-width '1e5'"},
        {round + "stroke-width=\"nan\"", "stroke-width 'nan'"},
        {round + "stroke-width=\"inf\"", "stroke-width 'inf'"},
        {round + "stroke-width=\"2em\"", "stroke-width '2em'"},
        {round + "stroke-width=\"5000\" transform=\"scale(3)\"", "stroke-width out of range"},
        {round + "transform=\"scale(2 1)\"", "scales unevenly"},
        {round + "stroke-opacity=\"2\"", "stroke-opacity is not a number in 0-1"},
    };
    for (const auto& [attributes, message] : cases) {
        INFO(attributes);
        try {
            decodeSvg(strokeSvg(attributes), ReadLimits{}, "s.svg");
            FAIL("read");
        } catch (const Error& e) {
            CHECK_THAT(e.what(), Catch::Contains(message));
            CHECK_THAT(e.what(), Catch::Contains("<path id=\"s1\"> at line 1"));
        }
    }
    CHECK(decodeSvg(strokeSvg(round), ReadLimits{}).shapes.size() == 1);
}

TEST_CASE("Inkscape draws stroked shapes like our renderer", "[svg][flat][stroke][external]") {
    if (!rendererPaintsStrokes()) FAIL("our renderer paints no strokes");
    const Document doc = gmtest::strokeTestDocument();
    const std::string svg = svgtest::tmpPath("strokes.svg");
    writeFileAtomically(svg, encodeSvg(doc, WriteOptions{}));
    const RgbaImage theirs = inkscapePng(svg, svgtest::tmpPath("strokes_inkscape.png"));
    REQUIRE(theirs.width == doc.width);
    REQUIRE(theirs.height == doc.height);
    const RgbaImage ours = svgtest::renderOverWhite(doc);
    writeImage(ours, svgtest::tmpPath("strokes_ours.png"));
    const double e = meanAbsAll(ours, theirs);
    std::printf("[svg figures] Inkscape strokes: E %.3f\n", e);
    CHECK(e <= 0.5);
}

TEST_CASE("a filled path of no segment paints nothing and is no shape", "[svg][flat]") {
    // "M x y z" encloses nothing: read as a shape, it would have no outline and fail the
    // document's validation.
    const std::string svg =
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 50 40\">"
        "<path fill=\"#f00\" d=\"M10 10z\"/>"
        "<linearGradient id=\"g\" x1=\"0\" x2=\"1\"><stop offset=\"0\" stop-color=\"#000\"/>"
        "<stop offset=\"1\" stop-color=\"#fff\"/></linearGradient>"
        "<path fill=\"url(#g)\" d=\"M20 20z M30 30\"/>"
        "<path fill=\"#00f\" d=\"M5 5h10v10z\"/></svg>";
    const Document doc = decodeSvg(svg, ReadLimits{});
    REQUIRE(doc.shapes.size() == 1);
    CHECK(doc.shapes[0].col.b == 1.0);
}
