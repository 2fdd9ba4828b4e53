// Coordinates that grow through nested transforms, and documents whose coordinates are out of
// any canvas: refused by the readers, by every writer, and the SVG number text is defined for
// every double.
#include <catch2/catch.hpp>

#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <string>

#include "formats/gmb.h"
#include "formats/registry.h"
#include "formats/svg.h"
#include "gmb/gmb_test_support.h"
#include "meshcore/error.h"
#include "meshcore/synthetic_meshes.h"
#include "meshcore/validate.h"
#include "support/cli_run.h"
#include "svg_number.h"

using namespace gm;

namespace {

// One patch of 50 px inside three nested scale(1e7): every number in the file is within the
// reader's 1e7, the mesh lands at 1e21 px.
std::string nestedScaleSvg() {
    return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\" "
           "viewBox=\"0 0 100 100\"><defs><meshgradient id=\"m\" "
           "gradientUnits=\"userSpaceOnUse\" x=\"10\" y=\"10\"><meshrow><meshpatch>"
           "<stop path=\"c 10,0 40,0 50,0\" stop-color=\"#ff0000\"/>"
           "<stop path=\"l 0,50\" stop-color=\"#00ff00\"/>"
           "<stop path=\"c -10,0 -40,0 -50,0\" stop-color=\"#0000ff\"/>"
           "<stop path=\"l 0,-50\" stop-color=\"white\"/>"
           "</meshpatch></meshrow></meshgradient></defs>"
           "<g transform=\"scale(1e7)\"><g transform=\"scale(1e7)\"><g transform=\"scale(1e7)\">"
           "<path d=\"M10,10 H60 V60 H10 Z\" fill=\"url(#m)\"/></g></g></g></svg>";
}

// The demo document moved by `shift` pixels: beyond the coordinate limit for a large shift.
Document shiftedDemo(double shift) {
    Document doc = makeDemoDocument();
    for (GradientMesh& m : doc.meshes) {
        for (Node& n : m.nodes) n.pos = n.pos + Vec2{shift, shift};
        for (Slit& s : m.slits)
            for (Node& n : s.below) n.pos = n.pos + Vec2{shift, shift};
    }
    return doc;
}

}  // namespace

TEST_CASE("svg numbers are written for every double", "[hostile][svg]") {
    const double values[] = {0.0,     -0.0,    1e-300, 12.5,    -0.25,   1e7,     -1e7,
                             9.2e14,  -9.3e14, 9.3e18, -9.3e18, 1e21,    -1e21,   DBL_MAX,
                             -DBL_MAX, 4.9e-324, 922337203685477.5807};
    for (double v : values) {
        std::string text;
        appendSvgNumber(text, v);
        INFO(v << " -> " << text);
        REQUIRE(!text.empty());
        char* end = nullptr;
        const double back = std::strtod(text.c_str(), &end);
        CHECK(*end == '\0');
        CHECK(std::fabs(back - v) <= std::max(5e-5, std::fabs(v) * 1e-15));
        CHECK(svgPrintedValue(v) == Approx(v).margin(5e-5));
    }
    for (double v : {NAN, INFINITY, -INFINITY}) {  // defined, though no reader lets them through
        std::string text;
        appendSvgNumber(text, v);
        CHECK(!text.empty());
    }
}

TEST_CASE("svg reader refuses coordinates that nested transforms make huge", "[hostile][svg]") {
    try {
        decodeSvg(nestedScaleSvg(), ReadLimits{}, "nested.svg");
        FAIL("a mesh at 1e21 px was read");
    } catch (const Error& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find("after its transforms") != std::string::npos);
        CHECK(std::string(e.what()).find("nested.svg") != std::string::npos);
    }
}

TEST_CASE("validation refuses positions beyond the coordinate limit", "[hostile]") {
    CHECK(validateDocument(shiftedDemo(kMaxCoordinate / 2)).empty());
    CHECK(validateDocument(shiftedDemo(1e21)).find("coordinate limit") != std::string::npos);
    Document wild = makeDemoDocument();
    wild.meshes[0].nodes[0].posU = {1e30, 0};  // a handle far away
    CHECK(validateDocument(wild).find("coordinate limit") != std::string::npos);
}

TEST_CASE("every writer refuses a document at 1e21 px without crashing", "[hostile]") {
    const Document doc = shiftedDemo(1e21);
    const auto dir = gmtest::scratchDir("hostile_", "writers");
    for (const MeshFormat* f : FormatRegistry::builtin().all()) {
        if (!f->canWrite() || f->name() == "raster") continue;  // the raster writer renders
        const std::string path = (dir / ("out" + f->extensions()[0])).string();
        INFO(f->name());
        CHECK_THROWS_AS(f->write(doc, path, WriteOptions{}), Error);
        CHECK(!std::filesystem::exists(path));
    }
    CHECK_THROWS_AS(encodeGmb(doc, true), Error);
}

TEST_CASE("the gmb reader refuses a file whose meshes lie at 1e21 px", "[hostile][gmb]") {
    // Written by the tests' own encoder: the real writer refuses such a document.
    const std::string bytes = gmbtest::specEncode(shiftedDemo(1e21));
    try {
        decodeGmb(bytes, ReadLimits{});
        FAIL("a mesh at 1e21 px was read");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("coordinate limit") != std::string::npos);
    }
}

TEST_CASE("convert of the nested-scale svg fails cleanly", "[hostile][cli]") {
    const auto dir = gmtest::scratchDir("hostile_", "nested_scale");
    const auto in = dir / "nested.svg";
    std::ofstream(in) << nestedScaleSvg();
    for (const char* ext : {".svg", ".gmb", ".eps", ".pdf", ".png"}) {
        const auto out = dir / (std::string("out") + ext);
        const gmtest::Run r = gmtest::runGradmesh("convert " + gmtest::q(in) + " -o " + gmtest::q(out), dir);
        INFO(ext << ": " << r.err);
        CHECK(r.code == 1);
        CHECK(r.err.find("after its transforms") != std::string::npos);
        CHECK(!std::filesystem::exists(out));
    }
}
