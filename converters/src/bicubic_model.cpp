// Hermite meshes refitted in the Bicubic model; see bicubic_model.h.
#include "converters/bicubic_model.h"

#include <algorithm>

#include "converters/convert_image.h"
#include "converters/visible_colors.h"
#include "meshcore/bicubic_colors.h"
#include "meshcore/render.h"

namespace gm {

bool hasHermiteMeshes(const Document& doc) {
    return std::any_of(doc.meshes.begin(), doc.meshes.end(), [](const GradientMesh& m) {
        return m.colorModel == ColorModel::Hermite;
    });
}

BicubicConversion toBicubicModel(const Document& doc, int threads) {
    BicubicConversion out;
    out.doc = doc;
    if (!hasHermiteMeshes(doc)) return out;
    RenderOptions renderOptions;
    renderOptions.threads = threads;
    RgbaImage target = renderDocument(doc, renderOptions).image;
    std::vector<uint8_t> covered(static_cast<size_t>(target.width) * target.height, 0);
    for (size_t p = 0; p < covered.size(); ++p) {
        float* px = &target.pixels[4 * p];
        covered[p] = px[3] >= 0.5f;
        for (int ch = 0; ch < 3; ++ch) px[ch] = std::clamp(px[ch], 0.0f, 1.0f);  // as viewers show it
    }
    out.doc = refitVisibleColors(doc, target, covered, ColorMode::FitBicubic, threads);
    for (GradientMesh& m : out.doc.meshes) {
        // A mesh topmost on too few pixels to refit keeps its colours, in the Bicubic model.
        if (m.colorModel == ColorModel::Hermite) useBicubicModel(m);
    }
    for (const GradientMesh& m : doc.meshes) out.refitted += m.colorModel == ColorModel::Hermite;
    out.error = compareOverMask(target, renderDocument(out.doc, renderOptions).image, covered);
    return out;
}

}  // namespace gm
