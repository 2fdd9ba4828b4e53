#include "segment_thin.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>

#include "meshcore/parallel_for.h"
#include "segment_ridges.h"

namespace gm {

namespace {

// Per pixel: 1 on a ridge, with the mean of the side pixels that made it one in `sides`.
struct Ridges {
    std::vector<uint8_t> on;
    std::vector<std::array<float, 3>> sides;
};

// Whether pixel (x, y) is on a ridge (ThinStructureOptions); the mean colour of its sides in
// `side`: of the pairs that make it one, the pair furthest from it (the surroundings rather
// than the structure's own anti-aliased fringe).
bool ridgeAt(const cv::Mat& bgr, int x, int y, const ThinStructureOptions& o,
             std::array<float, 3>& side) {
    const cv::Vec3b c = bgr.at<cv::Vec3b>(y, x);
    double best = 0;
    forEachSidePair(bgr, x, y, o.maxSpan, [&](const cv::Vec3b& sa, const cv::Vec3b& sb) {
        const double away = std::min(colourDistance(c, sa), colourDistance(c, sb));
        if (away < o.pixelContrast || 4 * colourDistance(sa, sb) >= away || away <= best)
            return;
        best = away;
        for (int k = 0; k < 3; ++k) side[k] = 0.5f * (sa[k] + sb[k]);
    });
    return best > 0;
}

Ridges findRidges(const cv::Mat& bgr, const ThinStructureOptions& o) {
    const int W = bgr.cols, H = bgr.rows;
    Ridges r;
    r.on.assign(static_cast<size_t>(W) * H, 0);
    r.sides.assign(r.on.size(), {0, 0, 0});
    parallelFor(H, o.threads, [&](int y, int) {
        for (int x = 0; x < W; ++x) {
            const size_t p = static_cast<size_t>(y) * W + x;
            r.on[p] = ridgeAt(bgr, x, y, o, r.sides[p]);
        }
    });
    return r;
}

// One 8-connected set of ridge pixels.
struct RidgeSet {
    std::vector<int> pixels;
    double mean[3] = {0, 0, 0}, side[3] = {0, 0, 0};
    double sideSpread = 0;  // RMS distance of the pixels' side colours from their mean
};

std::vector<RidgeSet> ridgeSets(const cv::Mat& bgr, const Ridges& r) {
    const int W = bgr.cols, H = bgr.rows;
    std::vector<uint8_t> seen(r.on.size(), 0);
    std::vector<RidgeSet> sets;
    const cv::Vec3b* colour = bgr.ptr<cv::Vec3b>(0);
    for (size_t start = 0; start < r.on.size(); ++start) {
        if (!r.on[start] || seen[start]) continue;
        RidgeSet set;
        set.pixels = flood8(static_cast<int>(start), W, H, seen,
                            [&](int, int q) { return r.on[static_cast<size_t>(q)] != 0; });
        for (const int p : set.pixels)
            for (int k = 0; k < 3; ++k) {
                set.side[k] += r.sides[static_cast<size_t>(p)][k];
                set.mean[k] += colour[p][k];
            }
        for (int k = 0; k < 3; ++k) {
            set.mean[k] /= set.pixels.size();
            set.side[k] /= set.pixels.size();
        }
        for (const int p : set.pixels)
            for (int k = 0; k < 3; ++k) {
                const double e = r.sides[static_cast<size_t>(p)][k] - set.side[k];
                set.sideSpread += e * e;
            }
        set.sideSpread = std::sqrt(set.sideSpread / set.pixels.size());
        sets.push_back(std::move(set));
    }
    return sets;
}

// Whether the pixels enclose others: some pixel of its bounding box's complement
// cannot be reached from outside the box through 4-neighbours not in the set.
bool enclosesSomething(const std::vector<int>& pixels, int W) {
    int x0 = W, y0 = 1 << 30, x1 = -1, y1 = -1;
    for (const int p : pixels) {
        x0 = std::min(x0, p % W), x1 = std::max(x1, p % W);
        y0 = std::min(y0, p / W), y1 = std::max(y1, p / W);
    }
    const int bw = x1 - x0 + 3, bh = y1 - y0 + 3;  // the box with a free pixel all round
    std::vector<uint8_t> state(static_cast<size_t>(bw) * bh, 0);  // 1 set, 2 reached
    for (const int p : pixels)
        state[static_cast<size_t>(p / W - y0 + 1) * bw + (p % W - x0 + 1)] = 1;
    std::vector<int> stack{0};
    state[0] = 2;
    long reached = 1;
    while (!stack.empty()) {
        const int q = stack.back();
        stack.pop_back();
        const int x = q % bw, y = q / bw;
        const int next[4] = {x > 0 ? q - 1 : -1, x + 1 < bw ? q + 1 : -1, y > 0 ? q - bw : -1,
                             y + 1 < bh ? q + bw : -1};
        for (const int n : next)
            if (n >= 0 && state[static_cast<size_t>(n)] == 0) {
                state[static_cast<size_t>(n)] = 2;
                stack.push_back(n);
                ++reached;
            }
    }
    return reached + static_cast<long>(pixels.size()) < static_cast<long>(state.size());
}

// Whether the pixels are one 4-connected set.
bool fourConnected(const std::vector<int>& pixels, int W, int H) {
    if (pixels.empty()) return false;
    std::vector<uint8_t> in(static_cast<size_t>(W) * H, 0);
    for (const int p : pixels) in[static_cast<size_t>(p)] = 1;
    std::vector<int> stack{pixels.front()};
    in[static_cast<size_t>(pixels.front())] = 2;
    size_t reached = 1;
    while (!stack.empty()) {
        const int q = stack.back();
        stack.pop_back();
        const int x = q % W, y = q / W;
        const int next[4] = {x > 0 ? q - 1 : -1, x + 1 < W ? q + 1 : -1, y > 0 ? q - W : -1,
                             y + 1 < H ? q + W : -1};
        for (const int n : next)
            if (n >= 0 && in[static_cast<size_t>(n)] == 1) {
                in[static_cast<size_t>(n)] = 2;
                stack.push_back(n);
                ++reached;
            }
    }
    return reached == pixels.size();
}

// The pixels cut in two across their longer side at their centroid.
std::array<std::vector<int>, 2> cutInTwo(const std::vector<int>& pixels, int W) {
    double cx = 0, cy = 0;
    int x0 = W, y0 = 1 << 30, x1 = -1, y1 = -1;
    for (const int p : pixels) {
        cx += p % W, cy += p / W;
        x0 = std::min(x0, p % W), x1 = std::max(x1, p % W);
        y0 = std::min(y0, p / W), y1 = std::max(y1, p / W);
    }
    cx /= pixels.size(), cy /= pixels.size();
    const bool acrossX = x1 - x0 >= y1 - y0;
    std::array<std::vector<int>, 2> halves;
    for (const int p : pixels) halves[acrossX ? (p % W < cx) : (p / W < cy)].push_back(p);
    return halves;
}

// Per label: whether every pixel lies within maxSteps 4-neighbour steps of another label.
std::vector<uint8_t> thinLabels(const std::vector<int>& labels, int W, int H, int count,
                                int maxSteps) {
    cv::Mat interior(H, W, CV_8U, cv::Scalar(255));  // 0 where a 4-neighbour is foreign
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const size_t p = static_cast<size_t>(y) * W + x;
            const int l = labels[p];
            if ((x > 0 && labels[p - 1] != l) || (x + 1 < W && labels[p + 1] != l) ||
                (y > 0 && labels[p - W] != l) || (y + 1 < H && labels[p + W] != l))
                interior.at<uint8_t>(y, x) = 0;
        }
    cv::Mat dist;
    cv::distanceTransform(interior, dist, cv::DIST_L1, 3);
    std::vector<uint8_t> thin(static_cast<size_t>(count), 1);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (dist.at<float>(y, x) > maxSteps)
                thin[static_cast<size_t>(labels[static_cast<size_t>(y) * W + x])] = 0;
    return thin;
}

}  // namespace

int liftThinStructures(const cv::Mat& bgr, std::vector<int>& labels, int count,
                       const ThinStructureOptions& options) {
    if (options.contrast <= 0 || bgr.cols < 3 || bgr.rows < 3) return count;
    const Ridges ridges = findRidges(bgr, options);
    for (const RidgeSet& set : ridgeSets(bgr, ridges)) {
        if (static_cast<long>(set.pixels.size()) < options.minPixels) continue;
        double d = 0;
        for (int k = 0; k < 3; ++k) d += (set.mean[k] - set.side[k]) * (set.mean[k] - set.side[k]);
        if (d <= options.contrast * options.contrast ||
            set.sideSpread > options.maxSideSpread * std::sqrt(d))
            continue;
        labelFourConnected(bgr, set.pixels, count++, {set.mean[0], set.mean[1], set.mean[2]},
                           labels, [](int) { return false; });
    }
    return count;
}

long growThinStructures(const cv::Mat& bgr, std::vector<int>& labels, int firstThin, int count,
                        double contrast) {
    if (firstThin >= count) return 0;
    const int W = bgr.cols, H = bgr.rows;
    // Each label's mean colour, before any pixel moves.
    std::vector<std::array<double, 3>> mean(static_cast<size_t>(count), {0, 0, 0});
    std::vector<long> size(static_cast<size_t>(count), 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int l = labels[static_cast<size_t>(y) * W + x];
            const cv::Vec3b c = bgr.at<cv::Vec3b>(y, x);
            for (int k = 0; k < 3; ++k) mean[static_cast<size_t>(l)][k] += c[k];
            ++size[static_cast<size_t>(l)];
        }
    for (int l = 0; l < count; ++l)
        for (double& v : mean[static_cast<size_t>(l)]) v /= std::max(1L, size[static_cast<size_t>(l)]);
    const auto distance = [&](const cv::Vec3b& c, int l) {
        return colourDistance(c, mean[static_cast<size_t>(l)]);
    };
    std::vector<int> queue;
    for (size_t p = 0; p < labels.size(); ++p)
        if (labels[p] >= firstThin) queue.push_back(static_cast<int>(p));
    long taken = 0;
    for (size_t head = 0; head < queue.size(); ++head) {
        const int p = queue[head], x = p % W, y = p / W, own = labels[static_cast<size_t>(p)];
        const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
        for (int d = 0; d < 4; ++d) {
            if (nx[d] < 0 || ny[d] < 0 || nx[d] >= W || ny[d] >= H) continue;
            const int q = ny[d] * W + nx[d];
            const int other = labels[static_cast<size_t>(q)];
            if (other >= firstThin) continue;
            const cv::Vec3b c = bgr.at<cv::Vec3b>(ny[d], nx[d]);
            const double toOwn = distance(c, own);
            if (toOwn >= 0.5 * contrast || toOwn >= 0.5 * distance(c, other)) continue;
            labels[static_cast<size_t>(q)] = own;
            queue.push_back(q);
            ++taken;
        }
    }
    return taken;
}

int cutThinLoops(std::vector<int>& labels, int W, int H, int count, int maxSteps,
                 long minPixels) {
    const std::vector<uint8_t> thin = thinLabels(labels, W, H, count, maxSteps);
    std::vector<std::vector<int>> pixels(static_cast<size_t>(count));
    for (size_t p = 0; p < labels.size(); ++p)
        if (thin[static_cast<size_t>(labels[p])])
            pixels[static_cast<size_t>(labels[p])].push_back(static_cast<int>(p));
    for (const std::vector<int>& own : pixels) {
        if (own.empty() || !enclosesSomething(own, W)) continue;
        const auto halves = cutInTwo(own, W);
        if (static_cast<long>(std::min(halves[0].size(), halves[1].size())) < minPixels ||
            !fourConnected(halves[0], W, H) || !fourConnected(halves[1], W, H))
            continue;
        for (const int p : halves[1]) labels[static_cast<size_t>(p)] = count;
        ++count;
    }
    return count;
}

}  // namespace gm
