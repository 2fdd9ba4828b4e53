#include "view_error_map.h"

#include <algorithm>
#include <cmath>

namespace gm {

namespace {

// Stops of a perceptually ordered dark-to-bright scale (close to matplotlib's "inferno"),
// evenly spaced from 0 to kErrorMapScale; the page's legend uses the same stops.
constexpr float kStops[][3] = {{0.001f, 0.000f, 0.014f}, {0.258f, 0.039f, 0.406f},
                               {0.578f, 0.148f, 0.404f}, {0.865f, 0.317f, 0.226f},
                               {0.988f, 0.645f, 0.040f}, {0.988f, 1.000f, 0.645f}};
constexpr int kStopCount = sizeof kStops / sizeof kStops[0];

// The source, grey and dimmed: where nothing is compared the map keeps the picture's context.
void dimmedSource(const float* source, float* out) {
    const float grey = 0.299f * source[0] + 0.587f * source[1] + 0.114f * source[2];
    for (int c = 0; c < 3; ++c) out[c] = 0.12f + 0.25f * grey;
    out[3] = source[3];
}

}  // namespace

void errorColor(double error, float rgb[3]) {
    const double x = std::clamp(error / kErrorMapScale, 0.0, 1.0) * (kStopCount - 1);
    const int k = std::min(static_cast<int>(x), kStopCount - 2);
    const float f = static_cast<float>(x - k);
    for (int c = 0; c < 3; ++c) rgb[c] = kStops[k][c] + f * (kStops[k + 1][c] - kStops[k][c]);
}

ErrorMap errorHeatMap(const RgbaImage& source, const RgbaImage& render) {
    ErrorMap map;
    map.image = RgbaImage(render.width, render.height);
    double sum = 0, squares = 0;
    for (int y = 0; y < render.height; ++y)
        for (int x = 0; x < render.width; ++x) {
            const float* s = source.at(x, y);
            const float* r = render.at(x, y);
            float* out = map.image.at(x, y);
            if (s[3] < 0.5f || r[3] < 0.5f) {
                dimmedSource(s, out);
                continue;
            }
            double error = 0;
            for (int c = 0; c < 3; ++c) {
                const double e = std::fabs(double(s[c]) - std::clamp(double(r[c]), 0.0, 1.0)) * 255.0;
                error += e / 3.0;
                squares += e * e;
            }
            sum += error;
            ++map.pixels;
            errorColor(error, out);
            out[3] = 1.0f;
        }
    if (map.pixels == 0) return map;
    map.meanAbs = sum / map.pixels;
    map.rmse = std::sqrt(squares / (3.0 * map.pixels));
    map.psnr = map.rmse > 0 ? 20.0 * std::log10(255.0 / map.rmse) : INFINITY;
    return map;
}

}  // namespace gm
