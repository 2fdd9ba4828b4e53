// Flat shapes in SVG: compact path data, read back by our reader, and drawn by Inkscape as our
// renderer draws them (anti-aliased borders included).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "formats/atomic_file.h"
#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "support/compare.h"
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

double largestPointDistance(const FlatShape& a, const FlatShape& b) {
    double worst = 0;
    for (size_t s = 0; s < a.subpaths.size(); ++s)
        for (size_t k = 0; k < a.subpaths[s].size(); ++k)
            worst = std::max(worst, norm(a.subpaths[s][k] - b.subpaths[s][k]));
    return worst;
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
        CHECK(largestPointDistance(doc.shapes[k], back.shapes[k]) <= 0.0051);
        for (int c = 0; c < 3; ++c)
            CHECK(std::fabs(back.shapes[k].col[c] - doc.shapes[k].col[c]) <= 0.5 / 255);
    }
    // Written again, the same shape paths.
    auto shapePaths = [](const std::string& text) {
        std::string paths;
        for (size_t at = text.find("<path fill="); at != std::string::npos;
             at = text.find("<path fill=", at + 1))
            paths += text.substr(at, text.find("/>", at) - at);
        return paths;
    };
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
    const std::string home = svgtest::tmpPath("inkscape-home-flat");
    std::remove(png.c_str());
    REQUIRE(gmtest::runCommand(
                "HOME=" + gmtest::quote(home) + " XDG_CONFIG_HOME=" + gmtest::quote(home) +
                " inkscape --export-type=png --export-background=white "
                "--export-background-opacity=1 --export-filename=" +
                gmtest::quote(png) + " " + gmtest::quote(svg) + " >/dev/null 2>&1") == 0);
    const RgbaImage theirs = readImage(png);
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
    std::remove(png2.c_str());
    REQUIRE(gmtest::runCommand(
                "HOME=" + gmtest::quote(home) + " XDG_CONFIG_HOME=" + gmtest::quote(home) +
                " inkscape --export-type=png --export-background=white "
                "--export-background-opacity=1 --export-filename=" +
                gmtest::quote(png2) + " " + gmtest::quote(svg2) + " >/dev/null 2>&1") == 0);
    const double eShapes = meanAbsAll(svgtest::renderOverWhite(shapesOnly), readImage(png2));
    std::printf("[svg figures] Inkscape flat shapes: E %.3f with meshes, %.3f shapes alone\n", e,
                eShapes);
    CHECK(eShapes <= 0.5);
    CHECK(e <= 1.0);  // the meshes' own difference, as in the mesh tests
}
