#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "formats/atomic_file.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "meshcore/bezier_patch.h"
#include "meshcore/evaluate.h"
#include "support/compare.h"
#include "svg_test_support.h"

using namespace gm;

namespace {

size_t countOf(const std::string& s, const std::string& what) {
    size_t n = 0;
    for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
    return n;
}

WriteOptions editable() {
    WriteOptions o;
    o.svgColors = "bicubic";
    return o;
}

WriteOptions exactColors() {
    WriteOptions o;
    o.svgColors = "exact";
    return o;
}

double maxDistance(Vec2 a, Vec2 b) { return std::max(std::fabs(a.x - b.x), std::fabs(a.y - b.y)); }
double maxDifference(Vec3 a, Vec3 b) {
    return std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b)});
}

// A meshgradient from hand-written patches, on a 100×100 canvas.
std::string svgWith(const std::string& gradientBody, const std::string& extraAttributes = "") {
    return "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" "
           "height=\"100\" viewBox=\"0 0 100 100\"><defs><meshgradient id=\"m\" "
           "gradientUnits=\"userSpaceOnUse\" x=\"10\" y=\"10\"" +
           extraAttributes + ">" + gradientBody +
           "</meshgradient></defs><path d=\"M10,10 H60 V60 H10 Z\" fill=\"url(#m)\"/></svg>";
}

const char* kOnePatch =
    "<meshrow><meshpatch>"
    "<stop path=\"c 10,0 40,0 50,0\" stop-color=\"#ff0000\"/>"
    "<stop path=\"l 0,50\" stop-color=\"#00ff00\"/>"
    "<stop path=\"c -10,0 -40,0 -50,0\" style=\"stop-color:#0000ff;stop-opacity:1\"/>"
    "<stop path=\"l 0,-50\" stop-color=\"white\"/>"
    "</meshpatch></meshrow>";

void requireErrorMentioning(const std::string& svg, const std::string& needle) {
    try {
        decodeSvg(svg, ReadLimits{}, "bad.svg");
        FAIL("no error for input expected to mention '" << needle << "'");
    } catch (const Error& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find(needle) != std::string::npos);
        CHECK(std::string(e.what()).find("bad.svg") != std::string::npos);
    }
}

}  // namespace

TEST_CASE("svg writer uses the 4/3/3/2 stop structure", "[svg]") {
    const Document doc = svgtest::curvedDocument();
    const std::string svg = encodeSvg(doc, editable());
    const int C = doc.meshes[0].columns(), R = doc.meshes[0].rows();
    CHECK(countOf(svg, "<meshgradient") == 1);
    CHECK(countOf(svg, "<meshrow>") == size_t(R));
    CHECK(countOf(svg, "<meshpatch") == size_t(C * R));
    CHECK(countOf(svg, "<stop ") == size_t(4 + 3 * (C - 1) + 3 * (R - 1) + 2 * (C - 1) * (R - 1)));
    CHECK(countOf(svg, "type=\"bicubic\"") == 1);
    CHECK(svg.find("viewBox=\"0 0 320 260\"") != std::string::npos);
    CHECK(svg.find("gradientUnits=\"userSpaceOnUse\"") != std::string::npos);
}

TEST_CASE("nearly straight edges inside a mesh are written as lines, its boundary as drawn",
          "[svg]") {
    // A 4x3 grid of 20 px patches, every edge bowed by 0.2 px: inside, lines (the curve moves
    // 0.09 px); on the boundary, which the outline path draws too, cubics.
    const int C = 4, R = 3;
    Document doc;
    doc.width = 100;
    doc.height = 80;
    GradientMesh mesh(C, R);
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            Node& n = mesh.node(i, j);
            n.pos = {10.0 + 20 * i, 10.0 + 20 * j};
            n.posU = {20, 0.6};  // handles 0.2 px off the chord
            n.posV = {0.6, 20};
            n.col = {0.1 * i, 0.2 * j, 0.5};
        }
    doc.meshes.push_back(mesh);
    const std::string svg = encodeSvg(doc, editable());
    const size_t inner = size_t(C * (R - 1) + (C - 1) * R), boundary = size_t(2 * C + 2 * R);
    CHECK(countOf(svg, "path=\"l") == inner);
    CHECK(countOf(svg, "path=\"c") == boundary);
    // Read back: corners where they were, handles within 0.2 px of the mesh's.
    const Document back = decodeSvg(svg, ReadLimits{});
    REQUIRE(back.meshes.size() == 1);
    double corner = 0;
    for (size_t k = 0; k < mesh.nodes.size(); ++k)
        corner = std::max(corner, maxDistance(mesh.nodes[k].pos, back.meshes[0].nodes[k].pos));
    CHECK(corner <= 0.005 + 1e-9);
}

TEST_CASE("a patch's tensor points are written where leaving them out would move its colours",
          "[svg]") {
    // Strongly curved patches: drawn with the Coons interior a reader assumes, their insides
    // move by pixels. Where their colours change steeply, that shows; where they are nearly
    // flat, it does not, and the attribute is left out.
    Document steep;
    steep.width = steep.height = 200;
    GradientMesh mesh(3, 3);
    for (int j = 0; j <= 3; ++j)
        for (int i = 0; i <= 3; ++i) {
            Node& n = mesh.node(i, j);
            n.pos = {20.0 + 50 * i, 20.0 + 50 * j};
            n.posU = {50, j % 2 ? 45.0 : -45.0};  // tangents that swing from row to row
            n.posV = {i % 2 ? 45.0 : -45.0, 50};
            n.col = i % 2 ? Vec3{0.9, 0.9, 0.9} : Vec3{0.1, 0.2, 0.1};  // a stripe a column
        }
    steep.meshes.push_back(mesh);
    Document gentle = steep;
    for (Node& n : gentle.meshes[0].nodes) n.col = 0.5 * Vec3{1, 1, 1} + 0.005 * n.col;
    const std::string steepSvg = encodeSvg(steep, editable());
    const std::string gentleSvg = encodeSvg(gentle, editable());
    CHECK(countOf(steepSvg, " tensor=\"") >= 4);
    CHECK(countOf(gentleSvg, " tensor=\"") == 0);
    // The exact syntax keeps every interior that differs at its precision.
    CHECK(countOf(encodeSvg(gentle, exactColors()), " tensor=\"") > 0);
}

TEST_CASE("svg numbers keep 1/100 px without accumulating along a row", "[svg]") {
    // A long row of patches far from the origin: relative offsets are written against the
    // reader's reconstructed corners, so the error stays at the rounding step.
    Document doc;
    doc.width = 40000;
    doc.height = 200;
    doc.meshes.push_back(makeCurvedMesh(200, 2, 12345.67891, 20.123456, 20000.0004, 150, 0.3, 5));
    const Document back = decodeSvg(encodeSvg(doc, editable()), ReadLimits{});
    REQUIRE(back.meshes.size() == 1);
    double worst = 0;
    for (size_t k = 0; k < doc.meshes[0].nodes.size(); ++k)
        worst = std::max(worst, maxDistance(doc.meshes[0].nodes[k].pos, back.meshes[0].nodes[k].pos));
    CHECK(worst <= 0.005 + 1e-9);
}

TEST_CASE("a mesh's outline path is relative and runs through its boundary nodes", "[svg]") {
    // Far from the origin and many patches long: written as differences of rounded points, the
    // outline must not drift from the patches' corners.
    Document doc;
    doc.width = 40000;
    doc.height = 200;
    doc.meshes.push_back(makeCurvedMesh(200, 2, 12345.67891, 20.123456, 20000.0004, 150, 0.3, 5));
    const std::string svg = encodeSvg(doc, editable());
    const std::string head = "fill:url(#m0) none\" d=\"";
    const size_t at = svg.find(head);
    REQUIRE(at != std::string::npos);
    const std::string d = svg.substr(at + head.size(), svg.find('"', at + head.size()) - at - head.size());
    CHECK(d.find('C') == std::string::npos);  // relative cubics only
    CHECK(d.find('c') != std::string::npos);
    // Read back as a flat shape's path: one subpath whose points are the boundary's corners
    // and handles, in order around the grid.
    const Document back = decodeSvg(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 40000 200\">"
        "<path fill=\"#000000\" d=\"" + d + "\"/></svg>",
        ReadLimits{});
    REQUIRE(back.shapes.size() == 1);
    REQUIRE(back.shapes[0].subpaths.size() == 1);
    const std::vector<Vec2>& path = back.shapes[0].subpaths[0];
    const GradientMesh& mesh = doc.meshes[0];
    const int C = mesh.columns(), R = mesh.rows();
    // Every boundary node lies on the outline: a cubic's end point, or on a line (straight runs
    // of patches are one line).
    REQUIRE(path.size() % 3 == 0);
    REQUIRE(path.size() <= size_t(3 * (2 * C + 2 * R)));
    auto distanceToOutline = [&](Vec2 p) {
        double best = INFINITY;
        for (size_t k = 0; k < path.size(); k += 3) {
            const Vec2 a = path[k], b = path[(k + 3) % path.size()];
            best = std::min(best, norm(p - a));
            const Vec2 d = b - a;
            const bool line = norm(path[k + 1] - (a + (1.0 / 3) * d)) < 1e-3 &&
                              norm(path[k + 2] - (a + (2.0 / 3) * d)) < 1e-3;
            const double len2 = dot(d, d);
            if (!line || len2 == 0) continue;
            const double t = std::clamp(dot(p - a, d) / len2, 0.0, 1.0);
            best = std::min(best, norm(p - (a + t * d)));
        }
        return best;
    };
    double worst = 0;
    for (int i = 0; i <= C; ++i)
        for (int j : {0, R}) worst = std::max(worst, distanceToOutline(mesh.node(i, j).pos));
    for (int j = 0; j <= R; ++j)
        for (int i : {0, C}) worst = std::max(worst, distanceToOutline(mesh.node(i, j).pos));
    CHECK(worst <= 0.005 * std::sqrt(2.0) + 1e-9);  // half a 1/100 px step along each axis
}

// How far a patch-local derivative `d` may come back from the compact syntax. Corners are
// written to 1/100 px and handles to 1/10 px relative to their edge's start as read; a
// derivative is 3× (handle − corner), so each rounding counts three times. And the reader
// takes the knot ratios from the lengths of rounded handles (about 20 px here, so within about
// 0.3 %), and a node's derivative is the mean of its two sides scaled by them.
double handleTolerance(Vec2 d) { return 3 * (0.05 + 0.005) + 0.003 * norm(d); }

TEST_CASE("bicubic svg reads back to the same grid", "[svg][roundtrip]") {
    const Document doc = svgtest::curvedDocument();
    const GradientMesh& a = doc.meshes[0];
    const Document back = decodeSvg(encodeSvg(doc, editable()), ReadLimits{});
    REQUIRE(back.meshes.size() == 1);
    const GradientMesh& b = back.meshes[0];
    REQUIRE(b.columns() == a.columns());
    REQUIRE(b.rows() == a.rows());
    CHECK(back.width == doc.width);
    CHECK(back.height == doc.height);
    double pos = 0, col = 0, handle = 0, excess = 0;
    for (int j = 0; j <= a.rows(); ++j)
        for (int i = 0; i <= a.columns(); ++i) {
            pos = std::max(pos, maxDistance(a.node(i, j).pos, b.node(i, j).pos));
            col = std::max(col, maxDifference(a.node(i, j).col, b.node(i, j).col));
        }
    // Edge handles (local derivatives) are what the file holds; knots may be rescaled.
    for (int j = 0; j < a.rows(); ++j)
        for (int i = 0; i < a.columns(); ++i) {
            const PatchHermite ha = patchHermite(a, i, j), hb = patchHermite(b, i, j);
            for (int c = 0; c < 4; ++c) {
                const HermiteCorner &x = ha.corner[c / 2][c % 2], &y = hb.corner[c / 2][c % 2];
                for (const auto& [d, e] : {std::pair{x.posS, y.posS}, std::pair{x.posT, y.posT}}) {
                    handle = std::max(handle, maxDistance(d, e));
                    excess = std::max(excess, maxDistance(d, e) - handleTolerance(d));
                }
            }
        }
    std::printf("[svg figures] bicubic round trip: corners within %.4f px, derivatives within "
                "%.4f px\n", pos, handle);
    CHECK(pos <= 0.005 + 1e-9);
    CHECK(col <= 0.5 / 255 + 1e-9);
    CHECK(excess <= 0);
    CHECK(b.colorModel == ColorModel::Bicubic);
}

TEST_CASE("exact svg reads back to refined pieces that render like the original",
          "[svg][roundtrip]") {
    for (const Document& doc : {svgtest::curvedDocument(), svgtest::holedDocument()}) {
        SvgEncodeStats stats;
        const std::string svg = encodeSvg(doc, exactColors(), &stats);
        const Document back = decodeSvg(svg, ReadLimits{});
        const int pieces = doc.meshes[0].holeCount() + 1;
        CHECK(back.meshes.size() == size_t(pieces));
        CHECK(stats.meshGradients == pieces);
        int64_t patches = 0;
        for (const GradientMesh& m : back.meshes) patches += m.patchCount();
        CHECK(patches == stats.svgPatches);
        const RgbaImage ours = svgtest::renderOurs(doc, true);
        const RgbaImage theirs = svgtest::renderOverWhite(back, true);
        const gmtest::DiffStats d = gmtest::compareInterior(ours, theirs, 1);
        std::printf("[svg figures] exact round trip (%d hole(s)): %lld SVG patches for %d, max k %d, "
                    "re-render mean %.4f max %.4f (0-255), %.1f bytes per original patch\n",
                    doc.meshes[0].holeCount(), static_cast<long long>(stats.svgPatches),
                    doc.meshes[0].patchCount(), stats.maxSubdivision, d.mean, d.max,
                    double(svg.size()) / doc.meshes[0].patchCount());
        CHECK(d.count > 1000);
        CHECK(d.max <= 1.0);
    }
}

// The number in attribute `name` of the first element `tag` of `svg`.
double firstAttribute(const std::string& svg, const std::string& tag, const std::string& name) {
    const size_t element = svg.find("<" + tag + " ");
    REQUIRE(element != std::string::npos);
    const size_t at = svg.find(" " + name + "=\"", element);
    REQUIRE(at < svg.find('>', element));
    return std::stod(svg.substr(at + name.size() + 3));
}

TEST_CASE("svg grows each mesh beyond its outline path, and reads back the mesh it had",
          "[svg][roundtrip]") {
    // Inkscape paints a mesh only at pixel centres its patches cover; the outline path, which
    // it anti-aliases, stays where the mesh ends.
    const Document doc = svgtest::curvedDocument();
    const std::string svg = encodeSvg(doc, editable());
    CHECK(countOf(svg, " data-outset=\"0.7\"") == 1);
    CHECK(countOf(svg, "data-outset-held") == 0);
    const GradientMesh& mesh = doc.meshes[0];
    const Vec2 corner = mesh.node(0, 0).pos, inner = mesh.node(1, 1).pos;
    const Vec2 written{firstAttribute(svg, "meshgradient", "x"), firstAttribute(svg, "meshgradient", "y")};
    CHECK(std::fabs(norm(written - corner) - 0.7) <= 0.01);
    CHECK(dot(written - corner, corner - inner) > 0);  // outward
    const Document back = decodeSvg(svg, ReadLimits{});
    CHECK(maxDistance(back.meshes[0].node(0, 0).pos, corner) <= 0.005 + 1e-9);

    // Pieces of a holed mesh hold the edges where they meet, and say which.
    const Document holed = svgtest::holedDocument();
    const std::string pieces = encodeSvg(holed, editable());
    CHECK(countOf(pieces, " data-outset=\"0.7\"") == 4);
    CHECK(countOf(pieces, "data-outset-held=\"bottom ") == 1);
    CHECK(countOf(pieces, "data-outset-held=\"top ") == 3);
    CHECK(countOf(pieces, " bottom ") == 2);
}

// The values of every `name` attribute in `svg`, in order.
std::vector<std::string> attributeValues(const std::string& svg, const std::string& name) {
    std::vector<std::string> out;
    const std::string key = " " + name + "=\"";
    for (size_t at = svg.find(key); at != std::string::npos; at = svg.find(key, at + 1)) {
        const size_t from = at + key.size();
        out.push_back(svg.substr(from, svg.find('"', from) - from));
    }
    return out;
}

TEST_CASE("pieces of a holed mesh read back and written again keep their seams", "[svg][roundtrip]") {
    // Read back, the pieces are meshes of their own; the writer finds their seams again (the
    // edges one piece's top row shares with another's bottom row), holds and bands them.
    const std::string first = encodeSvg(svgtest::holedDocument(), editable());
    const Document back = decodeSvg(first, ReadLimits{});
    const std::string second = encodeSvg(back, editable());
    CHECK(attributeValues(second, "data-outset-held") == attributeValues(first, "data-outset-held"));
    CHECK(countOf(second, "<path ") == countOf(first, "<path "));
    const Document again = decodeSvg(second, ReadLimits{});
    const gmtest::DiffStats d =
        gmtest::compareInterior(svgtest::renderOurs(back), svgtest::renderOverWhite(again), 1);
    std::printf("[svg figures] holed pieces written again: re-render mean %.4f max %.4f\n", d.mean, d.max);
    CHECK(d.max <= 4.0);
}

TEST_CASE("svg writes a mesh with holes as its legacy pieces", "[svg]") {
    const Document doc = svgtest::holedDocument();
    const std::string svg = encodeSvg(doc, editable());
    CHECK(countOf(svg, "<meshgradient") == 4);
    CHECK(countOf(svg, "<path ") == 4);
    const Document back = decodeSvg(svg, ReadLimits{});
    REQUIRE(back.meshes.size() == 4);
    int rows = 0;
    for (const GradientMesh& m : back.meshes) {
        CHECK(m.columns() == doc.meshes[0].columns());
        CHECK(m.holeCount() == 0);
        rows += m.rows();
    }
    CHECK(rows == doc.meshes[0].rows());
    // Legacy pieces render like the whole.
    const gmtest::DiffStats d =
        gmtest::compareInterior(svgtest::renderOurs(doc), svgtest::renderOverWhite(back), 1);
    std::printf("[svg figures] editable legacy round trip re-render: mean %.4f max %.4f\n", d.mean, d.max);
}

// Pixels within 1 px of the grid rows where `mesh` has slits (where its SVG pieces meet), over
// the whole width of the mesh, that are opaque in `mask` (the mesh's own render) and where
// `pieces` differs from `whole` (both over white) by more than `threshold` (0–1) in a channel.
size_t differingAlongSlitRows(const GradientMesh& mesh, const RgbaImage& mask, const RgbaImage& whole,
                              const RgbaImage& pieces, float threshold) {
    std::vector<char> near(static_cast<size_t>(whole.width) * whole.height, 0);
    for (const Slit& slit : mesh.slits)
        for (int i = 0; i < mesh.columns(); ++i) {
            const BezierPatch bz = toBezier(mesh, i, slit.row);  // its top edge is the cut row
            for (int k = 0; k <= 64; ++k) {
                const double t = k / 64.0, u = 1 - t;
                const Vec2 p = u * u * u * bz.p[0][0] + 3 * u * u * t * bz.p[1][0] +
                               3 * u * t * t * bz.p[2][0] + t * t * t * bz.p[3][0];
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int x = static_cast<int>(std::floor(p.x)) + dx, y = static_cast<int>(std::floor(p.y)) + dy;
                        if (x >= 0 && y >= 0 && x < whole.width && y < whole.height)
                            near[static_cast<size_t>(y) * whole.width + x] = 1;
                    }
            }
        }
    size_t differing = 0;
    for (int y = 0; y < whole.height; ++y)
        for (int x = 0; x < whole.width; ++x) {
            if (!near[static_cast<size_t>(y) * whole.width + x] || mask.at(x, y)[3] < 1.0f) continue;
            bool differs = false;
            for (int c = 0; c < 3; ++c) differs = differs || std::fabs(whole.at(x, y)[c] - pieces.at(x, y)[c]) > threshold;
            differing += differs;
        }
    return differing;
}

TEST_CASE("a mesh with holes read back from its SVG pieces renders without seams where they meet", "[svg]") {
    // The pieces share their cut rows; drawn one by one, each anti-aliased its side of them and
    // the background showed through a faint line along every cut row.
    Document doc = svgtest::holedDocument();
    GradientMesh& mesh = doc.meshes[0];
    // Bicubic colours (what the SVG holds exactly), and the mesh turned by 3° about a point
    // off the pixel grid, so that no cut row runs along pixel boundaries.
    mesh.colorModel = ColorModel::Bicubic;
    const double c = std::cos(0.05), s = std::sin(0.05);
    auto turn = [&](Vec2 v, bool point) {
        return Vec2{c * v.x - s * v.y + (point ? 12.37 : 0), s * v.x + c * v.y + (point ? -6.21 : 0)};
    };
    auto adjust = [&](Node& n) {
        n.pos = turn(n.pos, true);
        n.posU = turn(n.posU, false);
        n.posV = turn(n.posV, false);
        n.colU = n.colV = Vec3{};
    };
    for (Node& n : mesh.nodes) adjust(n);
    for (Slit& slit : mesh.slits) {
        for (Node& n : slit.below) adjust(n);
        slit.left.posU = turn(slit.left.posU, false);
        slit.right.posU = turn(slit.right.posU, false);
        slit.left.colU = slit.right.colU = Vec3{};
    }
    const Document back = decodeSvg(encodeSvg(doc, editable()), ReadLimits{});
    REQUIRE(back.meshes.size() == 4);
    const RgbaImage mask = renderDocument(doc).image;
    RgbaImage whole = mask, pieces = renderDocument(back).image;
    gm::compositeOver(whole, {1, 1, 1, 1});
    gm::compositeOver(pieces, {1, 1, 1, 1});
    const size_t differing = differingAlongSlitRows(doc.meshes[0], mask, whole, pieces, 4.0f / 255);
    std::printf("[svg figures] pieces of a holed mesh: %zu px along the cut rows differ by more than 4/255\n",
                differing);
    CHECK(differing == 0);
    // Pieces drawn alone (no neighbour to join) keep their own anti-aliased outline.
    Document first = back;
    first.meshes.resize(1);
    const RgbaImage alone = renderDocument(first).image;
    size_t partial = 0;
    for (size_t k = 3; k < alone.pixels.size(); k += 4) partial += alone.pixels[k] > 0 && alone.pixels[k] < 1;
    CHECK(partial > 0);
}

TEST_CASE("svg format is registered and writes atomically", "[svg]") {
    const MeshFormat* f = FormatRegistry::builtin().forPath("x.SVG");
    REQUIRE(f);
    CHECK(f->name() == "svg");
    const std::string path = svgtest::tmpPath("registered.svg");
    f->write(svgtest::curvedDocument(), path, WriteOptions{});
    CHECK(FormatRegistry::builtin().forReading(path) == f);
    const Document back = f->read(path, ReadOptions{});
    CHECK(back.meshes.size() == 1);
    WriteOptions bad;
    bad.svgColors = "pretty";
    CHECK_THROWS_AS(f->write(svgtest::curvedDocument(), svgtest::tmpPath("bad.svg"), bad), Error);
    std::ifstream gone(svgtest::tmpPath("bad.svg"));
    CHECK(!gone.good());
}

TEST_CASE("svg reader takes hand-written and Inkscape-style meshgradients", "[svg]") {
    const Document d = decodeSvg(svgWith(kOnePatch), ReadLimits{});
    REQUIRE(d.meshes.size() == 1);
    const GradientMesh& m = d.meshes[0];
    CHECK(maxDistance(m.node(0, 0).pos, {10, 10}) == 0);
    CHECK(maxDistance(m.node(1, 1).pos, {60, 60}) == 0);
    CHECK(maxDifference(m.node(0, 0).col, {1, 0, 0}) == 0);
    CHECK(maxDifference(m.node(1, 0).col, {0, 1, 0}) == 0);
    CHECK(maxDifference(m.node(1, 1).col, {0, 0, 1}) == 0);
    CHECK(maxDifference(m.node(0, 1).col, {1, 1, 1}) == 0);

    // Absolute commands, a gradientTransform and an href to the gradient holding the rows.
    const std::string linked =
        "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" "
        "width=\"100\" height=\"100\"><defs>"
        "<meshgradient id=\"rows\"><meshrow><meshpatch>"
        "<stop path=\"C 20,10 50,10 60,10\" stop-color=\"#ff0000\"/>"
        "<stop path=\"L 60,60\" stop-color=\"#00ff00\"/>"
        "<stop path=\"l -50,0\" stop-color=\"#0000ff\"/>"
        "<stop path=\"c 0,-20 0,-30\" stop-color=\"#ffffff\"/>"
        "</meshpatch></meshrow></meshgradient>"
        "<meshgradient id=\"use\" xlink:href=\"#rows\" gradientUnits=\"userSpaceOnUse\" x=\"10\" "
        "y=\"10\" gradientTransform=\"translate(5,-2)\"/></defs>"
        "<g transform=\"scale(1)\"><path d=\"M0 0\" style=\"fill:url(#use)\"/></g></svg>";
    const Document e = decodeSvg(linked, ReadLimits{});
    REQUIRE(e.meshes.size() == 1);
    CHECK(maxDistance(e.meshes[0].node(0, 0).pos, {15, 8}) < 1e-12);
    CHECK(maxDistance(e.meshes[0].node(1, 1).pos, {65, 58}) < 1e-12);
}

TEST_CASE("svg reader refuses malformed input with a clear error", "[svg][malformed]") {
    requireErrorMentioning("this is not xml", "XML");
    requireErrorMentioning("<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0 0\"/></svg>",
                           "no meshgradient");
    requireErrorMentioning("<html/>", "not <svg>");
    // Wrong stop count (3 on the first patch).
    requireErrorMentioning(svgWith("<meshrow><meshpatch><stop path=\"l 10,0\"/><stop path=\"l "
                                   "0,10\"/><stop path=\"l -10,0\"/></meshpatch></meshrow>"),
                           "3 stops, expected 4");
    // A path with two commands.
    std::string two = kOnePatch;
    two.replace(two.find("l 0,50"), 6, "l 0,50 l 1,1");
    requireErrorMentioning(svgWith(two), "more than one command");
    std::string bad = kOnePatch;
    bad.replace(bad.find("#ff0000"), 7, "#ff00zz");
    requireErrorMentioning(svgWith(bad), "bad stop-color");
    for (const char* absurd : {"1e308", "nan", "inf", "1e9", "0x10"}) {
        std::string s = kOnePatch;
        s.replace(s.find("40,0"), 2, absurd);
        requireErrorMentioning(svgWith(s), "stop path");
    }
    requireErrorMentioning(svgWith("", " gradientTransform=\"matrix(1,0,0,1,1e300,0)\""),
                           "no meshrow");
    requireErrorMentioning(svgWith(kOnePatch, " gradientTransform=\"matrix(1,0,0,1,1e300,0)\""),
                           "out of range");
    requireErrorMentioning(svgWith(kOnePatch, " gradientTransform=\"warp(2)\""),
                           "unsupported transform");
    std::string noUnits = svgWith(kOnePatch);
    noUnits.replace(noUnits.find("gradientUnits=\"userSpaceOnUse\""), 30, "");
    requireErrorMentioning(noUnits, "userSpaceOnUse");
    // Rows of different lengths.
    std::string ragged = svgWith(std::string(kOnePatch) +
                                 "<meshrow><meshpatch><stop path=\"l 0,1\"/><stop path=\"l "
                                 "1,0\"/><stop path=\"l 0,-1\"/></meshpatch><meshpatch><stop "
                                 "path=\"l 0,1\"/><stop path=\"l 1,0\"/></meshpatch></meshrow>");
    requireErrorMentioning(ragged, "the first row has 1");
    // The writer's outset (data-outset, data-outset-held), out of range or naming no column.
    requireErrorMentioning(svgWith(kOnePatch, " data-outset=\"-1\""), "data-outset must lie");
    requireErrorMentioning(svgWith(kOnePatch, " data-outset=\"50\""), "data-outset must lie");
    requireErrorMentioning(svgWith(kOnePatch, " data-outset=\"wide\""), "not a number");
    for (const char* held : {"top 1", "left 0", "0", "bottom 0-", "top 0 - 0", "top 99999999999"})
        requireErrorMentioning(
            svgWith(kOnePatch, std::string(" data-outset=\".7\" data-outset-held=\"") + held + "\""),
            "data-outset-held must read like");
}

TEST_CASE("svg reader refuses hostile XML", "[svg][malformed]") {
    SECTION("deep nesting does not overflow the stack") {
        std::string deep = "<svg xmlns=\"http://www.w3.org/2000/svg\">";
        for (int k = 0; k < 100000; ++k) deep += "<g>";
        for (int k = 0; k < 100000; ++k) deep += "</g>";
        deep += "</svg>";
        requireErrorMentioning(deep, "nested deeper");
    }
    SECTION("entity declarations (billion laughs)") {
        std::string lol = "<?xml version=\"1.0\"?>\n<!DOCTYPE svg [\n<!ENTITY lol \"lol\">\n";
        for (int k = 1; k < 10; ++k)
            lol += "<!ENTITY lol" + std::to_string(k) + " \"" +
                   std::string(10, '&') + "\">\n";
        lol += "]>\n<svg xmlns=\"http://www.w3.org/2000/svg\">&lol9;</svg>";
        requireErrorMentioning(lol, "entities");
    }
    SECTION("href cycle") {
        const std::string cyc =
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"><defs>"
            "<meshgradient id=\"a\" href=\"#b\"/><meshgradient id=\"b\" href=\"#a\"/></defs>"
            "<path d=\"M0 0\" fill=\"url(#a)\"/></svg>";
        requireErrorMentioning(cyc, "cycle");
    }
    SECTION("element count and file size limits") {
        std::string many = "<svg xmlns=\"http://www.w3.org/2000/svg\">";
        many.reserve(9u << 22);
        for (uint64_t k = 0; k <= SvgReadLimits::maxElements; ++k) many += "<g/>";
        many += "</svg>";
        requireErrorMentioning(many, "tags, over the limit");
    }
    SECTION("a 50 MB file over a reader limit") {
        const std::string path = svgtest::tmpPath("big.svg");
        {
            std::ofstream f(path, std::ios::binary);
            f << "<svg xmlns=\"http://www.w3.org/2000/svg\">";
            const std::string chunk(1 << 20, ' ');
            for (int k = 0; k < 50; ++k) f << chunk;
            f << "</svg>";
        }
        ReadOptions o;
        o.limits.maxFileBytes = 16u << 20;
        const MeshFormat* f = FormatRegistry::builtin().byName("svg");
        REQUIRE(f);
        try {
            f->read(path, o);
            FAIL("a 50 MB file was read");
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find("over the limit") != std::string::npos);
        }
        std::remove(path.c_str());
    }
}
