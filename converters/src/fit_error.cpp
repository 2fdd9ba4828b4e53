// compareOverMask (colors.h): the error figures of a render against an image.
#include <algorithm>
#include <cmath>

#include "converters/colors.h"

namespace gm {

FitError paintedError(const RgbaImage& image, const std::vector<size_t>& at,
                      const std::function<Vec3(size_t)>& paint, double outlierLimit,
                      long* outliers) {
    FitError e;
    e.pixels = static_cast<long>(at.size());
    if (outliers) *outliers = 0;
    if (at.empty()) return e;
    double absSum = 0, sqSum = 0;
    for (size_t k : at) {
        const Vec3 want = paint(k);
        double pixelAbs = 0;
        for (int c = 0; c < 3; ++c) {
            const double d = 255.0 * std::fabs(image.pixels[4 * k + c] - want[c]);
            pixelAbs += d;
            sqSum += d * d;
            e.maxAbs = std::max(e.maxAbs, d);
        }
        absSum += pixelAbs;
        if (outliers) *outliers += pixelAbs / 3 > outlierLimit;
    }
    const double n = 3.0 * double(at.size());
    e.meanAbs = absSum / n;
    e.rmse = std::sqrt(sqSum / n);
    e.psnr = e.rmse > 0 ? 20 * std::log10(255.0 / e.rmse) : INFINITY;
    return e;
}

FitError compareOverMask(const RgbaImage& reference, const RgbaImage& test,
                         const std::vector<uint8_t>& mask) {
    FitError e;
    double sum = 0, sq = 0;
    long uncovered = 0, n = 0;
    for (int y = 0; y < reference.height; ++y)
        for (int x = 0; x < reference.width; ++x) {
            if (!mask[static_cast<size_t>(y) * reference.width + x]) continue;
            ++n;
            const float* a = reference.at(x, y);
            const float* b = test.at(x, y);
            if (b[3] < 0.5f) {
                ++uncovered;
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                // Clamped, as every writer's colours are (and every viewer's).
                const double d = std::fabs(double(a[c]) - std::clamp(b[c], 0.0f, 1.0f)) * 255.0;
                sum += d;
                sq += d * d;
                e.maxAbs = std::max(e.maxAbs, d);
            }
        }
    const long covered = n - uncovered;
    e.pixels = n;
    e.uncovered = n ? double(uncovered) / n : 0;
    e.meanAbs = covered ? sum / (3.0 * covered) : 0;
    e.rmse = covered ? std::sqrt(sq / (3.0 * covered)) : 0;
    e.psnr = e.rmse > 0 ? 20 * std::log10(255.0 / e.rmse) : INFINITY;
    return e;
}

}  // namespace gm
