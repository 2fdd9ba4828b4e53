// What --svg-fallback writes: the layer and its image, the mesh paint, the bytes without it,
// and that our reader reads the meshes alone.
#include <catch2/catch.hpp>

#include <regex>

#include "fallback_support.h"
#include "formats/gmb.h"
#include "formats/svg.h"

using namespace fallbacktest;
using Catch::Matchers::Contains;
using gmtest::Run;

namespace {

gm::Document readSvg(const std::string& text) { return gm::decodeSvg(text, gm::ReadLimits{}); }

// The lossless .gmb of a document: equal bytes, equal meshes.
std::string gmbBytes(const gm::Document& doc) { return gm::encodeGmb(doc, false); }

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
}

}  // namespace

TEST_CASE("the fallback is one image in a locked Inkscape layer beneath the mesh shapes",
          "[fallback]") {
    const Sample& pic1 = kSamples[1];
    const fs::path d = tmpDir("layer");
    for (const char* kind : {"png", "webp"}) {
        INFO(kind);
        const fs::path svg = d / (std::string("pic1_") + kind + ".svg");
        checkSuccess(gmtest::runGradmesh("convert " + q(sampleGmb(pic1)) + " --svg-fallback " +
                                             kind + " -o " + q(svg), d));
        const std::string text = gmtest::slurp(svg);
        CHECK_THAT(text,
                   Contains("xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\""));
        CHECK_THAT(text, Contains("xmlns:sodipodi=\"http://sodipodi.sourceforge.net/DTD/"
                                  "sodipodi-0.dtd\""));
        CHECK_THAT(text, Contains("xmlns:xlink=\"http://www.w3.org/1999/xlink\""));
        CHECK(count(text, "<image ") == 1);
        CHECK(count(text, "inkscape:groupmode=\"layer\"") == 1);
        CHECK_THAT(text, Contains("sodipodi:insensitive=\"true\""));
        CHECK_THAT(text, Contains("width=\"400\" height=\"300\" preserveAspectRatio=\"none\""));
        CHECK_THAT(text, Contains(std::string("xlink:href=\"data:image/") + kind + ";base64,"));
        // Beneath: the layer comes after the definitions and before the first shape.
        const size_t layer = text.find("<g id=\"gradmesh-fallback\""), shape = text.find("<path ");
        CHECK(text.find("</defs>") < layer);
        CHECK(layer < shape);
    }
    // Lossless WebP is smaller than PNG.
    CHECK(fs::file_size(d / "pic1_webp.svg") < fs::file_size(d / "pic1_png.svg"));
}

TEST_CASE("without --svg-fallback the SVG has no image and paints meshes through style",
          "[fallback]") {
    const Sample& apple = kSamples[0];
    const fs::path d = tmpDir("none");
    const fs::path plain = d / "plain.svg", none = d / "none.svg";
    checkSuccess(gmtest::runGradmesh("convert " + q(sampleGmb(apple)) + " -o " + q(plain), d));
    checkSuccess(gmtest::runGradmesh(
        "convert " + q(sampleGmb(apple)) + " --svg-fallback none -o " + q(none), d));
    const std::string text = gmtest::slurp(plain);
    CHECK(text == gmtest::slurp(none));
    CHECK(text.find("<image") == std::string::npos);
    CHECK(text.find("xmlns:inkscape") == std::string::npos);
    CHECK(text.find("fill=\"url(") == std::string::npos);
    // Every shape's paint: the mesh, falling back to none.
    const std::regex paint("<path style=\"fill:url\\(#m[0-9]+\\) none\" d=\"");
    const size_t shapes = count(text, "<path ");
    CHECK(shapes >= 1);
    CHECK(size_t(std::distance(std::sregex_iterator(text.begin(), text.end(), paint),
                               std::sregex_iterator())) == shapes);
}

TEST_CASE("the reader reads the meshes of a fallback SVG as without it, either paint form",
          "[fallback]") {
    const fs::path d = tmpDir("reader");
    for (const Sample& s : kSamples) {
        INFO(s.name);
        const fs::path plain = d / (s.name + ".svg"), withPng = d / (s.name + "_png.svgz");
        checkSuccess(gmtest::runGradmesh("convert " + q(sampleGmb(s)) + " -o " + q(plain), d));
        checkSuccess(gmtest::runGradmesh(
            "convert " + q(sampleGmb(s)) + " --svg-fallback png -o " + q(withPng), d));
        // .gmb -> .svg(z) with a fallback -> .gmb: the same bytes as without one.
        const gm::MeshFormat* svg = gm::FormatRegistry::builtin().byName("svg");
        CHECK(gmbBytes(svg->read(withPng.string(), gm::ReadOptions{})) ==
              gmbBytes(svg->read(plain.string(), gm::ReadOptions{})));

        // Files from before the style paint carry a fill attribute: read alike.
        const std::string text = gmtest::slurp(plain);
        const std::string old = std::regex_replace(
            text, std::regex("style=\"fill:url\\(#(m[0-9]+)\\) none\""), "fill=\"url(#$1)\"");
        REQUIRE(old != text);
        CHECK(gmbBytes(readSvg(old)) == gmbBytes(readSvg(text)));
    }
}

TEST_CASE("the option --svg-fallback from an image, from an SVG, and its bad values", "[fallback]") {
    const fs::path d = tmpDir("cli");
    const fs::path S(GRADMESH_SAMPLES);
    // Straight from an image, and again from the SVG written.
    checkSuccess(gmtest::runGradmesh("convert " + q(S / "pic1.png") +
                                         " --svg-fallback webp -o " + q(d / "a.svg"), d));
    CHECK_THAT(gmtest::slurp(d / "a.svg"), Contains("data:image/webp;base64,"));
    checkSuccess(gmtest::runGradmesh("convert " + q(d / "a.svg") + " --svg-fallback png -o " +
                                         q(d / "b.svg"), d));
    const std::string b = gmtest::slurp(d / "b.svg");
    CHECK(count(b, "<image ") == 1);
    CHECK_THAT(b, Contains("data:image/png;base64,"));

    const Run bad = gmtest::runGradmesh(
        "convert " + q(d / "a.svg") + " --svg-fallback gif -o " + q(d / "c.svg"), d);
    CHECK(bad.code == 2);
    CHECK_THAT(bad.err, Contains("--svg-fallback expects png, webp or none, got 'gif'"));
    CHECK(!fs::exists(d / "c.svg"));
    // The image counts against --max-output-bytes (pic1: 162 KB without, 182 KB with a PNG).
    const Run big = gmtest::runGradmesh("convert " + q(d / "a.svg") + " --svg-fallback png" +
                                        " --max-output-bytes 172000 -o " + q(d / "d.svg"), d);
    CHECK(big.code == 1);
    CHECK_THAT(big.err, Contains("d.svg"));
    CHECK_THAT(big.err, Contains("--max-output-bytes"));
    CHECK(!fs::exists(d / "d.svg"));
    const Run help = gmtest::runGradmesh("convert --help", d);
    CHECK_THAT(help.out, Contains("--svg-fallback KIND"));

    // In memory: the image must come with the option that asks for it.
    const gm::Document doc = readSvg(gmtest::slurp(d / "a.svg"));
    gm::WriteOptions png;
    png.svgFallback = "png";
    CHECK_THROWS_WITH(gm::encodeSvg(doc, png), Contains("fallback image (png) was not made"));
    png.svgFallback = "jpeg";
    CHECK_THROWS_WITH(gm::encodeSvg(doc, png), Contains("unknown SVG fallback 'jpeg'"));
}
