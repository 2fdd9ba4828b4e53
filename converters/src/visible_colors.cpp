#include "converters/visible_colors.h"

#include <algorithm>

#include "converters/convert_image.h"
#include "meshcore/color_rule.h"
#include "meshcore/error.h"
#include "meshcore/parallel_for.h"
#include "meshcore/render.h"

namespace gm {

namespace {

void checkCanvas(const Document& doc, size_t maskSize, const RgbaImage* image) {
    const size_t n = static_cast<size_t>(std::max(doc.width, 0)) * std::max(doc.height, 0);
    if (maskSize != n)
        throw Error("visible colours: the mask has " + std::to_string(maskSize) +
                    " pixels, the canvas " + std::to_string(n));
    if (image && (image->width != doc.width || image->height != doc.height))
        throw Error("visible colours: the image is " + std::to_string(image->width) + "x" +
                    std::to_string(image->height) + ", the canvas " + std::to_string(doc.width) +
                    "x" + std::to_string(doc.height));
}

int threadCount(int threads) { return threadsToUse(threads); }

FitError errorOf(const Document& doc, const RgbaImage& image, const std::vector<uint8_t>& mask,
                 int threads) {
    RenderOptions renderOptions;
    renderOptions.threads = threads;
    return compareOverMask(image, renderDocument(doc, renderOptions).image, mask);
}

// The document's render samples: per pixel the topmost mesh covering its centre (antialias off,
// as colors.cpp renders for its fits).
std::vector<PixelSample> documentSamples(const Document& doc, int threads) {
    RenderOptions renderOptions;
    renderOptions.wantSamples = true;
    renderOptions.antialias = false;
    renderOptions.threads = threads;
    return renderDocument(doc, renderOptions).samples;
}

// refitVisibleColors with the document's samples given (one render serves refits of the same
// geometry).
Document refitWithSamples(const Document& doc, const RgbaImage& image,
                          const std::vector<uint8_t>& mask, ColorMode mode, int threads,
                          const std::vector<PixelSample>& samples) {
    Document out = doc;
    if (mode == ColorMode::Sampled || doc.meshes.empty()) return out;
    std::vector<int> pixels(doc.meshes.size(), 0);
    for (size_t p = 0; p < samples.size(); ++p)
        if (mask[p] && samples[p].mesh >= 0) ++pixels[static_cast<size_t>(samples[p].mesh)];

    // Meshes in parallel, each solve on one thread: a whole image has a few to a few dozen.
    auto refit = [&](int mesh, int) {
        const size_t k = static_cast<size_t>(mesh);
        if (pixels[k] < 4) return;
        Region region;
        region.width = doc.width;
        region.height = doc.height;
        region.mask.assign(mask.size(), 0);
        for (size_t p = 0; p < samples.size(); ++p)
            if (mask[p] && samples[p].mesh == static_cast<int>(k)) region.mask[p] = 1;
        region.pixelCount = pixels[k];
        ColorOptions colorOptions;
        // A Bicubic mesh stays Bicubic: its colours are all there is to refit.
        const bool bicubic = doc.meshes[k].colorModel == ColorModel::Bicubic;
        colorOptions.mode = bicubic ? ColorMode::FitBicubic : mode;
        colorOptions.threads = 1;
        colorOptions.warmStart = true;  // the colours given are near the refit's
        out.meshes[k] = fitColorsToSamples(doc.meshes[k], image, region, samples,
                                           static_cast<int>(k), colorOptions);
    };
    parallelFor(static_cast<int>(doc.meshes.size()), threadCount(threads), refit);
    return out;
}

}  // namespace

std::vector<int> topmostMeshes(const Document& doc, const std::vector<uint8_t>& mask, int threads) {
    checkCanvas(doc, mask.size(), nullptr);
    const std::vector<PixelSample> samples = documentSamples(doc, threads);
    std::vector<int> top(mask.size(), -1);
    for (size_t p = 0; p < top.size(); ++p)
        if (mask[p]) top[p] = samples[p].mesh;
    return top;
}

Document refitVisibleColors(const Document& doc, const RgbaImage& image,
                            const std::vector<uint8_t>& mask, ColorMode mode, int threads) {
    checkCanvas(doc, mask.size(), &image);
    if (mode == ColorMode::Sampled || doc.meshes.empty()) return doc;
    // One render gives every mesh's visible pixels and their (patch, s, t).
    return refitWithSamples(doc, image, mask, mode, threads, documentSamples(doc, threads));
}

QuantisedColors colorsForQuantisation(const Document& doc, const RgbaImage& image,
                                      const std::vector<uint8_t>& mask, ColorMode mode,
                                      const std::function<Document(const Document&)>& quantise,
                                      int threads, const FitError* unquantised) {
    checkCanvas(doc, mask.size(), &image);
    QuantisedColors best;
    best.doc = quantise(doc);
    best.error = errorOf(best.doc, image, mask, threads);
    best.unquantised = unquantised ? *unquantised : errorOf(doc, image, mask, threads);
    best.how = "as is";
    const double sq = best.error.rmse * best.error.rmse;
    const double sq0 = best.unquantised.rmse * best.unquantised.rmse;
    if (mode == ColorMode::Sampled || sq <= 1.01 * sq0) return best;
    auto consider = [&](Document candidate, const char* how) {
        const FitError e = errorOf(candidate, image, mask, threads);
        if (e.rmse < best.error.rmse) {
            best.doc = std::move(candidate);
            best.error = e;
            best.how = how;
        }
    };
    const Document quantised = best.doc;
    // The quantised geometry is every candidate's: one render gives its samples.
    const std::vector<PixelSample> samples = documentSamples(quantised, threads);
    auto refit = [&](const Document& d, ColorMode m) {
        return quantise(refitWithSamples(d, image, mask, m, threads, samples));
    };
    // A refit that fails (a solve, or a file the writer refuses) leaves the quantised document:
    // the file is still right, only not improved, and `how` says why.
    try {
        if (mode == ColorMode::FitBicubic) {
            consider(refit(quantised, ColorMode::FitBicubic), "bicubic refit");
            return best;
        }
        // Fit: all colours refitted to the quantised geometry, their slopes quantised, then the
        // values refitted to those slopes (at coarse levels the grid rounds most fitted slopes
        // to 0; values fitted to the slopes the grid left, without the fresh fit, never did
        // better on the bench images, nor did the fresh fit quantised without the second).
        consider(refit(refit(quantised, ColorMode::Fit), ColorMode::FitValues), "refit");
    } catch (const Error& e) {
        best.how += "; the refit failed: " + e.reason();
    }
    return best;
}

}  // namespace gm
