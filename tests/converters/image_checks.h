// How a viewer sees a whole-image conversion's faults: stray pixels (badly off, far from any
// strong image edge) and the error over chosen pixels.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "meshcore/image.h"

namespace gm::test {

inline int channel255(const RgbaImage& img, int x, int y, int c) {
    return static_cast<int>(std::lround(img.at(x, y)[c] * 255));
}

// The largest channel difference at (x, y), 0-255 units.
inline int worstChannelError(const RgbaImage& a, const RgbaImage& b, int x, int y) {
    int worst = 0;
    for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(channel255(a, x, y, c) - channel255(b, x, y, c)));
    return worst;
}

// The mean channel difference at (x, y), 0-255 units.
inline double meanChannelError(const RgbaImage& a, const RgbaImage& b, int x, int y) {
    int sum = 0;
    for (int c = 0; c < 3; ++c) sum += std::abs(channel255(a, x, y, c) - channel255(b, x, y, c));
    return sum / 3.0;
}

// Pixels within 2 px of a strong edge: a morphological gradient (5x5 max minus min, the largest
// over the channels) of at least 40, dilated by 2 px.
inline std::vector<uint8_t> nearStrongEdges(const RgbaImage& img) {
    const int W = img.width, H = img.height;
    std::vector<uint8_t> strong(static_cast<size_t>(W) * H, 0), near(strong.size(), 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int c = 0; c < 3; ++c) {
                int lo = 255, hi = 0;
                for (int v = std::max(0, y - 2); v <= std::min(H - 1, y + 2); ++v)
                    for (int u = std::max(0, x - 2); u <= std::min(W - 1, x + 2); ++u) {
                        lo = std::min(lo, channel255(img, u, v, c));
                        hi = std::max(hi, channel255(img, u, v, c));
                    }
                if (hi - lo >= 40) strong[static_cast<size_t>(y) * W + x] = 1;
            }
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int v = std::max(0, y - 2); v <= std::min(H - 1, y + 2); ++v)
                for (int u = std::max(0, x - 2); u <= std::min(W - 1, x + 2); ++u)
                    if (strong[static_cast<size_t>(v) * W + u]) near[static_cast<size_t>(y) * W + x] = 1;
    return near;
}

// Pixels whose largest channel error exceeds 48 and that lie more than 2 px from a strong edge.
inline long strayPixels(const RgbaImage& image, const RgbaImage& render) {
    const std::vector<uint8_t> nearEdge = nearStrongEdges(image);
    long stray = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (worstChannelError(image, render, x, y) > 48 &&
                !nearEdge[static_cast<size_t>(y) * image.width + x])
                ++stray;
    return stray;
}

}  // namespace gm::test
