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
    RgbaImage(int w, int h);  // zero-filled
    float* at(int x, int y) { return &pixels[(static_cast<size_t>(y) * width + x) * 4]; }
    const float* at(int x, int y) const {
        return &pixels[(static_cast<size_t>(y) * width + x) * 4];
    }
};

// Asks the kernel to back a large, not yet touched buffer with huge pages (Linux, transparent
// huge pages in "madvise" mode, Debian's default). Zero-filling a large render buffer otherwise
// costs a page fault per 4 KiB page, which can be most of a large render's time on a virtual
// machine. No-op for small buffers and elsewhere.
void adviseHugePages(void* data, size_t bytes);

}  // namespace gm
