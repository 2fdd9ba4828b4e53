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

TEST_CASE("positions beyond the coordinate limit are found", "[hostile]") {
    CHECK(coordinateProblem(shiftedDemo(kMaxCoordinate / 2)).empty());
    CHECK(coordinateProblem(shiftedDemo(1e21)).find("coordinate limit") != std::string::npos);
    Document wild = makeDemoDocument();
    wild.meshes[0].nodes[0].posU = {1e30, 0};  // a handle far away
    CHECK(coordinateProblem(wild).find("coordinate limit") != std::string::npos);
    CHECK(validateDocument(wild).empty());  // valid: .gmb keeps any finite double
}

TEST_CASE("a .gmb at 1e21 px reads, every vector writer refuses it, the renderer clips it",
          "[hostile][gmb]") {
    const Document doc = shiftedDemo(1e21);
    const Document back = decodeGmb(encodeGmb(doc, false), ReadLimits{});
    CHECK(back.meshes[0].nodes[0].pos.x == doc.meshes[0].nodes[0].pos.x);
    const auto dir = gmtest::scratchDir("hostile_", "writers");
    for (const MeshFormat* f : FormatRegistry::builtin().all()) {
        if (!f->canWrite() || f->name() == "gmb") continue;
        if (f->name() == "raster") {  // the renderer clips what lies off the canvas
            const std::string png = (dir / "out.png").string();
            CHECK_NOTHROW(f->write(doc, png, WriteOptions{}));
            continue;
        }
        const std::string path = (dir / ("out" + f->extensions()[0])).string();
        INFO(f->name());
        CHECK_THROWS_WITH(f->write(doc, path, WriteOptions{}), Catch::Contains("coordinate limit"));
        CHECK(!std::filesystem::exists(path));
    }
    // The SVG text itself, built without the writer's check, is defined (no crash).
    std::string text;
    CHECK_NOTHROW(text = encodeSvg(doc, WriteOptions{}));
    CHECK(text.find("e+21") != std::string::npos);
}

TEST_CASE("convert of the nested-scale svg fails cleanly", "[hostile][cli]") {
    const auto dir = gmtest::scratchDir("hostile_", "nested_scale");
    const auto in = dir / "nested.svg";
    std::ofstream(in) << nestedScaleSvg();
    for (const char* ext : {".svg", ".gmb", ".eps", ".pdf", ".png"}) {  // the reader refuses it
        const auto out = dir / (std::string("out") + ext);
        const gmtest::Run r = gmtest::runGradmesh("convert " + gmtest::q(in) + " -o " + gmtest::q(out), dir);
        INFO(ext << ": " << r.err);
        CHECK(r.code == 1);
        CHECK(r.err.find("after its transforms") != std::string::npos);
        CHECK(!std::filesystem::exists(out));
    }
}

TEST_CASE("convert of a .gmb at 1e21 px to svg, eps and pdf fails cleanly", "[hostile][cli]") {
    const auto dir = gmtest::scratchDir("hostile_", "gmb_1e21");
    const auto in = dir / "far.gmb";
    std::ofstream(in, std::ios::binary) << encodeGmb(shiftedDemo(1e21), false);
    for (const char* ext : {".svg", ".eps", ".pdf"}) {
        const auto out = dir / (std::string("out") + ext);
        const gmtest::Run r = gmtest::runGradmesh("convert " + gmtest::q(in) + " -o " + gmtest::q(out), dir);
        INFO(ext << ": " << r.err);
        CHECK(r.code == 1);
        CHECK(r.err.find("coordinate limit") != std::string::npos);
        CHECK(!std::filesystem::exists(out));
    }
}
