// Small files that would make huge work: patches per document, output bytes and canvas pixels
// are limited, checked before the work, each with an option to raise it.
#include <catch2/catch.hpp>

#include <chrono>
#include <string>

#include "formats/gmb.h"
#include "formats/registry.h"
#include "formats/svg.h"
#include "hostile_files.h"
#include "meshcore/error.h"
#include "support/cli_run.h"

using namespace gm;

namespace {

// One meshgradient of side × side flat patches, painted by `shapes` paths: every shape that
// paints it is a copy of the mesh.
std::string meshPaintedBy(int side, int shapes) {
    std::string s =
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"500\" height=\"500\"><defs>"
        "<meshgradient id=\"m\" gradientUnits=\"userSpaceOnUse\" x=\"0\" y=\"0\">";
    for (int r = 0; r < side; ++r) {
        s += "<meshrow>";
        for (int c = 0; c < side; ++c) {
            s += "<meshpatch>";
            if (r == 0) s += "<stop path=\"l 1,0\"/>";
            s += "<stop path=\"l 0,1\"/><stop path=\"l -1,0\"/>";
            if (c == 0) s += "<stop path=\"l 0,-1\"/>";
            s += "</meshpatch>";
        }
        s += "</meshrow>";
    }
    s += "</meshgradient></defs>";
    for (int k = 0; k < shapes; ++k) s += "<path d=\"M0 0\" fill=\"url(#m)\"/>";
    return s + "</svg>";
}

// A flat mesh of columns × rows one-pixel patches.
Document flatMesh(int columns, int rows) {
    Document doc;
    doc.width = columns;
    doc.height = rows;
    GradientMesh m;
    for (int i = 0; i <= columns; ++i) m.u.push_back(i);
    for (int j = 0; j <= rows; ++j) m.v.push_back(j);
    m.nodes.resize(static_cast<size_t>(columns + 1) * (rows + 1));
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i <= columns; ++i) {
            Node& n = m.nodes[static_cast<size_t>(j) * (columns + 1) + i];
            n.pos = {double(i), double(j)};
            n.posU = {1, 0};
            n.posV = {0, 1};
            n.col = {0.5, 0.5, 0.5};
        }
    doc.meshes.push_back(std::move(m));
    return doc;
}

}  // namespace

TEST_CASE("an SVG painting one mesh with 2,000 shapes is refused by the patch limit",
          "[hostile][amplification][svg]") {
    const std::string svg = meshPaintedBy(50, 2000);  // 2,500 patches, 5 M painted
    CHECK(svg.size() < 400000);
    const auto t0 = std::chrono::steady_clock::now();
    try {
        decodeSvg(svg, ReadLimits{}, "copies.svg");
        FAIL("5 M patches were read");
    } catch (const Error& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find("patches, over the limit of 1048576") != std::string::npos);
        CHECK(std::string(e.what()).find("--max-document-patches") != std::string::npos);
    }
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 10);
    ReadLimits raised;
    raised.maxPatches = 100000;
    CHECK(decodeSvg(meshPaintedBy(50, 4), raised).meshes.size() == 4);
}

TEST_CASE("a compact .gmb claiming a million patches is checked before it is decoded or written",
          "[hostile][amplification][gmb][cli]") {
    const auto dir = gmtest::scratchDir("hostile_", "gmb_million");
    // 1,049,600 flat patches, a few KB compact: over the default limit of 2^20.
    const std::string over = encodeGmb(flatMesh(1025, 1024), true);
    CHECK(over.size() < 64 * 1024);
    CHECK_THROWS_WITH(decodeGmb(over, ReadLimits{}), Catch::Contains("over the limit of 1048576"));
    hostile::writeBytes(dir / "over.gmb", over);
    gmtest::Run r = gmtest::runGradmesh(
        "convert " + gmtest::q(dir / "over.gmb") + " -o " + gmtest::q(dir / "out.svg"), dir);
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK(r.err.find("raise it with --max-document-patches") != std::string::npos);
    // Raised, it is read; the SVG it would make (over 60 MB) is refused before it is encoded.
    const auto t0 = std::chrono::steady_clock::now();
    r = gmtest::runGradmesh("convert " + gmtest::q(dir / "over.gmb") +
                                " --max-document-patches 2000000 --max-output-bytes 20000000 -o " +
                                gmtest::q(dir / "out.svg"),
                            dir);
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK(r.err.find("output would take at least") != std::string::npos);
    CHECK(r.err.find("raise it with --max-output-bytes") != std::string::npos);
    CHECK(!std::filesystem::exists(dir / "out.svg"));
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 30);
}

TEST_CASE("an SVG with a 31622-pixel viewBox is refused before rendering", "[hostile][amplification][cli]") {
    const auto dir = gmtest::scratchDir("hostile_", "huge_canvas");
    hostile::writeBytes(
        dir / "wide.svg",
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 31622 31622\"><defs>"
        "<meshgradient id=\"m\" gradientUnits=\"userSpaceOnUse\" x=\"0\" y=\"0\"><meshrow><meshpatch>"
        "<stop path=\"l 31622,0\" stop-color=\"#ff0000\"/><stop path=\"l 0,31622\"/>"
        "<stop path=\"l -31622,0\"/><stop path=\"l 0,-31622\"/></meshpatch></meshrow>"
        "</meshgradient></defs><path d=\"M0 0\" fill=\"url(#m)\"/></svg>");
    const auto png = gmtest::q(dir / "out.png"), in = gmtest::q(dir / "wide.svg");
    gmtest::Run r = gmtest::runGradmesh("render " + in + " -o " + png, dir);
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK(r.err.find("over the limit of 268435456 (lower --scale or raise --max-canvas-pixels)") !=
          std::string::npos);
    // Within a raised canvas limit, the memory budget still stops it before the canvas exists.
    r = gmtest::runGradmesh("render " + in + " --max-canvas-pixels 2000000000 -o " + png, dir);
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK(r.err.find("the render is too large for the memory budget") != std::string::npos);
    CHECK(!std::filesystem::exists(dir / "out.png"));
}
