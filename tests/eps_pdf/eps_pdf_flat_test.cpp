// Flat shapes in EPS and PDF: filled and stroked paths between the shadings, drawn by
// Ghostscript and pdftocairo as our renderer draws them.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "eps_pdf_test_support.h"
#include "formats/mesh_shading.h"
#include "formats/raster.h"
#include "formats/registry.h"
#include "meshcore/error.h"
#include "meshcore/render.h"
#include "meshcore/synthetic_meshes.h"
#include "support/compare.h"
#include "support/stroke_shapes.h"

using namespace gm;
using gmtest::quote;
using gmtest::runCommand;

namespace {

std::string flatTmp(const std::string& name) {
    const std::string dir = std::string(GRADMESH_TMP) + "/eps_pdf_flat";
    mkdir(GRADMESH_TMP, 0755);
    mkdir(dir.c_str(), 0755);
    return dir + "/" + name;
}

RgbaImage overWhite(const Document& doc) {
    RgbaImage img = renderDocument(doc).image;
    compositeOver(img, {1, 1, 1, 1});
    return img;
}

double meanAbsAll(const RgbaImage& a, const RgbaImage& b) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    double sum = 0;
    for (size_t k = 0; k < a.pixels.size(); k += 4)
        for (int c = 0; c < 3; ++c) sum += std::fabs(a.pixels[k + c] - b.pixels[k + c]);
    return 255 * sum / (3.0 * double(a.pixels.size() / 4));
}

// Ghostscript's render at 72 dpi, or at `supersample` times that averaged over blocks of
// supersample × supersample pixels.
RgbaImage ghostscript(const std::string& input, const std::string& png, int supersample = 1) {
    std::remove(png.c_str());
    const std::string crop = input.substr(input.size() - 4) == ".eps" ? " -dEPSCrop" : "";
    REQUIRE(runCommand("gs -q -dSAFER -dBATCH -dNOPAUSE -sDEVICE=png16m -r" +
                       std::to_string(72 * supersample) + " -dGraphicsAlphaBits=4" + crop +
                       " -sOutputFile=" + quote(png) + " " + quote(input) + " 2>&1") == 0);
    const RgbaImage fine = readImage(png);
    if (supersample == 1) return fine;
    RgbaImage img(fine.width / supersample, fine.height / supersample);
    const float share = 1.0f / float(supersample * supersample);
    for (int y = 0; y < fine.height - fine.height % supersample; ++y)
        for (int x = 0; x < fine.width - fine.width % supersample; ++x)
            for (int c = 0; c < 4; ++c)
                img.at(x / supersample, y / supersample)[c] += share * fine.at(x, y)[c];
    return img;
}

RgbaImage pdftocairo(const std::string& pdf, const std::string& base) {
    std::remove((base + ".png").c_str());
    REQUIRE(runCommand("pdftocairo -png -r 72 -singlefile " + quote(pdf) + " " + quote(base)) == 0);
    return readImage(base + ".png");
}

}  // namespace

TEST_CASE("flat shapes are filled paths in paint order in PDF and EPS", "[eps][pdf][flat]") {
    const Document doc = makeFlatDocument();
    const std::string ops = shapeFillOperators(doc.shapes[1], kPdfPathOperators);
    CHECK(ops.rfind("0.1 0.3 0.9 rg 20.25 110.5 m 80.25 110.5 l", 0) == 0);
    CHECK(ops.find(" h 40.5 130.75 m") != std::string::npos);
    CHECK(ops.substr(ops.size() - 4) == "h f\n");
    const std::string ps = shapeFillOperators(doc.shapes[0], kPostScriptPathOperators);
    CHECK(ps.find("setrgbcolor") != std::string::npos);
    CHECK(ps.find("curveto") != std::string::npos);

    Document translucent = doc;
    translucent.shapes[0].alpha = 0.5;
    const MeshFormat* eps = FormatRegistry::builtin().forPath("x.eps");
    CHECK_THROWS_AS(eps->encode(translucent, "x.eps", WriteOptions{}), Error);
    const std::string pdf =
        FormatRegistry::builtin().forPath("x.pdf")->encode(translucent, "x.pdf", WriteOptions{});
    CHECK(pdf.find("/ExtGState << /GS0 << /ca 0.5 >> >>") != std::string::npos);
}

TEST_CASE("Ghostscript and pdftocairo draw flat shapes like our renderer",
          "[eps][pdf][flat][external]") {
    Document shapesOnly = makeFlatDocument();
    shapesOnly.meshes.clear();
    for (FlatShape& s : shapesOnly.shapes) s.layer = 0;
    for (const Document* doc : {&shapesOnly}) {
        const RgbaImage ours = overWhite(*doc);
        const std::string eps = flatTmp("flat.eps"), pdf = flatTmp("flat.pdf");
        FormatRegistry::builtin().forPath(eps)->write(*doc, eps, WriteOptions{});
        FormatRegistry::builtin().forPath(pdf)->write(*doc, pdf, WriteOptions{});
        const double gsEps = meanAbsAll(ours, ghostscript(eps, flatTmp("flat_gs_eps.png")));
        const double gsPdf = meanAbsAll(ours, ghostscript(pdf, flatTmp("flat_gs_pdf.png")));
        const double cairo = meanAbsAll(ours, pdftocairo(pdf, flatTmp("flat_cairo")));
        std::printf("flat shapes: E gs EPS %.3f, gs PDF %.3f, pdftocairo %.3f\n", gsEps, gsPdf,
                    cairo);
        CHECK(gsEps <= 1.0);
        CHECK(gsPdf <= 1.0);
        CHECK(cairo <= 1.0);
    }
}

TEST_CASE("stroked shapes are round-capped stroked paths in PDF and EPS",
          "[eps][pdf][flat][stroke]") {
    const Document doc = gmtest::strokeTestDocument();
    // Open: no close; closed: the last line left to the close; curves as curves.
    CHECK(shapeStrokeOperators(doc.shapes[1], kPdfPathOperators) ==
          "0.7 0.1 0.1 RG 3 w 1 J 1 j 15 20 m 45 50 l 75 20 l 105 50 l S\n");
    CHECK(shapeStrokeOperators(doc.shapes[4], kPdfPathOperators) ==
          "0.5 0.2 0.6 RG 4 w 1 J 1 j 30 70 m 70 75 l 45 95 l h 160 115 m 185 130 l S\n");
    const std::string circle = shapeStrokeOperators(doc.shapes[3], kPdfPathOperators);
    CHECK(circle.rfind("0.1 0.6 0.2 RG 2.25 w 1 J 1 j 165 55 m ", 0) == 0);
    CHECK(epstest::countOccurrences(circle, " c ") == 4);
    CHECK(circle.substr(circle.size() - 13) == "165 55 c h S\n");
    CHECK(shapeStrokeOperators(doc.shapes[1], kPostScriptPathOperators) ==
          "0.7 0.1 0.1 setrgbcolor 3 setlinewidth 1 setlinecap 1 setlinejoin 15 20 moveto 45 50 "
          "lineto 75 20 lineto 105 50 lineto stroke\n");
    CHECK(shapeStrokeOperators(doc.shapes[4], kPostScriptPathOperators).find("lineto closepath") !=
          std::string::npos);

    // Each stroke within q/Q (gsave/grestore): its line width, caps and joins end with it. A
    // translucent stroke's graphics state sets the stroke opacity, /CA.
    const std::string pdf =
        FormatRegistry::builtin().forPath("x.pdf")->encode(doc, "x.pdf", WriteOptions{});
    CHECK(pdf.find("q 0.7 0.1 0.1 RG 3 w 1 J 1 j 15 20 m") != std::string::npos);
    CHECK(pdf.find("q /GS4 gs 0.5 0.2 0.6 RG 4 w") != std::string::npos);
    CHECK(pdf.find("/GS4 << /CA 0.6 >>") != std::string::npos);
    CHECK(epstest::countOccurrences(pdf, " S\nQ\n") == 5);
    Document opaque = doc;
    for (FlatShape& s : opaque.shapes) s.alpha = 1;
    const std::string eps =
        FormatRegistry::builtin().forPath("x.eps")->encode(opaque, "x.eps", WriteOptions{});
    CHECK(epstest::countOccurrences(eps, "gsave 0.") == 5);
    CHECK(epstest::countOccurrences(eps, " stroke\ngrestore\n") == 5);
    // PostScript has no transparency: a translucent stroke is refused as a translucent fill is.
    CHECK_THROWS_AS(
        FormatRegistry::builtin().forPath("x.eps")->encode(doc, "x.eps", WriteOptions{}), Error);
}

TEST_CASE("Ghostscript and pdftocairo draw stroked shapes like our renderer",
          "[eps][pdf][flat][stroke][external]") {
    // PDF with a translucent stroke; EPS, which has no transparency, all opaque.
    const Document doc = gmtest::strokeTestDocument();
    Document opaque = doc;
    for (FlatShape& s : opaque.shapes) s.alpha = 1;
    const RgbaImage ours = overWhite(doc), oursOpaque = overWhite(opaque);
    Document square = doc;
    square.shapes.resize(1);
    if (meanAbsAll(ours, overWhite(square)) == 0) FAIL("our renderer paints no strokes");
    const std::string eps = flatTmp("strokes.eps"), pdf = flatTmp("strokes.pdf");
    FormatRegistry::builtin().forPath(eps)->write(opaque, eps, WriteOptions{});
    FormatRegistry::builtin().forPath(pdf)->write(doc, pdf, WriteOptions{});
    // Ghostscript's anti-aliasing covers every subpixel an edge touches (Adobe's any-part-of-
    // pixel rule on a 4 × 4 grid): each edge spreads outward by an eighth of a pixel on average,
    // which the dense edges of strokes add up to E ≈ 1.4 at 72 dpi. Rendered at 4 × and averaged
    // down, it shows the geometry; its 72 dpi figures are printed alone.
    const double gsEps = meanAbsAll(oursOpaque, ghostscript(eps, flatTmp("strokes_gs_eps.png"), 4));
    const double gsPdf = meanAbsAll(ours, ghostscript(pdf, flatTmp("strokes_gs_pdf.png"), 4));
    const double cairo = meanAbsAll(ours, pdftocairo(pdf, flatTmp("strokes_cairo")));
    const double gsEps72 =
        meanAbsAll(oursOpaque, ghostscript(eps, flatTmp("strokes_gs_eps72.png")));
    const double gsPdf72 = meanAbsAll(ours, ghostscript(pdf, flatTmp("strokes_gs_pdf72.png")));
    std::printf("strokes: E gs EPS %.3f, gs PDF %.3f (at 72 dpi: %.3f, %.3f), pdftocairo %.3f\n",
                gsEps, gsPdf, gsEps72, gsPdf72, cairo);
    CHECK(gsEps <= 1.0);
    CHECK(gsPdf <= 1.0);
    CHECK(cairo <= 1.0);
}
