#include "segment_ink.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>

#include "meshcore/parallel_for.h"
#include "segment_ridges.h"

namespace gm {

namespace {

using Colour = cv::Vec3b;

double luma(const Colour& bgr) { return 0.114 * bgr[0] + 0.587 * bgr[1] + 0.299 * bgr[2]; }

// Where c lies as a blend of `from` and `to`: the share t of `to` (unclamped) and the distance
// from c to the nearest blend (t clamped to 0..1).
struct Blend {
    double share = 0, residual = 0;
};

Blend asBlend(const Colour& c, const Colour& from, const Colour& to) {
    double num = 0, den = 0;
    for (int k = 0; k < 3; ++k) {
        const double d = double(to[k]) - from[k];
        num += (double(c[k]) - from[k]) * d;
        den += d * d;
    }
    Blend b;
    b.share = den > 0 ? num / den : 0;
    const double t = std::clamp(b.share, 0.0, 1.0);
    double r = 0;
    for (int k = 0; k < 3; ++k) {
        const double e = c[k] - (from[k] + t * (double(to[k]) - from[k]));
        r += e * e;
    }
    b.residual = std::sqrt(r);
    return b;
}

// Per pixel: 1 on a dark ink ridge, 2 on a light one, 0 on none; the two side pixels that make
// it one and its distance from their blends.
struct Ridges {
    std::vector<uint8_t> kind;
    std::vector<std::array<Colour, 2>> sides;
    std::vector<float> contrast;
};

// The ridge kind of pixel (x, y) (InkLineOptions), its sides and contrast: of the pairs of side
// pixels that make it one, the pair it lies furthest from.
uint8_t ridgeAt(const cv::Mat& bgr, int x, int y, const InkLineOptions& o,
                std::array<Colour, 2>& sides, float& contrast) {
    const Colour c = bgr.at<Colour>(y, x);
    const double yc = luma(c);
    uint8_t kind = 0;
    double best = 0;
    forEachSidePair(bgr, x, y, o.maxSpan, [&](const Colour& sa, const Colour& sb) {
        const double dark = std::min(luma(sa), luma(sb)) - yc;
        const double light = yc - std::max(luma(sa), luma(sb));
        const double nearer = std::min(colourDistance(c, sa), colourDistance(c, sb));
        // Sides alike: a line of any hue on one surrounding.
        const bool alike = 4 * colourDistance(sa, sb) < nearer;
        if ((!alike && std::max(dark, light) < 0.5 * o.pixelContrast) || nearer < o.pixelContrast)
            return;
        const double away = asBlend(c, sa, sb).residual;
        if (away < o.pixelContrast || away <= best) return;
        best = away;
        kind = yc < 0.5 * (luma(sa) + luma(sb)) ? 1 : 2;
        sides = {sa, sb};
        contrast = static_cast<float>(away);
    });
    return kind;
}

Ridges findRidges(const cv::Mat& bgr, const InkLineOptions& o) {
    const int W = bgr.cols, H = bgr.rows;
    Ridges r;
    r.kind.assign(static_cast<size_t>(W) * H, 0);
    r.sides.resize(r.kind.size());
    r.contrast.assign(r.kind.size(), 0.f);
    parallelFor(H, o.threads, [&](int y, int) {
        for (int x = 0; x < W; ++x) {
            const size_t p = static_cast<size_t>(y) * W + x;
            r.kind[p] = ridgeAt(bgr, x, y, o, r.sides[p], r.contrast[p]);
        }
    });
    return r;
}

// The 8-connected sets of ridge pixels of one kind, neighbours joined when alike in colour.
std::vector<std::vector<int>> ridgeSets(const cv::Mat& bgr, const Ridges& r,
                                        const InkLineOptions& o) {
    const int W = bgr.cols, H = bgr.rows;
    const Colour* colour = bgr.ptr<Colour>(0);
    std::vector<uint8_t> seen(r.kind.size(), 0);
    std::vector<std::vector<int>> sets;
    for (size_t start = 0; start < r.kind.size(); ++start) {
        if (!r.kind[start] || seen[start]) continue;
        sets.push_back(flood8(static_cast<int>(start), W, H, seen, [&](int p, int q) {
            return r.kind[static_cast<size_t>(q)] == r.kind[static_cast<size_t>(p)] &&
                   colourDistance(colour[p], colour[q]) < o.joinDistance;
        }));
    }
    return sets;
}

// The set's ink colour: the mean of its quarter of pixels furthest from blends of their sides;
// false when those lie on average no further than options.contrast from them.
bool inkColourOf(const cv::Mat& bgr, const Ridges& r, const std::vector<int>& set,
                 const InkLineOptions& o, Colour& ink) {
    std::vector<std::pair<float, int>> byContrast;
    for (const int p : set) byContrast.push_back({-r.contrast[static_cast<size_t>(p)], p});
    const size_t purest = std::max<size_t>(1, byContrast.size() / 4);
    std::nth_element(byContrast.begin(), byContrast.begin() + static_cast<long>(purest - 1),
                     byContrast.end());
    const Colour* colour = bgr.ptr<Colour>(0);
    double sum[3] = {0, 0, 0}, contrast = 0;
    for (size_t i = 0; i < purest; ++i) {
        contrast -= byContrast[i].first;
        for (int k = 0; k < 3; ++k) sum[k] += colour[byContrast[i].second][k];
    }
    for (int k = 0; k < 3; ++k) ink[k] = cv::saturate_cast<uint8_t>(sum[k] / double(purest));
    return contrast / double(purest) > o.contrast;
}

// Scratch for one set at a time: a full-size mask, cleared after use.
class SetMask {
public:
    SetMask(int W, int H) : W_(W), H_(H), on_(static_cast<size_t>(W) * H, 0) {}
    void set(int p) {
        if (!on_[static_cast<size_t>(p)]) touched_.push_back(p);
        on_[static_cast<size_t>(p)] = 1;
    }
    bool operator[](int p) const { return on_[static_cast<size_t>(p)] != 0; }
    void clear() {
        for (const int p : touched_) on_[static_cast<size_t>(p)] = 0;
        touched_.clear();
    }
    // The parts of the mask at least `width` pixels wide (an opening with a width² square).
    cv::Mat wideParts(int width) {
        cv::Mat m(H_, W_, CV_8U, on_.data()), wide;
        cv::morphologyEx(m, wide, cv::MORPH_OPEN,
                         cv::getStructuringElement(cv::MORPH_RECT, {width, width}));
        return wide;
    }

private:
    int W_, H_;
    std::vector<uint8_t> on_;
    std::vector<int> touched_;
};

// The set's pixels that blend its ink with one of their sides, less its parts wider than
// maxWidth, plus their fringe (InkLineOptions).
std::vector<int> linePixels(const cv::Mat& bgr, const Ridges& r, const std::vector<int>& set,
                            const Colour& ink, const InkLineOptions& o, SetMask& mask) {
    const Colour* colour = bgr.ptr<Colour>(0);
    for (const int p : set) {
        const auto& s = r.sides[static_cast<size_t>(p)];
        if (std::min(asBlend(colour[p], s[0], ink).residual,
                     asBlend(colour[p], s[1], ink).residual) <= o.maxResidual)
            mask.set(p);
    }
    const cv::Mat wide = mask.wideParts(o.maxWidth + 1);
    std::vector<int> line;
    for (const int p : set)
        if (mask[p] && !wide.data[p]) line.push_back(p);
    const int W = bgr.cols, H = bgr.rows;
    std::vector<int> out = line;
    for (const int p : line) {
        const int x = p % W, y = p / W;
        const int next[4] = {x > 0 ? p - 1 : -1, x + 1 < W ? p + 1 : -1, y > 0 ? p - W : -1,
                             y + 1 < H ? p + W : -1};
        for (const int q : next) {
            if (q < 0 || mask[q]) continue;
            for (const Colour& side : r.sides[static_cast<size_t>(p)]) {
                const Blend b = asBlend(colour[q], side, ink);
                if (b.share >= o.minFringeShare && b.residual <= o.maxResidual) {
                    mask.set(q);
                    out.push_back(q);
                    break;
                }
            }
        }
    }
    mask.clear();
    return out;
}

// The 8-connected pieces of `pixels` with at least minPixels pixels. `seen`: width*height
// zeros, left so.
std::vector<std::vector<int>> pieces(const std::vector<int>& pixels, int W, int H, long minPixels,
                                     SetMask& mask, std::vector<uint8_t>& seen) {
    for (const int p : pixels) mask.set(p);
    std::vector<std::vector<int>> out;
    for (const int p : pixels) {
        if (seen[static_cast<size_t>(p)]) continue;
        std::vector<int> piece = flood8(p, W, H, seen, [&](int, int q) { return mask[q]; });
        if (static_cast<long>(piece.size()) >= minPixels) out.push_back(std::move(piece));
    }
    for (const int p : pixels) seen[static_cast<size_t>(p)] = 0;
    mask.clear();
    return out;
}

// The mean over the piece's ridge pixels of the ink's distance from the nearer of their two
// side pixels (0-255 RGB distance).
double sideDistance(const Ridges& r, const std::vector<int>& piece, const Colour& ink) {
    double sum = 0;
    long n = 0;
    for (const int p : piece) {
        const size_t q = static_cast<size_t>(p);
        if (!r.kind[q]) continue;
        sum += std::min(colourDistance(r.sides[q][0], ink), colourDistance(r.sides[q][1], ink));
        ++n;
    }
    return n > 0 ? sum / double(n) : 0;
}

// Gives `label` to the piece's pixels that no earlier piece took (`inkMask` 0) and, where two of
// them touch only diagonally, to the one of the two pixels between them closer to the ink in
// colour, so that the label is 4-connected where no other ink is in the way; marks them in
// inkMask.
void labelPiece(const cv::Mat& bgr, const std::vector<int>& piece, const Colour& ink, int label,
                std::vector<int>& labels, std::vector<uint8_t>& inkMask) {
    std::vector<int> own;  // the piece less what earlier pieces took
    for (const int p : piece)
        if (!inkMask[static_cast<size_t>(p)]) own.push_back(p);
    const std::vector<int> between = labelFourConnected(
        bgr, own, label, {double(ink[0]), double(ink[1]), double(ink[2])}, labels,
        [&](int p) { return inkMask[static_cast<size_t>(p)] != 0; });
    for (const int p : own) inkMask[static_cast<size_t>(p)] = 1;
    for (const int p : between) inkMask[static_cast<size_t>(p)] = 1;
}

// One piece of an ink line and its ink colour.
struct Piece {
    std::vector<int> pixels;
    Colour ink;
};

// The pieces of ink lines (InkLineOptions) among the pixels not yet set in `ink` and labelled
// under `count`.
std::vector<Piece> inkLinePieces(const cv::Mat& bgr, const std::vector<int>& labels, int count,
                                 const std::vector<uint8_t>& ink, const InkLineOptions& options) {
    const int W = bgr.cols, H = bgr.rows;
    Ridges ridges = findRidges(bgr, options);
    for (size_t p = 0; p < ridges.kind.size(); ++p)
        if (ink[p] || labels[p] >= count) ridges.kind[p] = 0;
    SetMask mask(W, H);
    std::vector<uint8_t> seen(static_cast<size_t>(W) * H, 0);
    std::vector<Piece> found;
    for (const std::vector<int>& set : ridgeSets(bgr, ridges, options)) {
        Colour inkColour;
        if (static_cast<long>(set.size()) < options.minPixels ||
            !inkColourOf(bgr, ridges, set, options, inkColour))
            continue;
        const std::vector<int> line = linePixels(bgr, ridges, set, inkColour, options, mask);
        if (static_cast<long>(line.size()) < options.minPixels) continue;
        for (std::vector<int>& piece : pieces(line, W, H, options.minPiece, mask, seen))
            if (sideDistance(ridges, piece, inkColour) >= options.minSideDistance)
                found.push_back({std::move(piece), inkColour});
    }
    return found;
}

// The share of the pixels on the labels' borders (with a 4-neighbour of another label) that lie
// within two pixels of a piece.
double inkedBorderShare(const std::vector<int>& labels, int W, int H,
                        const std::vector<Piece>& found) {
    cv::Mat onPiece(H, W, CV_8U, cv::Scalar(0)), near;
    for (const Piece& piece : found)
        for (const int p : piece.pixels) onPiece.data[p] = 1;
    cv::dilate(onPiece, near, cv::getStructuringElement(cv::MORPH_RECT, {5, 5}));
    long border = 0, inked = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int p = y * W + x, l = labels[static_cast<size_t>(p)];
            const bool onBorder = (x + 1 < W && labels[static_cast<size_t>(p + 1)] != l) ||
                                  (y + 1 < H && labels[static_cast<size_t>(p + W)] != l);
            border += onBorder;
            inked += onBorder && near.data[p];
        }
    return border > 0 ? double(inked) / double(border) : 0;
}

}  // namespace

int liftInkLines(const cv::Mat& bgr, std::vector<int>& labels, int count,
                 std::vector<uint8_t>& ink, const InkLineOptions& options) {
    const int W = bgr.cols, H = bgr.rows;
    if (options.contrast <= 0 || W < 3 || H < 3) return count;
    const std::vector<Piece> found = inkLinePieces(bgr, labels, count, ink, options);
    if (inkedBorderShare(labels, W, H, found) < options.minInkedBorders) return count;
    for (const Piece& piece : found)
        labelPiece(bgr, piece.pixels, piece.ink, count++, labels, ink);
    return count;
}

}  // namespace gm
