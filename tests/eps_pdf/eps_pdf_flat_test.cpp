// Flat shapes in EPS and PDF: filled paths between the shadings, drawn by Ghostscript and
// pdftocairo as our renderer draws them.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "formats/mesh_shading.h"
#include "formats/raster.h"
#include "formats/registry.h"
#include "meshcore/error.h"
#include "meshcore/render.h"
#include "meshcore/synthetic_meshes.h"
#include "support/compare.h"

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

RgbaImage ghostscript(const std::string& input, const std::string& png) {
    std::remove(png.c_str());
    const std::string crop = input.substr(input.size() - 4) == ".eps" ? " -dEPSCrop" : "";
    REQUIRE(runCommand("gs -q -dSAFER -dBATCH -dNOPAUSE -sDEVICE=png16m -r72 "
                       "-dGraphicsAlphaBits=4" +
                       crop + " -sOutputFile=" + quote(png) + " " + quote(input) + " 2>&1") == 0);
    return readImage(png);
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
