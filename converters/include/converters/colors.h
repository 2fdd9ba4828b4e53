// Pipeline stage 7, colours (docs/design.md §3, paper §4.5): node colours and colour derivatives of
// a mesh whose geometry is fixed.
//
//  - Sampled (the paper): node colours are bilinear samples of the image taken from the region's
//    side only; colour derivatives follow the monotone-cubic rule (the Bicubic model), so
//    formats omit them.
//  - Fit (beyond the paper): with geometry fixed, every pixel's colour is linear in the node
//    colours and colour derivatives (the patch's Hermite basis at the pixel's (s,t)). One
//    sparse least-squares solve over the region's pixels fits them all; pixel → patch and (s,t)
//    come from the renderer's own tessellation (renderMesh with wantSamples), so fit and render
//    agree. A small Tikhonov term pulls every unknown toward its sampled value so that patches
//    with few or no pixels stay well posed.
//
// Error figures are in 0–255 units of sRGB-encoded channels, rendered colours clamped to 0–1
// (what every writer outputs), over the region's pixels (Region::mask).
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include "converters/region.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"
#include "meshcore/render.h"

namespace gm {

// FitBicubic: only node colours are unknowns, in the Bicubic colour model (every slope by the
// SVG 2 bicubic rule, meshcore/bicubic_colors.h): nonlinear least squares through the rule
// (bicubic_fit.h). The result is a Bicubic mesh: one SVG patch per patch, drawn by Inkscape
// in our colours. Sampled also gives a Bicubic mesh.
// FitValues: only node colours are unknowns; every colour slope keeps the value it has in the
// geometry passed in (for a refit after the slopes were quantised); a Bicubic geometry is
// refitted as FitBicubic.
enum class ColorMode { Sampled, Fit, FitBicubic, FitValues };

struct ColorOptions {
    ColorMode mode = ColorMode::Fit;
    // Weight of the pull toward the sampled solution, relative to the mean pixel weight of an
    // unknown of the same kind (values, u-slopes, v-slopes).
    double regularization = 1e-3;
    int threads = 0;          // renderer threads (0: all)
    // fitColorsToSamples, Fit mode: the iterative solve starts from the geometry's own colours
    // (a refit of colours near the answer) instead of the sampled solution; the pull stays
    // toward the sampled one.
    bool warmStart = false;
    bool keepPixels = false;  // fill ColorResult::samples and pixelError
    // FitBicubic: the weight (relative to the mean pixel weight of a colour) pulling the two
    // ends of a patch edge of length L < 1 px toward one colour, times 1 − L (bicubic_fit.h).
    // 0: off.
    double subPixelEdgePull = 0;
};

struct FitError {
    double meanAbs = 0;    // E: mean absolute error per covered region pixel and channel
    double rmse = 0;       // root mean square over the same
    double psnr = 0;       // 20·log10(255 / rmse) dB; infinity when rmse is 0
    double maxAbs = 0;     // largest channel error
    double uncovered = 0;  // fraction of region pixels no patch paints (excluded from the above)
    long pixels = 0;       // region pixels
};

// The colour of pixel k (an index into the image), sRGB 0–1.
inline Vec3 pixelColour(const RgbaImage& image, size_t k) {
    return {image.pixels[4 * k], image.pixels[4 * k + 1], image.pixels[4 * k + 2]};
}

// The figures (E, RMSE, PSNR, max) of painting pixels `at` (indices into the image) in
// `paint(k)`; `outliers`, when given, counts the pixels whose mean channel error exceeds
// `outlierLimit` (0–255 units).
FitError paintedError(const RgbaImage& image, const std::vector<size_t>& at,
                      const std::function<Vec3(size_t)>& paint, double outlierLimit = INFINITY,
                      long* outliers = nullptr);

// The report's figures of `test` against `reference` over the pixels where mask (width*height,
// row-major) is non-zero: pixels whose test alpha is under 0.5 count as uncovered and are left
// out of E, RMSE, PSNR and max. Both images must have the mask's size.
FitError compareOverMask(const RgbaImage& reference, const RgbaImage& test,
                         const std::vector<uint8_t>& mask);

struct ColorResult {
    GradientMesh mesh;  // the input geometry with colours
    FitError error;
    std::vector<double> patchError;  // per patch j*C+i: Σ over its pixels of the mean channel
                                     // error (0–255)
    // With keepPixels: the render's samples and each pixel's mean channel error (−1 outside
    // the region or uncovered), row-major over the image.
    std::vector<PixelSample> samples;
    std::vector<float> pixelError;
};

// The image colour at image point p (pixels, y down) from region pixels only: bilinear over the
// in-region pixels among the four nearest centres, else the nearest region pixel. Throws
// gm::Error when the region's size differs from the image's.
Vec3 sampleRegionColor(const RgbaImage& image, const Region& region, Vec2 p);

// Sampled mode alone, without rendering: every node copy's colour sampled at its position,
// colour derivatives by applyColorRule.
void sampleNodeColors(GradientMesh& mesh, const RgbaImage& image, const Region& region);

// Stage entry point: colours for `geometry` (its colours are ignored) in the chosen mode, with
// the error figures of the result (one render). Throws gm::Error when the region and image
// sizes differ or the mesh is invalid.
ColorResult computeColors(const GradientMesh& geometry, const RgbaImage& image,
                          const Region& region, const ColorOptions& options = {});

// As computeColors without its render or error figures: `samples` (one per image pixel) come
// from a render of a document (RenderOptions::wantSamples, antialias off) in which the mesh
// is number `meshIndex`, and only the region's pixels whose sample names that mesh are
// fitted: the pixels where it is on top. Throws gm::Error like computeColors, or when
// `samples` is not one per pixel.
GradientMesh fitColorsToSamples(const GradientMesh& geometry, const RgbaImage& image,
                                const Region& region, const std::vector<PixelSample>& samples,
                                int meshIndex, const ColorOptions& options = {});

// The error figures of a coloured mesh against the image over the region (one render).
ColorResult measureColorError(const GradientMesh& mesh, const RgbaImage& image,
                              const Region& region, const ColorOptions& options = {});

}  // namespace gm
