// Colours refitted where each mesh shows, and for a compact file's grids, on a real whole-image
// conversion (samples/HappyFish.jpg at a few patches a region: the meshes overlap at every
// border, and level 6's grids cost it most).
#include "converters/visible_colors.h"

#include <catch2/catch.hpp>
#include <string>

#include "converters/convert_image.h"
#include "converters/convert_segments.h"
#include "formats/gmb.h"
#include "formats/raster.h"
#include "meshcore/color_rule.h"
#include "meshcore/error.h"
#include "meshcore/render.h"

using namespace gm;

namespace {

struct Whole {
    RgbaImage image;
    Document doc;
    std::vector<uint8_t> all;
};

const Whole& fish(ColorMode mode) {
    static Whole fit, rule;
    Whole& w = mode == ColorMode::FitBicubic ? rule : fit;
    if (w.doc.meshes.empty()) {
        w.image = readImage(std::string(GRADMESH_SAMPLES) + "/HappyFish.jpg");
        SegmentConvertOptions o;
        o.convert.maxError = 2;
        o.convert.maxPatches = 6;
        o.convert.colors = mode;
        w.doc = convertSegmented(w.image, o, "HappyFish.jpg");
        w.all.assign(static_cast<size_t>(w.image.width) * w.image.height, 1);
    }
    return w;
}

FitError errorOf(const Whole& w, const Document& doc) {
    return compareOverMask(w.image, renderDocument(doc).image, w.all);
}

std::function<Document(const Document&)> gmbAt(int level) {
    return
        [level](const Document& d) { return decodeGmb(encodeGmb(d, true, level), ReadLimits{}); };
}

bool sameGeometry(const Document& a, const Document& b) {
    if (a.meshes.size() != b.meshes.size()) return false;
    for (size_t k = 0; k < a.meshes.size(); ++k) {
        const GradientMesh &m = a.meshes[k], &n = b.meshes[k];
        if (m.u != n.u || m.v != n.v || m.nodes.size() != n.nodes.size()) return false;
        for (size_t i = 0; i < m.nodes.size(); ++i)
            if (!(m.nodes[i].pos == n.nodes[i].pos) || !(m.nodes[i].posU == n.nodes[i].posU) ||
                !(m.nodes[i].posV == n.nodes[i].posV))
                return false;
    }
    return true;
}

}  // namespace

TEST_CASE("each mesh's colours refitted where it shows lower the whole image's error",
          "[visible]") {
    const Whole& w = fish(ColorMode::Fit);
    const std::vector<int> top = topmostMeshes(w.doc, w.all);
    std::vector<int> shown(w.doc.meshes.size(), 0);
    for (int m : top)
        if (m >= 0) ++shown[static_cast<size_t>(m)];
    for (size_t k = 1; k < shown.size(); ++k) CHECK(shown[k] > 0);  // every region mesh shows

    const FitError before = errorOf(w, w.doc);
    const Document refit = refitVisibleColors(w.doc, w.image, w.all, ColorMode::Fit);
    const FitError after = errorOf(w, refit);
    WARN("HappyFish at 6 patches a region, colours refitted where each mesh shows: PSNR "
         << before.psnr << " -> " << after.psnr << " dB");
    CHECK(sameGeometry(refit, w.doc));
    CHECK(after.uncovered == before.uncovered);
    CHECK(after.psnr > before.psnr);  // measured +0.03 dB: the overlaps are a pixel wide

    // Sampled colours stay the paper's.
    const Document sampled = refitVisibleColors(w.doc, w.image, w.all, ColorMode::Sampled);
    for (size_t k = 0; k < w.doc.meshes.size(); ++k)
        CHECK(sampled.meshes[k].nodes == w.doc.meshes[k].nodes);

    CHECK_THROWS_AS(refitVisibleColors(w.doc, w.image, std::vector<uint8_t>(10, 1), ColorMode::Fit),
                    Error);
    CHECK_THROWS_AS(topmostMeshes(w.doc, std::vector<uint8_t>(10, 1)), Error);
    RgbaImage small(8, 8);
    CHECK_THROWS_AS(refitVisibleColors(w.doc, small, w.all, ColorMode::Fit), Error);
}

TEST_CASE("colours refitted to a compact file's grids win back what level 6 costs",
          "[visible][gmb]") {
    const Whole& w = fish(ColorMode::Fit);
    const auto quantise = gmbAt(6);
    const FitError lossless = errorOf(w, w.doc);
    const FitError plain = errorOf(w, quantise(w.doc));
    const QuantisedColors q =
        colorsForQuantisation(w.doc, w.image, w.all, ColorMode::Fit, quantise);
    const std::string bytes = encodeGmb(q.doc, true, 6);
    WARN("HappyFish at 6 patches a region, level 6: lossless "
         << lossless.psnr << " dB; the file " << plain.psnr << " dB, "
         << encodeGmb(w.doc, true, 6).size() << " B; refitted (" << q.how << ") " << q.error.psnr
         << " dB, " << bytes.size() << " B");
    CHECK(q.how == "refit");
    CHECK(q.unquantised.rmse == lossless.rmse);
    CHECK(q.error.psnr > plain.psnr + 0.3);  // measured +0.49 dB for +3 % bytes
    CHECK(sameGeometry(q.doc, quantise(w.doc)));
    // The document kept is what its file holds: written again it is the same file, and the
    // figures are that file's.
    const Document reread = decodeGmb(bytes, ReadLimits{});
    CHECK(encodeGmb(reread, true, 6) == bytes);
    const FitError fileError = errorOf(w, reread);
    CHECK(fileError.rmse == q.error.rmse);
    CHECK(fileError.meanAbs == q.error.meanAbs);
}

TEST_CASE("a quantisation that costs nothing keeps the document; rule colours keep the rule",
          "[visible][gmb]") {
    const Whole& w = fish(ColorMode::Fit);
    const QuantisedColors same = colorsForQuantisation(w.doc, w.image, w.all, ColorMode::Fit,
                                                       [](const Document& d) { return d; });
    CHECK(same.how == "as is");
    CHECK(same.error.rmse == same.unquantised.rmse);

    const Whole& r = fish(ColorMode::FitBicubic);
    const auto quantise = gmbAt(6);
    const FitError plain = errorOf(r, quantise(r.doc));
    const QuantisedColors q =
        colorsForQuantisation(r.doc, r.image, r.all, ColorMode::FitBicubic, quantise);
    WARN("HappyFish at 6 patches a region, bicubic colours, level 6: "
         << plain.psnr << " -> " << q.error.psnr << " dB (" << q.how << ")");
    CHECK((q.how == "as is" || q.how == "bicubic refit"));
    CHECK(q.error.rmse <= plain.rmse);
    for (const GradientMesh& m : q.doc.meshes) CHECK(m.colorModel == ColorModel::Bicubic);
}

TEST_CASE("a refit that fails leaves the quantised document and says why", "[visible][gmb]") {
    // The writer refuses the second document it is given: the refit's.
    const Whole& w = fish(ColorMode::Fit);
    int calls = 0;
    const auto level6 = gmbAt(6);
    const auto quantise = [&calls, &level6](const Document& d) {
        if (++calls > 1) throw Error("refused on purpose");
        return level6(d);
    };
    const QuantisedColors r =
        colorsForQuantisation(w.doc, w.image, w.all, ColorMode::Fit, quantise);
    CHECK(r.how == "as is; the refit failed: refused on purpose");
    CHECK(encodeGmb(r.doc, true, 6) == encodeGmb(w.doc, true, 6));
    CHECK(r.error.rmse == errorOf(w, r.doc).rmse);
}
