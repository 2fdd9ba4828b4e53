// Helpers for the segmentation tests: synthetic images and the label-map contract.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "converters/segment.h"
#include "meshcore/image.h"

namespace gm::test {

// An opaque image whose pixel (x, y) takes the colour f(x + .5, y + .5).
inline RgbaImage paint(int w, int h, const std::function<void(double, double, float*)>& f) {
    RgbaImage im(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = im.at(x, y);
            f(x + .5, y + .5, p);
            p[3] = 1;
        }
    return im;
}

// Whether every pixel of label l lies within 3 4-neighbour steps of another label (a line or
// an arc up to about 7 px wide).
inline bool thinLabel(const Segmentation& s, int l) {
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            if (s.labels[static_cast<size_t>(y) * s.width + x] != l) continue;
            bool near = false;
            for (int dy = -3; dy <= 3 && !near; ++dy)
                for (int dx = -3 + std::abs(dy); dx <= 3 - std::abs(dy) && !near; ++dx) {
                    const int u = x + dx, v = y + dy;
                    near = u >= 0 && v >= 0 && u < s.width && v < s.height &&
                           s.labels[static_cast<size_t>(v) * s.width + u] != l;
                }
            if (!near) return false;
        }
    return true;
}

// What a Segmentation must be; an empty string when it is all of it. With thinMinRegion > 0
// (the default minRegion's contract), a thin label may have as few as thinMinRegion pixels.
inline std::string labelMapProblem(const Segmentation& s, long minRegion,
                                   long thinMinRegion = 0) {
    const int W = s.width, H = s.height;
    const size_t N = static_cast<size_t>(W) * H;
    if (s.labels.size() != N) return "labels has the wrong size";
    if (s.count < 1) return "no region";
    std::vector<long> size(s.count, 0);
    for (int l : s.labels) {
        if (l < 0 || l >= s.count) return "label " + std::to_string(l) + " out of range";
        ++size[l];
    }
    // The ink lines come last (each group ordered by size) and, under the default minimum
    // region, may be as small as 16 pixels.
    const int firstInk = s.count - s.inkLabels;
    for (int l = 0; l < s.count; ++l) {
        if (size[l] == 0) return "label " + std::to_string(l) + " unused (not dense)";
        const long least = l >= firstInk && thinMinRegion > 0 ? std::min(minRegion, 16L) : minRegion;
        if (s.count > 1 && size[l] < least &&
            !(thinMinRegion > 0 && size[l] >= thinMinRegion && thinLabel(s, l)))
            return "label " + std::to_string(l) + " has " + std::to_string(size[l]) +
                   " pixels, under " + std::to_string(least);
        if (l > 0 && l != firstInk && size[l] > size[l - 1]) return "labels not ordered by size";
    }
    // Each label one 4-connected component: flood each label from its first pixel.
    std::vector<uint8_t> seen(N, 0);
    std::vector<int> stack;
    std::vector<uint8_t> started(s.count, 0);
    for (size_t start = 0; start < N; ++start) {
        if (seen[start]) continue;
        const int l = s.labels[start];
        if (started[l]) return "label " + std::to_string(l) + " is not 4-connected";
        started[l] = 1;
        seen[start] = 1;
        stack.push_back(static_cast<int>(start));
        while (!stack.empty()) {
            const int p = stack.back();
            stack.pop_back();
            const int x = p % W, y = p / W;
            const int nb[4] = {x > 0 ? p - 1 : -1, x + 1 < W ? p + 1 : -1, y > 0 ? p - W : -1,
                               y + 1 < H ? p + W : -1};
            for (int q : nb)
                if (q >= 0 && !seen[q] && s.labels[q] == l) {
                    seen[q] = 1;
                    stack.push_back(q);
                }
        }
    }
    return {};
}

inline long defaultMinRegion(int w, int h) {
    return std::max(64L, static_cast<long>(w) * h / 1000);
}

// Pixels where the label map disagrees with a two-region truth (inside → one label, outside →
// the other), under the better of the two ways of matching the labels.
inline long twoRegionMismatch(const Segmentation& s, const std::function<bool(double, double)>& in) {
    long a = 0, b = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const int l = s.labels[static_cast<size_t>(y) * s.width + x];
            const bool i = in(x + .5, y + .5);
            a += (l == 0) != i;
            b += (l == 1) != i;
        }
    return std::min(a, b);
}

}  // namespace gm::test
