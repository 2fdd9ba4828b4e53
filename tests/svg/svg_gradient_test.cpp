// Flat shapes painted with linear gradients in SVG: <linearGradient> elements before their
// paths, read back, what users' editors write (Inkscape's href chains, style stops,
// percentages, transforms) read as the model holds it or refused by name, and Inkscape and
// librsvg drawing them as our renderer does.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <regex>
#include <set>
#include <string>

#include "formats/atomic_file.h"
#include "formats/input_file.h"
#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "meshcore/synthetic_meshes.h"
#include "support/compare.h"
#include "support/gradient_shapes.h"
#include "svg_test_support.h"

using namespace gm;

namespace {

const std::string kSvgOpen =
    "<svg xmlns=\"http://www.w3.org/2000/svg\" "
    "xmlns:xlink=\"http://www.w3.org/1999/xlink\" viewBox=\"0 0 200 100\">";

// An SVG of `defs` (gradients) and one path filled by url(#g) with the given attributes, the
// path's id "p" and the gradient's "g" for messages.
std::string filledSvg(const std::string& defs,
                      const std::string& pathAttributes = "fill=\"url(#g)\"",
                      const std::string& d = "M10 10h80v40h-80z") {
    return kSvgOpen + defs + "<path id=\"p\" " + pathAttributes + " d=\"" + d + "\"/></svg>";
}

FlatShape onlyShape(const Document& doc) {
    REQUIRE(doc.shapes.size() == 1);
    return doc.shapes[0];
}

// The colour SVG paints at the canvas point q for the axis a→b of the gradient's own space
// mapped to the canvas by `m` (x' = m0 x + m2 y + m4, y' = m1 x + m3 y + m5), with pad.
Vec3 svgColourAt(Vec2 q, Vec2 a, Vec2 b, const double (&m)[6], const LinearGradient& stops) {
    const double det = m[0] * m[3] - m[1] * m[2];
    const Vec2 r = q - Vec2{m[4], m[5]};
    const Vec2 p{(m[3] * r.x - m[2] * r.y) / det, (-m[1] * r.x + m[0] * r.y) / det};
    LinearGradient inGradientSpace = stops;
    inGradientSpace.from = a;
    inGradientSpace.to = b;
    return inGradientSpace.colourAt(p);
}

void checkColour(Vec3 got, Vec3 want, double tolerance) {
    for (int c = 0; c < 3; ++c) CHECK(std::fabs(got[c] - want[c]) <= tolerance);
}

void checkRefused(const std::string& svg, const std::string& message, const std::string& where) {
    INFO(svg);
    try {
        decodeSvg(svg, ReadLimits{}, "g.svg");
        FAIL("read");
    } catch (const Error& e) {
        CHECK_THAT(e.what(), Catch::Contains(message));
        CHECK_THAT(e.what(), Catch::Contains(where));
    }
}

// The gradients and flat shape paths of an SVG text (the meshes and their outlines left out).
std::string gradientsAndPaths(const std::string& text) {
    std::string out;
    const std::regex element("<linearGradient[^]*?</linearGradient>|<path fill=[^>]*/>");
    for (std::sregex_iterator it(text.begin(), text.end(), element), end; it != end; ++it)
        out += it->str() + "\n";
    return out;
}

// Each shape of `back` against the document's: layer, opacity, outline at 1/100 px, gradient
// ends at 1e-4 px, offsets at 1e-4, colours at 8 bits.
void checkShapesRead(const Document& doc, const Document& back) {
    REQUIRE(back.shapes.size() == doc.shapes.size());
    for (size_t k = 0; k < doc.shapes.size(); ++k) {
        const FlatShape &a = doc.shapes[k], &b = back.shapes[k];
        INFO("shape " << k);
        CHECK(b.layer == a.layer);
        CHECK(std::fabs(b.alpha - a.alpha) <= 5e-5);
        REQUIRE(b.subpaths.size() == a.subpaths.size());
        for (size_t s = 0; s < a.subpaths.size(); ++s)
            REQUIRE(b.subpaths[s].size() == a.subpaths[s].size());
        CHECK(svgtest::largestPointDistance(a, b) <= 0.0051);
        checkColour(b.col, a.col, 1.0 / 255);
        REQUIRE(b.graded() == a.graded());
        if (!a.graded()) continue;
        CHECK(norm(b.gradient.from - a.gradient.from) <= 1e-4);
        CHECK(norm(b.gradient.to - a.gradient.to) <= 1e-4);
        REQUIRE(b.gradient.stops.size() == a.gradient.stops.size());
        for (size_t s = 0; s < a.gradient.stops.size(); ++s) {
            CHECK(std::fabs(b.gradient.stops[s].offset - a.gradient.stops[s].offset) <= 5e-5);
            checkColour(b.gradient.stops[s].col, a.gradient.stops[s].col, 0.5 / 255);
        }
    }
}

// The graded test document with a mesh over part of it and the shapes after the backdrop
// painted above the mesh: every SVG flavour then has meshes, and the browsers' script runs.
Document gradedDocumentWithMesh() {
    Document doc = gmtest::gradientTestDocument();
    doc.meshes.push_back(makeCurvedMesh(2, 2, 130, 92, 62, 44, 0.5, 3));
    for (size_t k = 1; k < doc.shapes.size(); ++k) doc.shapes[k].layer = 1;
    return doc;
}

}  // namespace

TEST_CASE("graded shapes are linearGradients before their paths and read back",
          "[svg][flat][gradient]") {
    const Document doc = gmtest::gradientTestDocument();
    WriteOptions options;
    options.svgScript = "none";
    const std::string svg = encodeSvg(doc, options);
    // The first graded square: its gradient right before it, in user space, offsets 0 and 1.
    const std::regex square(
        "<linearGradient id=\"(g[0-9a-f]{10})\" gradientUnits=\"userSpaceOnUse\" x1=\"10\" "
        "y1=\"40\" x2=\"80\" y2=\"40\"><stop offset=\"0\" stop-color=\"#e61a1a\"/><stop "
        "offset=\"1\" stop-color=\"#1a33e6\"/></linearGradient>\n<path fill=\"url\\(#\\1\\)\" "
        "d=\"M10 10h70v60h-70z\"/>");
    CHECK(std::regex_search(svg, square));
    CHECK(svg.find("offset=\"0.4\"") != std::string::npos);
    CHECK(svg.find("fill-opacity=\"0.6\"") != std::string::npos);
    CHECK(svg.find("<defs") == std::string::npos);  // no meshes: plain SVG 1.1
    // Four gradients of four ids, each written before the path it fills.
    std::set<std::string> ids;
    const std::regex fill("fill=\"url\\(#(g[0-9a-f]{10})\\)\"");
    for (std::sregex_iterator it(svg.begin(), svg.end(), fill), end; it != end; ++it) {
        const std::string id = (*it)[1];
        CHECK(svg.find("id=\"" + id + "\"") < static_cast<size_t>(it->position()));
        ids.insert(id);
    }
    CHECK(ids.size() == 4);

    const Document back = decodeSvg(svg, ReadLimits{});
    CHECK(back.width == doc.width);
    CHECK(back.height == doc.height);
    checkShapesRead(doc, back);
    CHECK(encodeSvg(back, options) == svg);  // written again, the same text
}

TEST_CASE("graded shapes are the same in every SVG flavour", "[svg][flat][gradient]") {
    const Document doc = gradedDocumentWithMesh();
    WriteOptions plain;
    const std::string reference = gradientsAndPaths(encodeSvg(doc, plain));
    REQUIRE(reference.find("<linearGradient") != std::string::npos);
    const SvgFallbackImage image{"png", "not read"};
    for (int flavour = 0; flavour < 5; ++flavour) {
        WriteOptions o;
        const SvgFallbackImage* fallback = nullptr;
        if (flavour == 1) o.svgColors = "exact";
        if (flavour == 2) o.svgColors = "editable";
        if (flavour == 3) o.legacy = true;
        if (flavour == 4) o.svgFallback = "png", fallback = &image;
        INFO("flavour " << flavour);
        const std::string svg = encodeSvg(doc, o, nullptr, fallback);
        CHECK(gradientsAndPaths(svg) == reference);
        // The mesh is painted between the backdrop and the graded shapes.
        CHECK(svg.find("url(#m0)") < svg.find("<linearGradient"));
        CHECK(svg.find("<script") < svg.find("</svg>"));
        const Document back = decodeSvg(svg, ReadLimits{});
        REQUIRE(back.meshes.size() == 1);
        checkShapesRead(doc, back);
    }
}

TEST_CASE("one gradient element per distinct gradient, its id a hash of it",
          "[svg][flat][gradient]") {
    Document doc = gmtest::gradientTestDocument();
    doc.shapes.push_back(doc.shapes[1]);  // the square's gradient again, on another path
    doc.shapes.back().subpaths = {polygonAsCubics({{150, 100}, {190, 100}, {190, 130}})};
    const std::string svg = encodeSvg(doc, WriteOptions{});
    size_t elements = 0;
    for (size_t at = svg.find("<linearGradient"); at != std::string::npos;
         at = svg.find("<linearGradient", at + 1))
        ++elements;
    CHECK(elements == 4);
    checkShapesRead(doc, decodeSvg(svg, ReadLimits{}));
    // The same gradient has the same id in another document; another gradient another id.
    Document other;
    other.width = other.height = 50;
    other.shapes = {doc.shapes[1]};
    const std::string one = encodeSvg(other, WriteOptions{});
    const std::string id = one.substr(one.find("id=\"g") + 4, 11);
    CHECK(svg.find("id=\"" + id + "\"") != std::string::npos);
    std::swap(other.shapes[0].gradient.from, other.shapes[0].gradient.to);
    CHECK(encodeSvg(other, WriteOptions{}).find(id) == std::string::npos);
}

TEST_CASE("gradient offsets keep increasing as written", "[svg][flat][gradient]") {
    Document doc;
    doc.width = doc.height = 40;
    doc.shapes = {gmtest::gradedShape({polygonAsCubics({{0, 0}, {40, 0}, {40, 40}})},
                                      gmtest::linearGradient({0, 0}, {40, 0},
                                                             {{0, {1, 0, 0}},
                                                              {1.0 / 3, {0, 1, 0}},
                                                              {0.50001, {0, 0, 1}},
                                                              {0.500012, {1, 1, 0}},
                                                              {1, {0, 0, 0}}}))};
    const std::string svg = encodeSvg(doc, WriteOptions{});
    // Six decimals for all: the fewest that keep 0.50001 and 0.500012 apart.
    CHECK(svg.find("offset=\"0.333333\"") != std::string::npos);
    CHECK(svg.find("offset=\"0.50001\"") != std::string::npos);
    CHECK(svg.find("offset=\"0.500012\"") != std::string::npos);
    const FlatShape back = onlyShape(decodeSvg(svg, ReadLimits{}));
    REQUIRE(back.gradient.stops.size() == 5);
    CHECK(back.gradient.stops[3].offset == 0.500012);
}

TEST_CASE("the SVG reader follows Inkscape's href chains and takes style stops",
          "[svg][flat][gradient]") {
    // As Inkscape saves a gradient it edited: the stops on one element (style stops, an id
    // each), the axis, units and transform on another that links to it; the fill in style.
    const std::string svg = filledSvg(
        "<defs><linearGradient id=\"vector\"><stop style=\"stop-color:#ff0000;stop-opacity:1\" "
        "offset=\"0\" id=\"s1\"/><stop style=\"stop-color:#0000ff;stop-opacity:1\" offset=\"1\" "
        "id=\"s2\"/></linearGradient><linearGradient xlink:href=\"#vector\" id=\"g\" "
        "gradientUnits=\"userSpaceOnUse\" x1=\"10\" y1=\"30\" x2=\"90\" y2=\"30\" "
        "gradientTransform=\"matrix(0.8,0.6,-0.6,0.8,20,-10)\"/></defs>",
        "fill=\"#00ff00\" style=\"fill:url(#g);fill-opacity:.5\"");
    const FlatShape s = onlyShape(decodeSvg(svg, ReadLimits{}));
    REQUIRE(s.graded());
    CHECK(s.alpha == Approx(0.5));
    // A rotation with a translation: the axis's ends are mapped as points.
    CHECK(s.gradient.from.x == Approx(0.8 * 10 - 0.6 * 30 + 20));
    CHECK(s.gradient.from.y == Approx(0.6 * 10 + 0.8 * 30 - 10));
    CHECK(s.gradient.to.x == Approx(0.8 * 90 - 0.6 * 30 + 20));
    CHECK(s.gradient.to.y == Approx(0.6 * 90 + 0.8 * 30 - 10));
    REQUIRE(s.gradient.stops.size() == 2);
    checkColour(s.gradient.stops[0].col, {1, 0, 0}, 0);
    checkColour(s.gradient.stops[1].col, {0, 0, 1}, 0);
    checkColour(s.col, {0.5, 0, 0.5}, 1e-12);  // the mean colour

    // SVG 2's href, a three-link chain: attributes from the nearest element that has them.
    const std::string chained = filledSvg(
        "<linearGradient id=\"a\" x1=\"0\" x2=\"50\" gradientUnits=\"userSpaceOnUse\">"
        "<stop offset=\"0\" stop-color=\"#000\"/><stop offset=\"1\" stop-color=\"#fff\"/>"
        "</linearGradient><linearGradient id=\"b\" href=\"#a\" x2=\"100\"/>"
        "<linearGradient id=\"g\" href=\"#b\" x1=\"20\"/>");
    const FlatShape c = onlyShape(decodeSvg(chained, ReadLimits{}));
    CHECK(c.gradient.from.x == 20);
    CHECK(c.gradient.to.x == 100);
    CHECK(c.gradient.from.y == 0);
    CHECK(c.gradient.to.y == 0);
}

TEST_CASE("the SVG reader normalises stops as SVG draws them", "[svg][flat][gradient]") {
    const std::string units = "gradientUnits=\"userSpaceOnUse\" x1=\"0\" x2=\"100\"";
    auto stopsOf = [&](const std::string& stops) {
        return onlyShape(decodeSvg(
            filledSvg("<linearGradient id=\"g\" " + units + ">" + stops + "</linearGradient>"),
            ReadLimits{}));
    };
    // Percentages; stops at 0 and 1 added with the end colours; rgb() and named colours.
    const FlatShape a = stopsOf(
        "<stop offset=\"20%\" stop-color=\"rgb(255,0,0)\"/><stop offset=\".8\" "
        "stop-color=\"blue\"/>");
    REQUIRE(a.gradient.stops.size() == 4);
    CHECK(a.gradient.stops[0].offset == 0);
    CHECK(a.gradient.stops[1].offset == Approx(0.2));
    CHECK(a.gradient.stops[2].offset == Approx(0.8));
    CHECK(a.gradient.stops[3].offset == 1);
    checkColour(a.gradient.stops[0].col, {1, 0, 0}, 0);
    checkColour(a.gradient.stops[3].col, {0, 0, 1}, 0);
    checkColour(a.col, {0.5, 0, 0.5}, 1e-12);
    // Offsets out of order or range are clamped; a hard step (equal offsets) becomes a ramp of
    // 1e-6; of three stops at one offset the middle one is never seen and is dropped.
    const FlatShape b = stopsOf(
        "<stop offset=\"-1\" stop-color=\"#f00\"/><stop offset=\"0.5\" stop-color=\"#f00\"/>"
        "<stop offset=\"0.4\" stop-color=\"#0f0\"/><stop offset=\"0.5\" stop-color=\"#00f\"/>"
        "<stop offset=\"0.5\" stop-color=\"#fff\"/><stop offset=\"2\" stop-color=\"#000\"/>");
    REQUIRE(b.gradient.stops.size() == 4);
    CHECK(b.gradient.stops[1].offset == 0.5);
    CHECK(b.gradient.stops[2].offset == Approx(0.5 + 1e-6).margin(1e-12));
    checkColour(b.gradient.stops[2].col, {1, 1, 1}, 0);
    checkColour(b.gradient.colourAt({49.9, 0}), {1, 0, 0}, 0);
    checkColour(b.gradient.colourAt({50.0001, 0}), {1, 1, 1}, 1e-6);
    // One stop: a flat colour. A uniform stop-opacity multiplies the shape's opacity.
    const FlatShape c =
        stopsOf("<stop offset=\"0.3\" style=\"stop-color:#336699;stop-opacity:0.5\"/>");
    CHECK_FALSE(c.graded());
    checkColour(c.col, {0.2, 0.4, 0.6}, 1e-12);
    CHECK(c.alpha == Approx(0.5));
    // No stops: painted as none, so no fill; the path's stroke is still read.
    const Document none =
        decodeSvg(filledSvg("<linearGradient id=\"g\"/>",
                            "fill=\"url(#g)\" stroke=\"#000\" stroke-linecap=\"round\" "
                            "stroke-linejoin=\"round\""),
                  ReadLimits{});
    CHECK(onlyShape(none).stroked());
    // An axis of no length: the last stop's colour.
    const FlatShape d = onlyShape(decodeSvg(
        filledSvg("<linearGradient id=\"g\" x1=\"0.5\" x2=\"0.5\"><stop stop-color=\"#f00\"/>"
                  "<stop offset=\"1\" stop-color=\"#0f0\"/></linearGradient>"),
        ReadLimits{}));
    CHECK_FALSE(d.graded());
    checkColour(d.col, {0, 1, 0}, 0);
}

TEST_CASE("the SVG reader maps gradient axes exactly through any affine transform",
          "[svg][flat][gradient]") {
    const std::string stops =
        "<stop offset=\"0\" stop-color=\"#000\"/><stop offset=\"1\" stop-color=\"#fff\"/>";
    LinearGradient ramp;
    ramp.stops = {{0, {0, 0, 0}}, {1, {1, 1, 1}}};
    // Bounding-box units (the default, with its default axis 0% -> 100%) on a 80 x 40 box, a
    // skew, a non-uniform scale of the path: lines of one colour turn against the axis, and
    // the model's gradient must give SVG's colour everywhere.
    struct Case {
        std::string gradient, path;
        Vec2 a, b;
        double m[6];  // gradient space to canvas
    };
    const Case cases[] = {
        {"<linearGradient id=\"g\">" + stops + "</linearGradient>",
         "fill=\"url(#g)\"",
         {0, 0},
         {1, 0},
         {80, 0, 0, 40, 10, 10}},
        {"<linearGradient id=\"g\" x2=\"1\" y2=\"1\">" + stops + "</linearGradient>",
         "fill=\"url(#g)\"",
         {0, 0},
         {1, 1},
         {80, 0, 0, 40, 10, 10}},
        {"<linearGradient id=\"g\" gradientUnits=\"userSpaceOnUse\" x1=\"20\" y1=\"20\" "
         "x2=\"60\" y2=\"30\" gradientTransform=\"skewX(30)\">" +
             stops + "</linearGradient>",
         "fill=\"url(#g)\"",
         {20, 20},
         {60, 30},
         {1, 0, std::tan(M_PI / 6), 1, 0, 0}},
        {"<linearGradient id=\"g\" gradientUnits=\"userSpaceOnUse\" x1=\"20\" y1=\"20\" "
         "x2=\"60\" y2=\"30\">" +
             stops + "</linearGradient>",
         "fill=\"url(#g)\" transform=\"translate(5 -3) scale(1.5 0.5)\"",
         {20, 20},
         {60, 30},
         {1.5, 0, 0, 0.5, 5, -3}},
        {"<linearGradient id=\"g\" gradientUnits=\"userSpaceOnUse\" x1=\"10%\" y1=\"0\" "
         "x2=\"50%\" y2=\"50%\">" +
             stops + "</linearGradient>",
         "fill=\"url(#g)\"",
         {20, 0},
         {100, 50},
         {1, 0, 0, 1, 0, 0}},
    };
    for (const Case& c : cases) {
        INFO(c.gradient << " " << c.path);
        const FlatShape s = onlyShape(decodeSvg(filledSvg(c.gradient, c.path), ReadLimits{}));
        REQUIRE(s.graded());
        for (double x = 0; x <= 200; x += 10)
            for (double y = 0; y <= 100; y += 10)
                checkColour(s.gradient.colourAt({x, y}), svgColourAt({x, y}, c.a, c.b, c.m, ramp),
                            1e-9);
    }
    // The fill of a path under a transform is read with the path; its curves' box, not their
    // handles', is the bounding box.
    const FlatShape curved =
        onlyShape(decodeSvg(filledSvg("<linearGradient id=\"g\">" + stops + "</linearGradient>",
                                      "fill=\"url(#g)\"", "M10 10C10 -10 50 -10 50 10z"),
                            ReadLimits{}));
    CHECK(curved.gradient.from.x == Approx(10));
    CHECK(curved.gradient.to.x == Approx(50));
}

TEST_CASE("the SVG reader refuses gradients the model cannot hold, naming them",
          "[svg][flat][gradient]") {
    const std::string stops =
        "<stop offset=\"0\" stop-color=\"#000\"/><stop offset=\"1\" stop-color=\"#fff\"/>";
    const std::string user = " gradientUnits=\"userSpaceOnUse\" x1=\"0\" x2=\"100\"";
    auto linear = [&](const std::string& attributes, const std::string& content = "") {
        return "<linearGradient id=\"g\"" + attributes + ">" + (content.empty() ? stops : content) +
               "</linearGradient>";
    };
    const std::string atPath = "<path id=\"p\"> at line 1",
                      atGradient = "<linearGradient id=\"g\">";
    checkRefused(
        filledSvg("<radialGradient id=\"g\">" + stops + "</radialGradient>"),
        "fills by <radialGradient> are not supported (<radialGradient id=\"g\"> at line 1)",
        atPath);
    checkRefused(
        filledSvg(linear(" gradientUnits=\"userSpaceOnUse\" x2=\"50\" spreadMethod=\"reflect\"")),
        "spreadMethod 'reflect' is not supported where the shape reaches beyond", atGradient);
    checkRefused(filledSvg(linear(user + " spreadMethod=\"sideways\"")), "unknown spreadMethod",
                 atGradient);
    checkRefused(filledSvg(linear(user,
                                  "<stop offset=\"0\" stop-color=\"#000\"/><stop "
                                  "offset=\"1\" stop-color=\"#fff\" stop-opacity=\".5\"/>")),
                 "stops of different stop-opacity are not supported",
                 "(in the fill of <path id=\"p\">");
    std::string many;
    for (int k = 0; k < 17; ++k) many += "<stop offset=\"" + std::to_string(k / 16.0) + "\"/>";
    checkRefused(filledSvg(linear(user, many)), "a gradient of 17 stops is over the limit of 16",
                 atGradient);
    std::string sixteen;
    for (int k = 1; k <= 16; ++k) sixteen += "<stop offset=\"" + std::to_string(k / 20.0) + "\"/>";
    checkRefused(filledSvg(linear(user, sixteen)),
                 "a gradient of 18 stops with those added at 0 and 1 is over the limit of 16",
                 atGradient);
    checkRefused(filledSvg("<linearGradient id=\"g\" href=\"#h\"/><linearGradient id=\"h\" "
                           "href=\"#g\"/>"),
                 "href chain has a cycle", "<linearGradient id=\"h\">");
    checkRefused(filledSvg("<linearGradient id=\"g\" href=\"#p\"/>"),
                 "href to <path>, not a linearGradient or radialGradient", atGradient);
    checkRefused(filledSvg(linear(user), "fill=\"#fff\" stroke=\"url(#g)\""),
                 "strokes painted with a gradient (<linearGradient id=\"g\"> at line 1) are not "
                 "supported",
                 atPath);
    checkRefused(filledSvg(linear(""), "fill=\"url(#g)\"", "M0 10h50z"),
                 "a gradient in objectBoundingBox units on a path of no width or no height",
                 atGradient);
    checkRefused(filledSvg(linear(user + " gradientTransform=\"matrix(1 0 2 0 0 0)\"")),
                 "the gradient's transform to the canvas is not invertible", atGradient);
    checkRefused(filledSvg(linear(" gradientUnits=\"userSpaceOnUse\" x1=\"10\" x2=\"10.05\"")),
                 "the gradient's colours change over less than 0.1 px", atGradient);
    checkRefused(filledSvg(linear(" gradientUnits=\"objectBoundingBoxes\"")),
                 "unknown gradientUnits", atGradient);
    checkRefused(filledSvg(linear(user, "<stop offset=\"half\"/><stop offset=\"1\"/>")),
                 "offset 'half' is not a number or a percentage", "<stop> at line 1");
    checkRefused(filledSvg(linear(" gradientUnits=\"userSpaceOnUse\" x2=\"3em\"")),
                 "x2 '3em' is not a number of pixels or a percentage", atGradient);
    checkRefused("<svg xmlns=\"http://www.w3.org/2000/svg\">" +
                     linear(" x2=\"50%\" "
                            "gradientUnits=\"userSpaceOnUse\"") +
                     "<path fill=\"url(#g)\" d=\"M0 0h9v9z\"/></svg>",
                 "x2 is a percentage of a canvas of unknown size", atGradient);
    checkRefused(filledSvg(linear(user + " style=\"color-interpolation:linearRGB\"")),
                 "color-interpolation linearRGB is not supported", atGradient);
    // reflect and repeat are taken where the shape lies between the axis's ends.
    CHECK(onlyShape(decodeSvg(filledSvg(linear(" gradientUnits=\"userSpaceOnUse\" x1=\"10\" "
                                               "x2=\"90\" spreadMethod=\"repeat\"")),
                              ReadLimits{}))
              .graded());
}

namespace {

std::string inkscapeCommand(const std::string& args) {
    const std::string home = svgtest::tmpPath("inkscape-home-gradient");  // not the real profile
    return "HOME=" + gmtest::quote(home) + " XDG_CONFIG_HOME=" + gmtest::quote(home) +
           " timeout 120 inkscape " + args + " >/dev/null 2>&1";
}

// Inkscape's PNG of an SVG file, over white.
RgbaImage inkscapePng(const std::string& svg, const std::string& png) {
    std::remove(png.c_str());
    REQUIRE(gmtest::runCommand(inkscapeCommand(
                "--export-type=png --export-background=white --export-background-opacity=1 "
                "--export-filename=" +
                gmtest::quote(png) + " " + gmtest::quote(svg))) == 0);
    return readImage(png);
}

// librsvg's PNG of an SVG file, over white.
RgbaImage rsvgPng(const std::string& svg, const std::string& png) {
    std::remove(png.c_str());
    REQUIRE(gmtest::runCommand("rsvg-convert --background-color=white -o " + gmtest::quote(png) +
                               " " + gmtest::quote(svg)) == 0);
    return readImage(png);
}

struct ConsumerError {
    double all = 0, away = 0;  // E over every pixel; over those 2 px or more from outlines
};

// A consumer's picture of `doc` (its SVG written with `options` to NAME.svg, drawn to
// NAME_<consumer>.png) against our render over white (NAME_ours.png).
ConsumerError consumerError(const Document& doc, const std::string& name,
                            const std::string& consumer, const WriteOptions& options = {}) {
    const std::string svg = svgtest::tmpPath(name + ".svg");
    const std::string png = svgtest::tmpPath(name + "_" + consumer + ".png");
    writeFileAtomically(svg, encodeSvg(doc, options));
    const RgbaImage theirs = consumer == "inkscape" ? inkscapePng(svg, png) : rsvgPng(svg, png);
    REQUIRE(theirs.width == doc.width);
    REQUIRE(theirs.height == doc.height);
    const RgbaImage ours = svgtest::renderOverWhite(doc);
    writeImage(ours, svgtest::tmpPath(name + "_ours.png"));
    return {svgtest::meanAbs(ours, theirs),
            svgtest::meanAbs(ours, theirs, svgtest::awayFromOutlines(doc))};
}

}  // namespace

TEST_CASE("Inkscape draws graded shapes like our renderer", "[svg][flat][gradient][external]") {
    const ConsumerError e = consumerError(gmtest::gradientTestDocument(), "gradients", "inkscape");
    WriteOptions exact;
    exact.svgColors = "exact";
    const ConsumerError withMesh =
        consumerError(gradedDocumentWithMesh(), "gradients_mesh", "inkscape", exact);
    std::printf(
        "[svg figures] Inkscape graded shapes: E %.3f (%.3f away from outlines); "
        "with a mesh E %.3f (%.3f)\n",
        e.all, e.away, withMesh.all, withMesh.away);
    CHECK(e.away <= 0.5);
    CHECK(e.all <= 0.5);
    CHECK(withMesh.all <= 1.0);  // the mesh's own difference, as in the mesh tests
}

TEST_CASE("librsvg draws graded shapes like our renderer", "[svg][flat][gradient][external]") {
    REQUIRE(gmtest::runCommand("command -v rsvg-convert >/dev/null") == 0);
    const ConsumerError e = consumerError(gmtest::gradientTestDocument(), "gradients", "rsvg");
    std::printf("[svg figures] rsvg-convert graded shapes: E %.3f (%.3f away from outlines)\n",
                e.all, e.away);
    CHECK(e.away <= 0.5);
    CHECK(e.all <= 0.5);
}

TEST_CASE("a graded shape Inkscape transformed reads back as Inkscape draws it",
          "[svg][flat][gradient][external]") {
    // Two paths of one gradient (one element for both) across the canvas. Inkscape rotating
    // and scaling the second forks the gradient: an element of its own with xlink:href to the
    // stops and a gradientTransform, the path's fill in its style.
    Document doc = gmtest::gradientTestDocument();
    const LinearGradient across = gmtest::linearGradient(
        {0, 0}, {200, 40}, {{0, {0.9, 0.2, 0.1}}, {0.5, {0.95, 0.9, 0.3}}, {1, {0.1, 0.3, 0.8}}});
    doc.shapes = {
        doc.shapes[0],
        gmtest::gradedShape({polygonAsCubics({{10, 10}, {90, 10}, {90, 60}, {10, 60}})}, across),
        gmtest::gradedShape({polygonAsCubics({{110, 60}, {180, 60}, {180, 120}, {110, 120}})},
                            across)};
    std::string text = encodeSvg(doc, WriteOptions{});
    text.insert(text.rfind("<path ") + 5, " id=\"copy\"");
    const std::string svg = svgtest::tmpPath("gradients_shared.svg");
    const std::string resaved = svgtest::tmpPath("gradients_resaved.svg");
    writeFileAtomically(svg, text);
    std::remove(resaved.c_str());
    REQUIRE(gmtest::runCommand(inkscapeCommand(
                "--actions=\"select-by-id:copy;transform-rotate:30;transform-scale:1.2;"
                "export-filename:" +
                resaved + ";export-plain-svg;export-do\" " + gmtest::quote(svg))) == 0);
    const std::string saved = readWholeFile(resaved, 1 << 20);
    REQUIRE(std::regex_search(saved, std::regex("xlink:href=\"#g[0-9a-f]{10}\"")));
    REQUIRE(saved.find("gradientTransform") != std::string::npos);

    const Document back = decodeSvg(saved, ReadLimits{}, resaved);
    REQUIRE(back.shapes.size() == 3);
    checkShapesRead(Document{doc.width, doc.height, {}, {doc.shapes[0], doc.shapes[1]}},
                    Document{back.width, back.height, {}, {back.shapes[0], back.shapes[1]}});
    const FlatShape& copy = back.shapes[2];
    REQUIRE(copy.graded());
    // Turned by 30° and scaled by 1.2, as the outline is.
    const Vec2 axis = copy.gradient.to - copy.gradient.from;
    CHECK(std::atan2(axis.y, axis.x) == Approx(std::atan2(40, 200) + M_PI / 6).margin(1e-6));
    CHECK(norm(axis) == Approx(1.2 * std::hypot(200, 40)).margin(1e-3));
    const RgbaImage theirs =
        inkscapePng(resaved, svgtest::tmpPath("gradients_resaved_inkscape.png"));
    const RgbaImage ours = svgtest::renderOverWhite(back);
    writeImage(ours, svgtest::tmpPath("gradients_resaved_ours.png"));
    const double e = svgtest::meanAbs(ours, theirs);
    const double away = svgtest::meanAbs(ours, theirs, svgtest::awayFromOutlines(back));
    std::printf(
        "[svg figures] Inkscape-transformed graded shape read back: E %.3f (%.3f away "
        "from outlines)\n",
        e, away);
    CHECK(away <= 0.5);
    CHECK(e <= 0.5);
}

TEST_CASE("librsvg draws hand-written gradients as the SVG reader reads them",
          "[svg][flat][gradient][external]") {
    REQUIRE(gmtest::runCommand("command -v rsvg-convert >/dev/null") == 0);
    // Bounding-box units under a skew and a non-uniform scale of the path, an href chain with
    // style stops, a uniform stop-opacity, percentages, a hard step, reflect within the axis.
    const std::string text =
        "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" "
        "width=\"200\" height=\"140\" viewBox=\"0 0 200 140\">"
        "<path fill=\"#e6e0d0\" d=\"M0 0h200v140H0z\"/><defs><linearGradient id=\"stops\">"
        "<stop style=\"stop-color:#ffcc00;stop-opacity:0.7\" offset=\"20%\"/>"
        "<stop style=\"stop-color:#003366;stop-opacity:0.7\" offset=\"60%\"/>"
        "<stop offset=\"60%\" stop-color=\"#c04080\" stop-opacity=\".7\"/></linearGradient>"
        "<linearGradient xlink:href=\"#stops\" id=\"user\" gradientUnits=\"userSpaceOnUse\" "
        "x1=\"20\" y1=\"10\" x2=\"90\" y2=\"50\" gradientTransform=\"rotate(20 50 30) "
        "scale(1.2)\"/><linearGradient href=\"#stops\" id=\"box\" x1=\"0\" y1=\"0\" "
        "x2=\"100%\" y2=\"1\" spreadMethod=\"reflect\" gradientTransform=\"skewX(10)\"/></defs>"
        "<path style=\"fill:url(#user)\" d=\"M10 10C60 -10 100 20 95 60L10 60z\"/>"
        "<g transform=\"translate(100 70) scale(1.6 0.6)\"><path fill=\"url(#box)\" "
        "d=\"M-40 -80h58v100h-58z\"/></g>"
        "<path fill=\"url(#box)\" d=\"M20 80h60v50h-60z\"/></svg>";
    const std::string svg = svgtest::tmpPath("gradients_hand.svg");
    writeFileAtomically(svg, text);
    const Document doc = decodeSvg(text, ReadLimits{});
    REQUIRE(doc.shapes.size() == 4);
    for (size_t k = 1; k < 4; ++k) CHECK(doc.shapes[k].graded());
    const RgbaImage theirs = rsvgPng(svg, svgtest::tmpPath("gradients_hand_rsvg.png"));
    const RgbaImage ours = svgtest::renderOverWhite(doc);
    writeImage(ours, svgtest::tmpPath("gradients_hand_ours.png"));
    const double e = svgtest::meanAbs(ours, theirs);
    const double away = svgtest::meanAbs(ours, theirs, svgtest::awayFromOutlines(doc));
    std::printf(
        "[svg figures] rsvg-convert hand-written gradients: E %.3f (%.3f away from "
        "outlines)\n",
        e, away);
    CHECK(away <= 0.5);
    CHECK(e <= 0.5);
}
