#include "segment_borders.h"

#include <algorithm>
#include <array>
#include <atomic>

#include "meshcore/parallel_for.h"

namespace gm {

namespace {

// Labels of the small image, with the neighbourhood questions the refinement asks.
struct SmallLabels {
    const std::vector<int>& label;
    int width, height;
    std::vector<unsigned char> nearBorder;  // the 3×3 window holds two labels or more

    int at(int x, int y) const { return label[static_cast<size_t>(y) * width + x]; }

    // Distinct labels (≥ 0) in the (2r+1)² window around (x, y), at most out.size().
    int distinctAround(int x, int y, int r, std::array<int, 25>& out) const {
        int n = 0;
        for (int yy = std::max(0, y - r); yy <= std::min(height - 1, y + r); ++yy)
            for (int xx = std::max(0, x - r); xx <= std::min(width - 1, x + r); ++xx) {
                const int l = at(xx, yy);
                if (l >= 0 && std::find(out.begin(), out.begin() + n, l) == out.begin() + n &&
                    n < static_cast<int>(out.size()))
                    out[n++] = l;
            }
        return n;
    }

    bool isNearBorder(int x, int y) const { return nearBorder[static_cast<size_t>(y) * width + x]; }
    bool interior(int x, int y) const { return at(x, y) >= 0 && !isNearBorder(x, y); }
};

// A label that a pixel near a border may take, with its colour around there.
struct Candidate {
    int label = -1;
    float mean[3] = {0, 0, 0};
};

// Mean colour of the small pixels labelled `label` in the 5×5 window around (x, y): its
// interior pixels when there are any (border pixels of the small image mix both sides'
// colours), else all of them.
Candidate localColor(const cv::Mat& smallBgr, const SmallLabels& labels, int x, int y,
                      int label) {
    double sum[2][3] = {{0, 0, 0}, {0, 0, 0}};
    int count[2] = {0, 0};
    for (int yy = std::max(0, y - 2); yy <= std::min(labels.height - 1, y + 2); ++yy)
        for (int xx = std::max(0, x - 2); xx <= std::min(labels.width - 1, x + 2); ++xx) {
            if (labels.at(xx, yy) != label) continue;
            const int kind = labels.interior(xx, yy) ? 0 : 1;
            const cv::Vec3b c = smallBgr.at<cv::Vec3b>(yy, xx);
            for (int k = 0; k < 3; ++k) sum[kind][k] += c[k];
            ++count[kind];
        }
    const int use = count[0] > 0 ? 0 : 1;
    Candidate cand;
    cand.label = label;
    for (int k = 0; k < 3; ++k) cand.mean[k] = static_cast<float>(sum[use][k] / std::max(1, count[use]));
    return cand;
}

// The candidates of small pixel (x, y): every label of its 3×3 window, with local colours.
int candidatesAt(const cv::Mat& smallBgr, const SmallLabels& labels, int x, int y,
                 std::array<Candidate, 9>& out) {
    std::array<int, 25> distinct;
    const int n = std::min(9, labels.distinctAround(x, y, 1, distinct));
    for (int i = 0; i < n; ++i) out[i] = localColor(smallBgr, labels, x, y, distinct[i]);
    return n;
}

int closestCandidate(const cv::Vec3b& colour, const std::array<Candidate, 9>& cands, int n) {
    int best = cands[0].label;
    float bestDist = 1e30f;
    for (int i = 0; i < n; ++i) {
        float d = 0;
        for (int k = 0; k < 3; ++k) {
            const float e = colour[k] - cands[i].mean[k];
            d += e * e;
        }
        if (d < bestDist) {
            bestDist = d;
            best = cands[i].label;
        }
    }
    return best;
}

}  // namespace

std::vector<int> upscaleLabelsRefined(const cv::Mat& smallBgr, const std::vector<int>& small,
                                      const cv::Mat& fullBgr, int threads, long* changed) {
    const int ws = smallBgr.cols, hs = smallBgr.rows, W = fullBgr.cols, H = fullBgr.rows;
    SmallLabels labels{small, ws, hs, std::vector<unsigned char>(static_cast<size_t>(ws) * hs)};
    // The small pixel each full pixel falls in (as plain nearest-neighbour upscaling).
    std::vector<int> sx(W);
    for (int x = 0; x < W; ++x) sx[x] = std::min(ws - 1, static_cast<int>((x + 0.5) * ws / W));
    // The full pixels of small pixels near a border are refined.
    parallelFor(hs, threads, [&](int y, int) {
        std::array<int, 25> seen;
        for (int x = 0; x < ws; ++x)
            labels.nearBorder[static_cast<size_t>(y) * ws + x] = labels.distinctAround(x, y, 1, seen) > 1;
    });
    std::vector<int> full(static_cast<size_t>(W) * H);
    std::atomic<long> changedCount{0};
    parallelFor(H, threads, [&](int y, int) {
        const int syy = std::min(hs - 1, static_cast<int>((y + 0.5) * hs / H));
        const auto* colours = fullBgr.ptr<cv::Vec3b>(y);
        int* row = &full[static_cast<size_t>(y) * W];
        std::array<Candidate, 9> cands;
        int candCount = 0, candFor = -1;  // candidates of small pixel (candFor, syy)
        long rowChanged = 0;
        for (int x = 0; x < W; ++x) {
            const int q = sx[x];
            const int plain = labels.at(q, syy);
            row[x] = plain;
            if (plain < 0 || !labels.isNearBorder(q, syy)) continue;
            if (candFor != q) {
                candCount = candidatesAt(smallBgr, labels, q, syy, cands);
                candFor = q;
            }
            row[x] = closestCandidate(colours[x], cands, candCount);
            rowChanged += row[x] != plain;
        }
        changedCount += rowChanged;
    });
    if (changed) *changed = changedCount;
    return full;
}

}  // namespace gm
