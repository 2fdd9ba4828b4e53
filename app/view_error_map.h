// The view page's error heat map: where a render differs from the image it was converted from.
#pragma once

#include <cstddef>

#include "meshcore/image.h"

namespace gm {

// Per-pixel error: the mean absolute difference of R, G and B in 0-255 units. The heat map
// colours it from 0 to kErrorMapScale (and above) on a dark-to-bright scale; the page's legend
// states the same scale, so that pages of different conversions read alike.
constexpr double kErrorMapScale = 32.0;

struct ErrorMap {
    RgbaImage image;      // the heat map; outside the compared pixels, the source dimmed
    double meanAbs = 0;   // E over the compared pixels
    double rmse = 0;
    double psnr = 0;      // dB; infinite for identical pixels
    size_t pixels = 0;    // compared pixels
};

// Compares `render` with `source` (same size) where both are opaque (alpha at least 1/2): the
// pixels the mesh paints of the object the image shows.
ErrorMap errorHeatMap(const RgbaImage& source, const RgbaImage& render);

// The heat map's colour of a per-pixel error (0-255 units): RGB 0-1.
void errorColor(double error, float rgb[3]);

}  // namespace gm
