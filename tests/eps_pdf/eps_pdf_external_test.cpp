// Our EPS and PDF files rendered by programs nobody here wrote (Ghostscript, poppler's cairo
// backend), compared with our own renderer.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>

#include "eps_pdf_test_support.h"
#include "formats/mesh_shading.h"
#include "formats/raster.h"
#include "formats/registry.h"
#include "meshcore/render.h"
#include "support/compare.h"

using namespace gm;
using namespace epstest;
using gmtest::quote;
using gmtest::runCommand;

namespace {

void writeAs(const Document& doc, const std::string& path, const WriteOptions& options = {}) {
    FormatRegistry::builtin().forPath(path)->write(doc, path, options);
}

RgbaImage ghostscript(const std::string& input, const std::string& png) {
    std::remove(png.c_str());
    const std::string dsc =
        input.size() > 4 && input.substr(input.size() - 4) == ".eps" ? " -dEPSCrop" : "";
    const std::string command = "gs -q -dSAFER -dBATCH -dNOPAUSE -sDEVICE=png16m -r72" + dsc +
                                " -sOutputFile=" + quote(png) + " " + quote(input) + " 2>&1";
    REQUIRE(runCommand(command) == 0);
    return readImage(png);
}

RgbaImage pdftocairo(const std::string& pdf, const std::string& pngBase) {
    std::remove((pngBase + ".png").c_str());
    REQUIRE(runCommand("pdftocairo -png -r 72 -singlefile " + quote(pdf) + " " + quote(pngBase)) ==
            0);
    return readImage(pngBase + ".png");
}

std::string commandOutput(const std::string& command) {
    std::string out;
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    REQUIRE(pipe);
    char buf[4096];
    for (size_t n; (n = fread(buf, 1, sizeof buf, pipe.get())) > 0;) out.append(buf, n);
    return out;
}

// Our render, straight alpha: compareInterior takes the interior from its alpha, and interior
// pixels are opaque, so no background is needed there.
RgbaImage ourRender(const Document& doc) { return renderDocument(doc).image; }

// Pixels that we leave uncovered (alpha 0 within 1 px all round: outside every mesh, or in a
// hole) that the consumer painted anything but background.
size_t paintedWhereUncovered(const RgbaImage& oursStraight, const RgbaImage& theirs) {
    size_t bad = 0;
    for (int y = 1; y + 1 < oursStraight.height; ++y) {
        for (int x = 1; x + 1 < oursStraight.width; ++x) {
            bool empty = true;
            for (int dy = -1; dy <= 1 && empty; ++dy)
                for (int dx = -1; dx <= 1 && empty; ++dx)
                    empty = oursStraight.at(x + dx, y + dy)[3] == 0.f;
            if (!empty) continue;
            const float* p = theirs.at(x, y);
            if (p[0] < 0.99f || p[1] < 0.99f || p[2] < 0.99f) ++bad;
        }
    }
    return bad;
}

// Centres of the holes of a mesh: midway between a slit's upper and lower node copies.
std::vector<Vec2> holeCentres(const GradientMesh& mesh) {
    std::vector<Vec2> centres;
    for (const Slit& s : mesh.slits) {
        const int i = (s.i0 + s.i1) / 2;
        const Vec2 up = mesh.node(i, s.row).pos,
                   low = s.below[static_cast<size_t>(i - s.i0 - 1)].pos;
        centres.push_back(0.5 * (up + low));
    }
    return centres;
}

}  // namespace

TEST_CASE("corner colours and point order are right in Ghostscript and cairo",
          "[eps][pdf][external]") {
    // Red, green, blue and white corners on a patch with curved edges: any mix-up of the point
    // or colour order moves colours by far more than the limits below (a transposed point order
    // measured mean 54, max 230 here).
    Document doc;
    doc.width = 200;
    doc.height = 160;
    GradientMesh m(1, 1);
    m.node(0, 0).pos = {20, 20};
    m.node(1, 0).pos = {180, 30};
    m.node(0, 1).pos = {30, 140};
    m.node(1, 1).pos = {170, 150};
    m.node(0, 0).col = {1, 0, 0};
    m.node(1, 0).col = {0, 1, 0};
    m.node(0, 1).col = {0, 0, 1};
    m.node(1, 1).col = {1, 1, 1};
    for (Node& n : m.nodes) {
        n.posU = {150, 0};
        n.posV = {0, 120};
    }
    m.node(0, 0).posU = {150, 60};
    m.node(1, 0).posV = {-60, 120};
    m.node(0, 1).posU = {150, -50};
    doc.meshes.push_back(m);
    const BezierPatch b = toBezier(m, 0, 0);

    // One unsplit patch (tolerance 1): the consumer must show the bilinear mix of the corner
    // colours at each point of the exact Bézier geometry.
    WriteOptions whole;
    whole.colorTolerance = 1.0;
    writeAs(doc, tmpPath("order.eps"), whole);
    writeAs(doc, tmpPath("order.pdf"), whole);
    const RgbaImage images[] = {ghostscript(tmpPath("order.eps"), tmpPath("order_gs.png")),
                                pdftocairo(tmpPath("order.pdf"), tmpPath("order_cairo"))};
    for (const RgbaImage& img : images) {
        REQUIRE(img.width == 200);
        REQUIRE(img.height == 160);
        double sum = 0, worst = 0;
        int n = 0;
        for (int i = 1; i < 20; ++i) {
            for (int j = 1; j < 20; ++j) {
                const double s = i / 20.0, t = j / 20.0;
                const Vec2 p = bezierPosition(b, s, t);
                const Vec3 c = (1 - s) * (1 - t) * b.c[0][0] + s * (1 - t) * b.c[3][0] +
                               (1 - s) * t * b.c[0][3] + s * t * b.c[3][3];
                const float* px = img.at(int(p.x), int(p.y));
                for (int ch = 0; ch < 3; ++ch) {
                    const double e = std::fabs(px[ch] - c[ch]) * 255;
                    sum += e;
                    worst = std::max(worst, e);
                }
                ++n;
            }
        }
        INFO("mean " << sum / (3 * n) << " max " << worst);
        CHECK(sum / (3 * n) <= 2.0);
        CHECK(worst <= 16);
    }

    // Exact colour (default tolerance) against our renderer.
    writeAs(doc, tmpPath("order_exact.eps"));
    writeAs(doc, tmpPath("order_exact.pdf"));
    const RgbaImage ours = ourRender(doc);
    const gmtest::DiffStats gs = gmtest::compareInterior(
        ours, ghostscript(tmpPath("order_exact.eps"), tmpPath("oe_gs.png")), 1);
    const gmtest::DiffStats cairo = gmtest::compareInterior(
        ours, pdftocairo(tmpPath("order_exact.pdf"), tmpPath("oe_cairo")), 1);
    std::printf("asymmetric patch: gs EPS mean %.3f max %.1f; pdftocairo PDF mean %.3f max %.1f\n",
                gs.mean, gs.max, cairo.mean, cairo.max);
    CHECK(gs.count > 10000);
    CHECK(gs.mean <= 2.0);
    CHECK(gs.max <= 16);
    CHECK(cairo.mean <= 2.0);
    CHECK(cairo.max <= 16);
}

TEST_CASE("Ghostscript on our EPS and pdftocairo on our PDF match our renderer",
          "[eps][pdf][external]") {
    for (const NamedDocument& nd : externalTestDocuments()) {
        SECTION(nd.name) {
            const Document& doc = nd.doc;
            const RgbaImage ours = ourRender(doc);
            const std::string eps = tmpPath("ext_" + nd.name + ".eps");
            const std::string pdf = tmpPath("ext_" + nd.name + ".pdf");
            writeAs(doc, eps);
            writeAs(doc, pdf);

            const RgbaImage gsEps = ghostscript(eps, tmpPath("ext_" + nd.name + "_gs.png"));
            const RgbaImage cairoPdf = pdftocairo(pdf, tmpPath("ext_" + nd.name + "_cairo"));
            const RgbaImage gsPdf = ghostscript(pdf, tmpPath("ext_" + nd.name + "_gspdf.png"));
            const gmtest::DiffStats a = gmtest::compareInterior(ours, gsEps, 1);
            const gmtest::DiffStats c = gmtest::compareInterior(ours, cairoPdf, 1);
            const gmtest::DiffStats g = gmtest::compareInterior(ours, gsPdf, 1);
            std::printf(
                "%-8s %4d patches: gs EPS mean %.3f max %.1f | pdftocairo PDF mean %.3f "
                "max %.1f | gs PDF mean %.3f max %.1f (%zu interior pixels)\n",
                nd.name.c_str(), doc.meshes[0].patchCount(), a.mean, a.max, c.mean, c.max, g.mean,
                g.max, a.count);
            CHECK(a.count > 20000);
            CHECK(a.mean <= 2.0);
            CHECK(a.max <= 16);
            CHECK(c.mean <= 2.0);
            CHECK(c.max <= 16);
            CHECK(g.mean <= 2.0);
            CHECK(g.max <= 16);

            // Holes and the outside stay background.
            CHECK(paintedWhereUncovered(ours, gsEps) == 0);
            CHECK(paintedWhereUncovered(ours, cairoPdf) == 0);
            for (const Vec2& centre : holeCentres(doc.meshes[0])) {
                const int x = int(centre.x), y = int(centre.y);
                CHECK(ours.at(x, y)[3] == 0.f);
                for (const RgbaImage* img : {&gsEps, &cairoPdf}) {
                    const float* p = img->at(x, y);
                    CHECK((p[0] == 1.f && p[1] == 1.f && p[2] == 1.f));
                }
            }

            // pdfinfo reads the file without complaint.
            const std::string info = commandOutput("pdfinfo " + quote(pdf) + " 2>&1");
            CHECK(info.find("Pages:           1") != std::string::npos);
            CHECK(info.find("Error") == std::string::npos);
            CHECK(info.find("Warning") == std::string::npos);
            CHECK(info.find("Page size:       " + std::to_string(doc.width) + " x " +
                            std::to_string(doc.height) + " pts") != std::string::npos);
        }
    }
}

TEST_CASE("text and binary DataSource render the same; binary is much smaller", "[eps][external]") {
    for (const NamedDocument& nd : externalTestDocuments()) {
        SECTION(nd.name) {
            const Document& doc = nd.doc;
            WriteOptions text;
            text.textShading = true;
            const std::string binPath = tmpPath("ds_" + nd.name + "_bin.eps");
            const std::string textPath = tmpPath("ds_" + nd.name + "_text.eps");
            const std::string pdfPath = tmpPath("ds_" + nd.name + ".pdf");
            writeAs(doc, binPath);
            writeAs(doc, textPath, text);
            writeAs(doc, pdfPath);
            const RgbaImage ours = ourRender(doc);
            const RgbaImage bin = ghostscript(binPath, tmpPath("ds_" + nd.name + "_bin.png"));
            const RgbaImage txt = ghostscript(textPath, tmpPath("ds_" + nd.name + "_text.png"));
            const gmtest::DiffStats d = gmtest::compareInterior(ours, txt, 1);
            CHECK(d.mean <= 2.0);
            CHECK(d.max <= 16);
            // Against each other: the same patches to within 1e-4 px and 1e-6 colour.
            double sum = 0, worst = 0;
            for (size_t k = 0; k < bin.pixels.size(); ++k) {
                const double e = std::fabs(bin.pixels[k] - txt.pixels[k]) * 255;
                sum += e;
                worst = std::max(worst, e);
            }
            const double meanBetween = sum / bin.pixels.size();
            CHECK(meanBetween <= 0.05);

            const double patches = doc.meshes[0].patchCount();
            size_t pieces = 0;
            for (const MeshShading& s : buildMeshShadings(doc, WriteOptions{}))
                pieces += s.patches.size();
            const double binBytes = readFile(binPath).size(), textBytes = readFile(textPath).size(),
                         pdfBytes = readFile(pdfPath).size();
            std::printf(
                "%-8s %4.0f patches (%zu written after colour split): bytes/patch EPS "
                "binary %.1f, EPS text %.1f, PDF %.1f; text vs binary render mean %.4f max "
                "%.1f\n",
                nd.name.c_str(), patches, pieces, binBytes / patches, textBytes / patches,
                pdfBytes / patches, meanBetween, worst);
            CHECK(binBytes * 2 < textBytes);
        }
    }
}

TEST_CASE("legacy pieces render like the whole mesh", "[eps][pdf][external]") {
    const NamedDocument nd = externalTestDocuments()[0];
    REQUIRE(nd.doc.meshes[0].holeCount() >= 3);
    WriteOptions legacy;
    legacy.legacy = true;
    const std::string eps = tmpPath("legacy_ext.eps"), pdf = tmpPath("legacy_ext.pdf");
    writeAs(nd.doc, eps, legacy);
    writeAs(nd.doc, pdf, legacy);
    const RgbaImage ours = ourRender(nd.doc);
    const RgbaImage gsEps = ghostscript(eps, tmpPath("legacy_ext_gs.png"));
    const RgbaImage cairoPdf = pdftocairo(pdf, tmpPath("legacy_ext_cairo"));
    const gmtest::DiffStats a = gmtest::compareInterior(ours, gsEps, 1);
    const gmtest::DiffStats c = gmtest::compareInterior(ours, cairoPdf, 1);
    std::printf("legacy %s: gs EPS mean %.3f max %.1f | pdftocairo PDF mean %.3f max %.1f\n",
                nd.name.c_str(), a.mean, a.max, c.mean, c.max);
    CHECK(a.mean <= 2.0);
    CHECK(a.max <= 16);
    CHECK(c.mean <= 2.0);
    CHECK(c.max <= 16);
    CHECK(paintedWhereUncovered(ours, gsEps) == 0);
    CHECK(paintedWhereUncovered(ours, cairoPdf) == 0);
}

TEST_CASE("exact colour on small patches: pieces of a pixel are as faithful and far fewer",
          "[eps][pdf][external]") {
    // A whole image's meshes have patches of a few pixels with fitted colour far from bilinear
    // (fruits.jpg whole: most of 4-5 px, each cut ~13x13 at 0.5/255). Here 24 x 24 patches of
    // 4 px with random colour, slopes included (within 0-1: the formats clamp corner colours).
    Document doc;
    doc.width = doc.height = 104;
    GradientMesh m(24, 24);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(0.25, 0.75), S(-0.5, 0.5);
    for (int j = 0; j <= 24; ++j)
        for (int i = 0; i <= 24; ++i) {
            Node& n = m.node(i, j);
            n.pos = {4.0 + 4 * i, 4.0 + 4 * j};
            n.posU = {4, 0};
            n.posV = {0, 4};
            n.col = {U(rng), U(rng), U(rng)};
            n.colU = {S(rng), S(rng), S(rng)};
            n.colV = {S(rng), S(rng), S(rng)};
        }
    doc.meshes.push_back(m);
    const RgbaImage ours = ourRender(doc);
    // At 0.5/255, where the unlimited pieces are many (the default 1/255 halves them).
    WriteOptions limited;
    limited.colorTolerance = 0.5 / 255;
    WriteOptions unlimited = limited;
    unlimited.minPiece = 0;
    const std::string pieces = tmpPath("small_patches.pdf"), all = tmpPath("small_patches_all.pdf");
    writeAs(doc, pieces, limited);
    writeAs(doc, all, unlimited);
    const size_t bytes = std::filesystem::file_size(pieces),
                 bytesAll = std::filesystem::file_size(all);
    // Each consumer against our render, with 1-px pieces and with pieces as small as exact
    // colour asks. This content changes colour every few pixels, so where a consumer puts a
    // pixel's sample shows (Ghostscript paints every pixel a piece touches, and is ~8 off
    // either way); the pieces must not make either consumer notably worse.
    const double
        gsPieces = gmtest::compareInterior(ours, ghostscript(pieces, tmpPath("sp_gs.png")), 1).mean,
        gsAll = gmtest::compareInterior(ours, ghostscript(all, tmpPath("spa_gs.png")), 1).mean,
        cairoPieces =
            gmtest::compareInterior(ours, pdftocairo(pieces, tmpPath("sp_cairo")), 1).mean,
        cairoAll = gmtest::compareInterior(ours, pdftocairo(all, tmpPath("spa_cairo")), 1).mean;
    std::printf(
        "4-px patches: PDF %zu B with 1-px pieces (gs mean %.3f, pdftocairo %.3f), %zu B "
        "unlimited (gs %.3f, pdftocairo %.3f)\n",
        bytes, gsPieces, cairoPieces, bytesAll, gsAll, cairoAll);
    CHECK(bytesAll > 10 * bytes);
    CHECK(gsPieces <= gsAll + 1.0);
    CHECK(cairoPieces <= cairoAll + 1.0);
    CHECK(cairoPieces <= 3.0);
}
