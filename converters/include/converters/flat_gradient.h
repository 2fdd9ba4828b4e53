// Whole images (docs/design.md §5): a flat region whose colour runs smoothly across it — a
// shaded panel of a drawing, a sky — painted with a linear gradient instead of its mean colour,
// when the colour it wins back is worth the gradient's bytes.
#pragma once

#include <cstddef>
#include <vector>

#include "converters/colors.h"
#include "converters/region.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

struct GradientFitOptions {
    int maxStops = 4;  // 2 at least
    // What a gradient adds to an SVG, bytes: the element with its axis, and each stop.
    double bytesPerGradient = 110;
    double bytesPerStop = 40;
    // The squared error (0–255 units, the mean over channels, summed over pixels) one byte must
    // win back: a gradient of K stops pays when the region's squared error falls by at least
    // this times its bytes (convertSegmented: SegmentConvertOptions::flatErrorPerByte).
    double errorPerByte = 1000;
    // Fewer pixels to fit: no gradient.
    int minPixels = 16;
    // A shaded region may be drawn as a graded flat shape instead of a mesh when a gradient of
    // at most maxStops stops fits its interior pixels with E at most errorShare times the
    // conversion's error target, with at most outlierShare of them further than outlierError
    // times the target (fitGradedRegion), and draws the region no worse than its mesh.
    double errorShare = 0.5;
    double outlierShare = 0.02;
    double outlierError = 4;
};

// The linear gradient that paints pixels `at` (indices into the image) best among those that
// pay against the flat colour `flat`, or one without stops when none pays. Its axis runs along
// the direction the colour changes most (of the principal direction of the pixels' affine
// colour fit, the image axes and the diagonals); its stops lie where the colour's profile
// along it bends, their colours least-squares fits.
LinearGradient fitPayingGradient(const RgbaImage& image, const std::vector<size_t>& at,
                                 const Vec3& flat, const GradientFitOptions& options = {});

// Region `own` (its pixels as the image shows them) as a linear gradient with the fewest stops
// that fits its interior pixels (those whose four neighbours are in it) as options.errorShare,
// outlierShare and outlierError ask against `maxError` (0–255 units); one without stops when
// none does or the region has fewer than options.minPixels interior pixels.
LinearGradient fitGradedRegion(const RgbaImage& image, const Region& own, double maxError,
                               const GradientFitOptions& options = {});

// The summed squared error (0–255 units, the mean over channels) of painting pixels `at` in
// the gradient's colours (the flat colour `flat` when it has no stops).
double gradientSquaredError(const RgbaImage& image, const std::vector<size_t>& at,
                            const LinearGradient& gradient, const Vec3& flat);

// The FitError (E, RMSE, PSNR, max) of painting pixels `at` in the gradient's colours.
FitError gradientFitError(const RgbaImage& image, const std::vector<size_t>& at,
                          const LinearGradient& gradient);

}  // namespace gm
