// Checks by a real consumer: Inkscape renders our SVG, and opens and saves it.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "formats/atomic_file.h"
#include "formats/input_file.h"
#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "support/compare.h"
#include "svg_test_support.h"

using namespace gm;

namespace {

std::string inkscape(const std::string& args) {
    // A private HOME: Inkscape must not read or write the real profile.
    const std::string home = svgtest::tmpPath("inkscape-home");
    return "HOME=" + gmtest::quote(home) + " XDG_CONFIG_HOME=" + gmtest::quote(home) +
           " inkscape " + args + " >/dev/null 2>&1";
}

RgbaImage inkscapeRender(const std::string& svgPath, const std::string& pngPath) {
    std::remove(pngPath.c_str());
    const int rc = gmtest::runCommand(
        inkscape("--export-type=png --export-background=white --export-background-opacity=1 "
                 "--export-filename=" + gmtest::quote(pngPath) + " " + gmtest::quote(svgPath)));
    REQUIRE(rc == 0);
    return readImage(pngPath);
}

struct Case {
    const char* name;
    Document doc;
};

}  // namespace

TEST_CASE("Inkscape renders our exact svg like our renderer", "[svg][external]") {
    const Case cases[] = {{"holed", svgtest::holedDocument()},
                          {"curved", svgtest::curvedDocument()},
                          {"large", svgtest::largeDocument()}};
    for (const Case& c : cases) {
        const std::string svg = svgtest::tmpPath(std::string("ink_") + c.name + ".svg");
        const std::string png = svgtest::tmpPath(std::string("ink_") + c.name + ".png");
        SvgEncodeStats stats;
        WriteOptions exact;
        exact.svgColors = "exact";
        const std::string bytes = encodeSvg(c.doc, exact, &stats);
        writeFileAtomically(svg, bytes);
        const RgbaImage theirs = inkscapeRender(svg, png);
        REQUIRE(theirs.width == c.doc.width);
        REQUIRE(theirs.height == c.doc.height);
        const RgbaImage ours = svgtest::renderOurs(c.doc);
        writeImage(ours, svgtest::tmpPath(std::string("ours_") + c.name + ".png"));
        const gmtest::DiffStats d = gmtest::compareInterior(ours, theirs, 1);
        std::printf("[svg figures] Inkscape exact %-6s: %d patches -> %lld SVG patches (max k %d), "
                    "%zu bytes = %.1f B/patch (%.1f B/SVG patch), interior mean %.3f max %.2f\n",
                    c.name, c.doc.meshes[0].patchCount(), static_cast<long long>(stats.svgPatches),
                    stats.maxSubdivision, bytes.size(), double(bytes.size()) / c.doc.meshes[0].patchCount(),
                    double(bytes.size()) / stats.svgPatches, d.mean, d.max);
        CHECK(d.count > 10000);
        CHECK(d.mean <= 1.0);
        CHECK(d.max <= 12.0);

        // Holes stay uncovered: pixels well inside a hole are the white background.
        if (c.doc.meshes[0].holeCount() > 0) {
            const RgbaImage alpha = renderDocument(c.doc).image;
            size_t holePixels = 0, painted = 0;
            for (int y = 2; y < alpha.height - 2; ++y)
                for (int x = 2; x < alpha.width - 2; ++x) {
                    bool clear = true;
                    for (int dy = -2; dy <= 2 && clear; ++dy)
                        for (int dx = -2; dx <= 2 && clear; ++dx)
                            clear = alpha.at(x + dx, y + dy)[3] == 0.f;
                    if (!clear) continue;
                    ++holePixels;
                    const float* p = theirs.at(x, y);
                    if (p[0] < 0.999f || p[1] < 0.999f || p[2] < 0.999f) ++painted;
                }
            CHECK(holePixels > 1000);
            CHECK(painted == 0);
        }
    }
}

TEST_CASE("Inkscape renders our editable svg close to our renderer", "[svg][external]") {
    const Document doc = svgtest::curvedDocument();
    WriteOptions o;
    o.svgColors = "editable";
    const std::string svg = svgtest::tmpPath("ink_editable.svg");
    writeFileAtomically(svg, encodeSvg(doc, o));
    const RgbaImage theirs = inkscapeRender(svg, svgtest::tmpPath("ink_editable.png"));
    const gmtest::DiffStats d = gmtest::compareInterior(svgtest::renderOurs(doc), theirs, 1);
    const SvgEditableDeviation dev = svgEditableDeviation(doc);
    std::printf("[svg figures] Inkscape editable curved: interior mean %.3f max %.2f; rule deviation "
                "%.4f, slope deviation %.4f (colour bound %.2f/255)\n",
                d.mean, d.max, dev.ruleDeviation, dev.slopeDeviation, dev.maxColorDifference * 255);
    // Geometry is exact (tensor points); colour differs by the rule, bounded by the deviation
    // plus 8-bit stops and Inkscape's 8×8 bilinear subdivision.
    CHECK(d.max <= dev.maxColorDifference * 255 + 12);
}

TEST_CASE("a mesh Inkscape has transformed reads back transformed", "[svg][external]") {
    // Inkscape moves a mesh-filled path by adding a gradientTransform (and a polyfill script).
    const Document doc = svgtest::curvedDocument();
    WriteOptions o;
    o.svgColors = "editable";
    const std::string svg = svgtest::tmpPath("moved_in.svg");
    const std::string saved = svgtest::tmpPath("moved_out.svg");
    writeFileAtomically(svg, encodeSvg(doc, o));
    std::remove(saved.c_str());
    REQUIRE(gmtest::runCommand(inkscape(
                "--actions=\"select-all:all;transform-translate:10,5;transform-scale:1.1;"
                "export-filename:" + saved + ";export-plain-svg;export-do\" " +
                gmtest::quote(svg))) == 0);
    const std::string text = readWholeFile(saved, 1u << 30);
    CHECK(text.find("gradientTransform") != std::string::npos);
    const Document before = decodeSvg(readWholeFile(svg, 1u << 30), ReadLimits{});
    const Document after = decodeSvg(text, ReadLimits{}, saved);
    REQUIRE(after.meshes.size() == 1);
    const GradientMesh &a = before.meshes[0], &b = after.meshes[0];
    REQUIRE(a.nodes.size() == b.nodes.size());
    // A scale about some centre plus a translation: fitted from two nodes, checked on all.
    const Vec2 p0 = a.nodes.front().pos, p1 = a.nodes.back().pos;
    const Vec2 q0 = b.nodes.front().pos, q1 = b.nodes.back().pos;
    const double sx = (q1.x - q0.x) / (p1.x - p0.x), sy = (q1.y - q0.y) / (p1.y - p0.y);
    CHECK(sx == Approx(1.1).epsilon(1e-6));
    CHECK(sy == Approx(1.1).epsilon(1e-6));
    double worst = 0;
    for (size_t k = 0; k < a.nodes.size(); ++k) {
        const Vec2 p = a.nodes[k].pos;
        const Vec2 expect{q0.x + sx * (p.x - p0.x), q0.y + sy * (p.y - p0.y)};
        worst = std::max(worst, norm(expect - b.nodes[k].pos));
    }
    CHECK(worst <= 1e-3);
}

TEST_CASE("Inkscape round trip keeps node positions and colours", "[svg][external][roundtrip]") {
    const Case cases[] = {{"holed", svgtest::holedDocument()},
                          {"curved", svgtest::curvedDocument()}};
    for (const Case& c : cases) {
        for (const char* mode : {"exact", "bicubic"}) {
            WriteOptions o;
            o.svgColors = mode;
            const std::string name = std::string(c.name) + "_" + mode;
            const std::string svg = svgtest::tmpPath("rt_" + name + ".svg");
            const std::string saved = svgtest::tmpPath("rt_" + name + "_inkscape.svg");
            writeFileAtomically(svg, encodeSvg(c.doc, o));
            std::remove(saved.c_str());
            REQUIRE(gmtest::runCommand(inkscape("--export-plain-svg --export-filename=" +
                                                gmtest::quote(saved) + " " + gmtest::quote(svg))) == 0);
            const MeshFormat* f = FormatRegistry::builtin().byName("svg");
            REQUIRE(f);
            const Document ours = f->read(svg, ReadOptions{});
            const Document theirs = f->read(saved, ReadOptions{});
            REQUIRE(theirs.meshes.size() == ours.meshes.size());
            CHECK(theirs.width == ours.width);
            CHECK(theirs.height == ours.height);
            double pos = 0, col = 0, handle = 0;
            for (size_t m = 0; m < ours.meshes.size(); ++m) {
                const GradientMesh &a = ours.meshes[m], &b = theirs.meshes[m];
                REQUIRE(a.columns() == b.columns());
                REQUIRE(a.rows() == b.rows());
                for (size_t k = 0; k < a.nodes.size(); ++k) {
                    const Node &x = a.nodes[k], &y = b.nodes[k];
                    pos = std::max({pos, std::fabs(x.pos.x - y.pos.x), std::fabs(x.pos.y - y.pos.y)});
                    for (int ch = 0; ch < 3; ++ch) col = std::max(col, std::fabs(x.col[ch] - y.col[ch]));
                }
                for (int j = 0; j < a.rows(); ++j)
                    for (int i = 0; i < a.columns(); ++i) {
                        const PatchHermite ha = patchHermite(a, i, j), hb = patchHermite(b, i, j);
                        for (int q = 0; q < 4; ++q) {
                            const HermiteCorner &x = ha.corner[q / 2][q % 2], &y = hb.corner[q / 2][q % 2];
                            handle = std::max({handle, std::fabs(x.posS.x - y.posS.x),
                                               std::fabs(x.posS.y - y.posS.y),
                                               std::fabs(x.posT.x - y.posT.x),
                                               std::fabs(x.posT.y - y.posT.y)});
                        }
                    }
            }
            // And against the mesh we wrote: the original's node positions.
            std::printf("[svg figures] Inkscape round trip %-16s: node positions %.2e px, colours "
                        "%.2e, local derivatives %.2e px\n",
                        name.c_str(), pos, col * 255, handle);
            CHECK(pos <= 1e-3);
            CHECK(col <= 1.0 / 255);
        }
    }
}
