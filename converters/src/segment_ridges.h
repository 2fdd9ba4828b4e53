// What the full-size line finders (segment_thin.h, segment_ink.h) share: the pairs of pixels on
// either side of a pixel, colour distances, 8-connected flood fills, and how a found line
// becomes a 4-connected label.
#pragma once

#include <opencv2/core.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace gm {

// RGB distance, 0-255 units.
inline double colourDistance(const cv::Vec3b& a, const cv::Vec3b& b) {
    double d = 0;
    for (int k = 0; k < 3; ++k) d += (double(a[k]) - b[k]) * (double(a[k]) - b[k]);
    return std::sqrt(d);
}

inline double colourDistance(const cv::Vec3b& a, const std::array<double, 3>& b) {
    double d = 0;
    for (int k = 0; k < 3; ++k) d += (a[k] - b[k]) * (a[k] - b[k]);
    return std::sqrt(d);
}

// Calls visit(a, b) for every pair of pixels of `bgr` (8-bit BGR) a >= 1 steps before and b >= 1
// after (x, y), a + b <= maxSpan, along each of the four directions, both inside the image.
template <class Visit>
void forEachSidePair(const cv::Mat& bgr, int x, int y, int maxSpan, Visit visit) {
    static const int kDirs[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
    for (const auto& d : kDirs)
        for (int a = 1; a < maxSpan; ++a)
            for (int b = 1; a + b <= maxSpan; ++b) {
                const int xa = x - a * d[0], ya = y - a * d[1], xb = x + b * d[0], yb = y + b * d[1];
                if (xa < 0 || ya < 0 || ya >= bgr.rows || xb >= bgr.cols || yb < 0 ||
                    yb >= bgr.rows)
                    continue;
                visit(bgr.at<cv::Vec3b>(ya, xa), bgr.at<cv::Vec3b>(yb, xb));
            }
}

// The pixels reached from `start` through 8-neighbours for which `joins(p, q)` holds, marking
// them in `seen`.
template <class Joins>
std::vector<int> flood8(int start, int W, int H, std::vector<uint8_t>& seen, Joins joins) {
    std::vector<int> out, stack{start};
    seen[static_cast<size_t>(start)] = 1;
    while (!stack.empty()) {
        const int p = stack.back();
        stack.pop_back();
        out.push_back(p);
        const int x = p % W, y = p / W;
        for (int v = std::max(0, y - 1); v <= std::min(H - 1, y + 1); ++v)
            for (int u = std::max(0, x - 1); u <= std::min(W - 1, x + 1); ++u) {
                const int q = v * W + u;
                if (!seen[static_cast<size_t>(q)] && joins(p, q)) {
                    seen[static_cast<size_t>(q)] = 1;
                    stack.push_back(q);
                }
            }
    }
    return out;
}

// Gives `label` to `pixels` and, where two of them touch only diagonally, to the one of the two
// pixels between them closer in colour to `reference`, unless either of those is `blocked(p)`:
// the label is 4-connected where nothing blocks it. Returns the pixels added between.
template <class Blocked>
std::vector<int> labelFourConnected(const cv::Mat& bgr, const std::vector<int>& pixels, int label,
                                    const std::array<double, 3>& reference,
                                    std::vector<int>& labels, Blocked blocked) {
    const int W = bgr.cols, H = bgr.rows;
    const cv::Vec3b* colour = bgr.ptr<cv::Vec3b>(0);
    for (const int p : pixels) labels[static_cast<size_t>(p)] = label;
    std::vector<int> between;
    for (const int p : pixels) {
        const int x = p % W, y = p / W;
        if (y + 1 >= H) continue;
        for (const int dx : {-1, 1}) {
            if (x + dx < 0 || x + dx >= W) continue;
            const int diag = p + W + dx, side = p + dx, below = p + W;
            if (labels[diag] != label || labels[side] == label || labels[below] == label ||
                blocked(side) || blocked(below))
                continue;
            between.push_back(colourDistance(colour[side], reference) <=
                                      colourDistance(colour[below], reference)
                                  ? side
                                  : below);
            labels[static_cast<size_t>(between.back())] = label;
        }
    }
    return between;
}

}  // namespace gm
