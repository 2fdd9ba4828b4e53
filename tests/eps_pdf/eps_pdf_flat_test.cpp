// Flat shapes in EPS and PDF: filled, stroked and graded paths between the shadings, drawn by
// Ghostscript and pdftocairo as our renderer draws them.
#include <sys/stat.h>

#include <algorithm>
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
#include "support/gradient_shapes.h"
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

TEST_CASE("graded shapes are axial shadings within their outlines in PDF and EPS",
          "[eps][pdf][flat][gradient]") {
    const Document doc = gmtest::gradientTestDocument();
    // Two stops: one exponential function; more: a stitching one over them.
    CHECK(axialShadingEntries(doc.shapes[1].gradient) ==
          "/ShadingType 2 /ColorSpace /DeviceRGB /Coords [10 40 80 40] /Extend [true true]\n"
          "/Function << /FunctionType 2 /Domain [0 1] /C0 [0.9 0.1 0.1] /C1 [0.1 0.2 0.9] /N 1 >>");
    const std::string three = axialShadingEntries(doc.shapes[2].gradient);
    CHECK(three.find("/FunctionType 3 /Domain [0 1] /Functions [\n") != std::string::npos);
    CHECK(epstest::countOccurrences(three, "/FunctionType 2") == 2);
    CHECK(three.find("/Bounds [0.4] /Encode [0 1 0 1] >>") != std::string::npos);
    const std::string four = axialShadingEntries(doc.shapes[3].gradient);
    CHECK(four.find("/Coords [70 132 70 80]") != std::string::npos);
    CHECK(epstest::countOccurrences(four, "/FunctionType 2") == 3);
    CHECK(four.find("/Bounds [0.3 0.7] /Encode [0 1 0 1 0 1] >>") != std::string::npos);
    // Offsets that round to one value: the piece between them goes, the step stays.
    const LinearGradient step = gmtest::linearGradient(
        {0, 0}, {10, 0},
        {{0, {1, 0, 0}}, {0.5, {1, 0, 0}}, {0.5 + 1e-9, {0, 0, 1}}, {1, {0, 0, 1}}});
    const std::string stepped = axialShadingEntries(step);
    CHECK(epstest::countOccurrences(stepped, "/FunctionType 2") == 2);
    CHECK(stepped.find("/C1 [1 0 0] /N 1 >>\n<< /FunctionType 2 /Domain [0 1] /C0 [0 0 1]") !=
          std::string::npos);
    CHECK(stepped.find("/Bounds [0.5] /Encode [0 1 0 1] >>") != std::string::npos);
}

TEST_CASE("PDF paints a graded shape as a clipped shading between the meshes",
          "[eps][pdf][flat][gradient]") {
    Document doc = gmtest::gradientTestDocument();
    doc.meshes.push_back(makeCurvedMesh(2, 2, 120, 90, 60, 40, 0.5, 1));
    doc.shapes.back().layer = 1;  // the translucent triangle over the mesh
    const std::string pdf =
        FormatRegistry::builtin().forPath("x.pdf")->encode(doc, "x.pdf", WriteOptions{});
    CHECK(epstest::countOccurrences(pdf, "/ShadingType 2 ") == 4);
    CHECK(epstest::countOccurrences(pdf, "/ShadingType 7 ") == 1);
    CHECK(pdf.find("/Resources << /Shading << /Sh0 5 0 R /Sh1 6 0 R /Sh2 7 0 R /Sh3 8 0 R /Sh4 9 "
                   "0 R >> /ExtGState << /GS4 << /ca 0.6 >> >> >>") != std::string::npos);
    CHECK(pdf.find("8 0 obj\n<< /ShadingType 7 ") != std::string::npos);
    CHECK(pdf.find("\nq 10 10 m 80 10 l 80 70 l 10 70 l h W n\n/Sh0 sh\nQ\n") != std::string::npos);
    CHECK(pdf.find(" 90 95 l h W n\n/Sh2 sh\nQ\n/Sh3 sh\nq /GS4 gs 60 30 m 180 100 l 100 135 l h "
                   "W n\n/Sh4 sh\nQ\nQ\n") != std::string::npos);
    CHECK(pdf.find("9 0 obj\n<< /ShadingType 2 ") != std::string::npos);
}

TEST_CASE("EPS paints a graded shape with shfill within its clipped outline",
          "[eps][pdf][flat][gradient]") {
    Document doc = gmtest::gradientTestDocument();
    const MeshFormat* eps = FormatRegistry::builtin().forPath("x.eps");
    // PostScript has no transparency: a translucent graded shape is refused as a flat one is.
    CHECK_THROWS_AS(eps->encode(doc, "x.eps", WriteOptions{}), Error);
    doc.shapes.back().alpha = 1;
    // Sixteen stops make the longest function.
    std::vector<std::pair<double, Vec3>> stops;
    for (int k = 0; k < 16; ++k) stops.push_back({k / 15.0, {k / 15.0, 0.123456, 1 - k / 15.0}});
    doc.shapes[1].gradient = gmtest::linearGradient({-9999999.99, 0}, {9999999.99, 0.01}, stops);
    const std::string ps = eps->encode(doc, "x.eps", WriteOptions{});
    CHECK(epstest::countOccurrences(ps, " clip newpath\n<< /ShadingType 2 ") == 4);
    CHECK(epstest::countOccurrences(ps, " >> >> shfill grestore\n") == 4);
    CHECK(ps.find("0.92 0.9 0.85 setrgbcolor 0 0 moveto") != std::string::npos);
    CHECK(ps.find("gsave 10 10 moveto 80 10 lineto 80 70 lineto 10 70 lineto closepath clip "
                  "newpath\n") != std::string::npos);
    CHECK(ps.find("/Coords [-9999999.99 0 9999999.99 0.01]") != std::string::npos);
    size_t longest = 0;
    for (size_t start = 0, end; start < ps.size(); start = end + 1) {
        end = ps.find('\n', start);
        longest = std::max(longest, end - start);
    }
    CHECK(longest < 255);
}

TEST_CASE("Ghostscript and pdftocairo draw graded shapes like our renderer",
          "[eps][pdf][flat][gradient][external]") {
    // PDF with the translucent triangle; EPS, which has no transparency, all opaque.
    const Document doc = gmtest::gradientTestDocument();
    Document opaque = doc, flat = doc;
    for (FlatShape& s : opaque.shapes) s.alpha = 1;
    for (FlatShape& s : flat.shapes) s.gradient.stops.clear();
    const RgbaImage ours = overWhite(doc), oursOpaque = overWhite(opaque);
    // Each shape in its mean colour instead differs by far more than the bar.
    const double unshaded = meanAbsAll(ours, overWhite(flat));
    if (unshaded < 10) FAIL("our renderer paints no gradients: E " << unshaded);
    const std::string eps = flatTmp("gradients.eps"), pdf = flatTmp("gradients.pdf");
    FormatRegistry::builtin().forPath(eps)->write(opaque, eps, WriteOptions{});
    FormatRegistry::builtin().forPath(pdf)->write(doc, pdf, WriteOptions{});
    // Ghostscript does not anti-alias the edges of a clipped shading: at 72 dpi they are jagged,
    // E ≈ 1.5 with three quarters of it at the edges (the interior is within 0.5 on average).
    // Rendered at 4 × and averaged down, it shows the geometry; its 72 dpi figures are printed
    // alone.
    const double gsEps =
        meanAbsAll(oursOpaque, ghostscript(eps, flatTmp("gradients_gs_eps.png"), 4));
    const double gsPdf = meanAbsAll(ours, ghostscript(pdf, flatTmp("gradients_gs_pdf.png"), 4));
    const double cairo = meanAbsAll(ours, pdftocairo(pdf, flatTmp("gradients_cairo")));
    const double gsEps72 =
        meanAbsAll(oursOpaque, ghostscript(eps, flatTmp("gradients_gs_eps72.png")));
    const double gsPdf72 = meanAbsAll(ours, ghostscript(pdf, flatTmp("gradients_gs_pdf72.png")));
    std::printf(
        "gradients: E gs EPS %.3f, gs PDF %.3f (at 72 dpi: %.3f, %.3f), pdftocairo %.3f "
        "(mean colours: %.3f)\n",
        gsEps, gsPdf, gsEps72, gsPdf72, cairo, unshaded);
    CHECK(gsEps <= 1.0);
    CHECK(gsPdf <= 1.0);
    CHECK(cairo <= 0.5);
}
