// A float RGBA raster: the renderer's output and the raster readers' result.
#pragma once

#include <cstddef>
#include <vector>

namespace gm {

// Straight (unassociated) alpha; colour channels sRGB-encoded 0–1; row 0 at the top.
struct RgbaImage {
    int width = 0, height = 0;
    std::vector<float> pixels;  // 4 floats per pixel, row-major

    RgbaImage() = default;
    RgbaImage(int w, int h) : width(w), height(h), pixels(static_cast<size_t>(w) * h * 4, 0.f) {}
    float* at(int x, int y) { return &pixels[(static_cast<size_t>(y) * width + x) * 4]; }
    const float* at(int x, int y) const {
        return &pixels[(static_cast<size_t>(y) * width + x) * 4];
    }
};

}  // namespace gm
