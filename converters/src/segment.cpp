#include "converters/segment.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/segmentation.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <unordered_map>
#include <utility>

#include "meshcore/error.h"
#include "meshcore/parallel_for.h"
#include "opencv_memory.h"
#include "segment_borders.h"
#include "segment_ink.h"
#include "segment_thin.h"

namespace gm {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// 8-bit BGR (OpenCV's order), colour premultiplied by alpha.
cv::Mat toBgr8(const RgbaImage& image) {
    cv::Mat bgr(image.height, image.width, CV_8UC3);
    for (int y = 0; y < image.height; ++y) {
        auto* row = bgr.ptr<cv::Vec3b>(y);
        for (int x = 0; x < image.width; ++x) {
            const float* p = image.at(x, y);
            const float a = std::clamp(p[3], 0.f, 1.f);
            for (int c = 0; c < 3; ++c)
                row[x][2 - c] =
                    static_cast<uint8_t>(std::lround(std::clamp(p[c], 0.f, 1.f) * a * 255));
        }
    }
    return bgr;
}

float colourDist2(const cv::Vec3b& c, const double* mean) {
    const double d0 = c[0] - mean[0], d1 = c[1] - mean[1], d2 = c[2] - mean[2];
    return static_cast<float>(d0 * d0 + d1 * d1 + d2 * d2);
}

struct MergeResult {
    int count = 0, components = 0;
    long merged = 0, weakMerged = 0;
};
struct MergeParams {
    long minRegion = 1;
    int sliverWidth = 0;
    double weakEdge = 0;
    // Components of labels from `firstKept` on (liftDistinctPieces), or of at least
    // keptMinSize pixels, whose mean colour lies further than `keepContrast` (RGB distance,
    // 0–255 units) from every neighbour's are not merged for their size (0: all are).
    int firstKept = std::numeric_limits<int>::max();
    long keptMinSize = std::numeric_limits<long>::max();
    double keepContrast = 0;
    double thinContrast = 0;  // thin components this distinct are kept (mergeSmallAndThin)
    // When set (width*height): components mostly of these pixels (ink lines), and those wholly
    // enclosed by them, of at least minInkPiece pixels are never merged; ink takes in a
    // neighbour only when it has no other; of the other components, only the pieces that a
    // label lost to ink, and a label's largest component when under minKeptPiece, are merged.
    const std::vector<uint8_t>* ink = nullptr;
    long minInkPiece = 0, minKeptPiece = 0;
};
MergeResult mergeRegions(const cv::Mat& bgr, std::vector<int>& labels, const MergeParams& mp);

// ---------------------------------------------------------------------------------------
// (1) Felzenszwalb–Huttenlocher on the working image, cleaned of slivers and of pieces under
// the minimum size there already (FH's own minimum-size pass works on 8-connected pieces).

struct FhRun {
    std::vector<int> labels;  // working image, dense
    int count = 0, rawCount = 0;
};

// OpenCV's FH labels of the working image for threshold k and minimum piece size minSize.
std::vector<int> fhLabels(const cv::Mat& work, double k, double sigma, int minSize) {
    cv::Mat fh;
    auto gs = cv::ximgproc::segmentation::createGraphSegmentation(sigma, static_cast<float>(k),
                                                                   minSize);
    gs->processImage(work, fh);
    return std::vector<int>(fh.begin<int>(), fh.end<int>());
}

// FH's minimum-size pass joins a small piece to a neighbour across its weakest edge however
// strong that edge is: a small object ends inside its surroundings' region, whose mesh then
// paints the object's colour smoothly across its own, well outside the object. The same k
// with a smaller minimum size (`fine`) splits no less, so each of its pieces lies in one region
// of `coarse`; a piece of at least minPiece pixels whose mean colour lies further than
// `contrast` from the rest of its region's gets a label of its own. Returns the label count.
int liftDistinctPieces(const cv::Mat& work, const std::vector<int>& fine,
                       std::vector<int>& coarse, long minPiece, double contrast) {
    const int fineCount = *std::max_element(fine.begin(), fine.end()) + 1;
    const int coarseCount = *std::max_element(coarse.begin(), coarse.end()) + 1;
    struct Stats {
        long size = 0;
        double sum[3] = {0, 0, 0};
    };
    std::vector<Stats> piece(static_cast<size_t>(fineCount)), region(static_cast<size_t>(coarseCount));
    std::vector<int> regionOf(static_cast<size_t>(fineCount), -1);
    const cv::Vec3b* colour = work.ptr<cv::Vec3b>(0);
    for (size_t p = 0; p < fine.size(); ++p) {
        for (Stats* st : {&piece[static_cast<size_t>(fine[p])], &region[static_cast<size_t>(coarse[p])]}) {
            ++st->size;
            for (int c = 0; c < 3; ++c) st->sum[c] += colour[p][c];
        }
        regionOf[static_cast<size_t>(fine[p])] = coarse[p];
    }
    std::vector<int> lifted(static_cast<size_t>(fineCount), -1);
    int count = coarseCount;
    for (int f = 0; f < fineCount; ++f) {
        const Stats& a = piece[static_cast<size_t>(f)];
        if (a.size < std::max(1L, minPiece)) continue;
        const Stats& r = region[static_cast<size_t>(regionOf[static_cast<size_t>(f)])];
        if (2 * a.size >= r.size) continue;
        double d2 = 0;
        for (int c = 0; c < 3; ++c) {
            const double e = a.sum[c] / a.size - (r.sum[c] - a.sum[c]) / (r.size - a.size);
            d2 += e * e;
        }
        if (d2 > contrast * contrast) lifted[static_cast<size_t>(f)] = count++;
    }
    for (size_t p = 0; p < fine.size(); ++p)
        if (lifted[static_cast<size_t>(fine[p])] >= 0) coarse[p] = lifted[static_cast<size_t>(fine[p])];
    return count;
}

// FH with minimum size minSize, its distinct smaller pieces (of at least noiseSize) lifted out,
// then cleaned: slivers and pieces under minSize merged by colour, the lifted ones kept.
FhRun runFh(const cv::Mat& work, double k, const SegmentOptions& o, int minSize, int noiseSize) {
    FhRun run;
    run.labels = fhLabels(work, k, o.sigma, minSize);
    run.rawCount = *std::max_element(run.labels.begin(), run.labels.end()) + 1;
    MergeParams merge{minSize, o.sliverWidth, o.weakEdge};
    merge.thinContrast = o.distinctContrast;
    if (o.distinctContrast > 0 && noiseSize < minSize) {
        merge.firstKept = run.rawCount;
        merge.keptMinSize = noiseSize;
        merge.keepContrast = o.distinctContrast;
        run.rawCount = liftDistinctPieces(work, fhLabels(work, k, o.sigma, noiseSize), run.labels,
                                          noiseSize, o.distinctContrast);
    }
    run.count = mergeRegions(work, run.labels, merge).count;
    return run;
}

// Uses the given k, the default k, or, for `segments`, searches k by bisection in log k
// towards that many regions (the count falls with k, though not strictly; the run closest to
// the target in ratio is kept, the larger k on ties).
FhRun graphSegment(const cv::Mat& work, const SegmentOptions& o, int minSize, int noiseSize,
                   SegmentStats& st) {
    if (work.total() < 4) {  // nothing to segment; OpenCV's FH wants edges
        FhRun run;
        run.labels.assign(work.total(), 0);
        run.count = run.rawCount = 1;
        return run;
    }
    const double kScale = static_cast<double>(work.total()) / (1 << 16);
    if (o.threshold > 0 || o.segments <= 0) {
        st.threshold = o.threshold > 0 ? o.threshold : o.defaultThreshold * kScale;
        st.fhTrials = 1;
        return runFh(work, st.threshold, o, minSize, noiseSize);
    }
    const int target = o.segments;
    double lo = 20 * kScale, hi = 5000 * kScale;
    double bestScore = std::numeric_limits<double>::infinity();
    FhRun best;
    for (int t = 0; t < std::max(1, o.maxTrials); ++t) {
        const double k = std::sqrt(lo * hi);
        FhRun run = runFh(work, k, o, minSize, noiseSize);
        ++st.fhTrials;
        const int n = run.count;
        const double score = std::abs(std::log(static_cast<double>(n) / target));
        if (score < bestScore || (score == bestScore && k > st.threshold)) {
            bestScore = score;
            st.threshold = k;
            best = std::move(run);
        }
        if (std::abs(n - target) <= target / 10) break;
        (n > target ? lo : hi) = k;
    }
    return best;
}

// Nearest-neighbour upscaling of the working labels to the full image.
std::vector<int> upscaleLabels(const std::vector<int>& small, int ws, int hs, int W, int H) {
    std::vector<int> labels(static_cast<size_t>(W) * H);
    std::vector<int> sx(W);
    for (int x = 0; x < W; ++x)
        sx[x] = std::min(ws - 1, static_cast<int>((x + 0.5) * ws / W));
    for (int y = 0; y < H; ++y) {
        const int syy = std::min(hs - 1, static_cast<int>((y + 0.5) * hs / H));
        const int* row = &small[static_cast<size_t>(syy) * ws];
        for (int x = 0; x < W; ++x) labels[static_cast<size_t>(y) * W + x] = row[sx[x]];
    }
    return labels;
}

// ---------------------------------------------------------------------------------------
// (2) GrabCut refinement of each segment's boundary band.

struct Segment {
    long pixels = 0;
    int x0 = std::numeric_limits<int>::max(), y0 = std::numeric_limits<int>::max(), x1 = -1,
        y1 = -1;
    double sum[3] = {0, 0, 0};
    double mean[3] = {0, 0, 0};
};

std::vector<Segment> describeSegments(const cv::Mat& bgr, const std::vector<int>& labels,
                                      int count) {
    std::vector<Segment> segs(count);
    const int W = bgr.cols, H = bgr.rows;
    for (int y = 0; y < H; ++y) {
        const auto* row = bgr.ptr<cv::Vec3b>(y);
        for (int x = 0; x < W; ++x) {
            const int l = labels[static_cast<size_t>(y) * W + x];
            if (l < 0) continue;
            Segment& s = segs[l];
            ++s.pixels;
            s.x0 = std::min(s.x0, x);
            s.x1 = std::max(s.x1, x);
            s.y0 = std::min(s.y0, y);
            s.y1 = std::max(s.y1, y);
            for (int c = 0; c < 3; ++c) s.sum[c] += row[x][c];
        }
    }
    for (auto& s : segs)
        if (s.pixels > 0)
            for (int c = 0; c < 3; ++c) s.mean[c] = s.sum[c] / s.pixels;
    return segs;
}

// One segment's GrabCut result over its region of interest.
struct SegmentCut {
    cv::Rect roi;
    cv::Mat before, mask;  // empty: the segment is left as it is
};

struct GrabCutParams {
    int band = 0;        // half-width of the uncertain band along the segment's border
    int iterations = 0;  // GrabCut iterations
    long minPixels = 0;  // smaller segments are left as they are
    int margin = 0;      // colour context beyond the band
};

// Segment s's trimap over roi: pixels farther than `band` from its border are sure foreground
// (inside) or background (outside), the others probable; `fg` and `bg` count each side.
cv::Mat segmentTrimap(const std::vector<int>& labels, int W, int s, const cv::Rect& roi, int band,
                      long& fg, long& bg) {
    cv::Mat inside(roi.size(), CV_8U);
    for (int y = 0; y < roi.height; ++y) {
        auto* row = inside.ptr<uint8_t>(y);
        const int* lab = &labels[static_cast<size_t>(y + roi.y) * W + roi.x];
        for (int x = 0; x < roi.width; ++x) row[x] = lab[x] == s ? 255 : 0;
    }
    cv::Mat distIn, distOut, outside;
    cv::bitwise_not(inside, outside);
    cv::distanceTransform(inside, distIn, cv::DIST_L2, cv::DIST_MASK_3);
    cv::distanceTransform(outside, distOut, cv::DIST_L2, cv::DIST_MASK_3);
    cv::Mat mask(roi.size(), CV_8U);
    fg = bg = 0;
    for (int y = 0; y < roi.height; ++y) {
        const auto* in = inside.ptr<uint8_t>(y);
        const auto* di = distIn.ptr<float>(y);
        const auto* dout = distOut.ptr<float>(y);
        auto* m = mask.ptr<uint8_t>(y);
        for (int x = 0; x < roi.width; ++x) {
            if (in[x]) {
                m[x] = di[x] > band ? cv::GC_FGD : cv::GC_PR_FGD;
                ++fg;
            } else {
                m[x] = dout[x] > band ? cv::GC_BGD : cv::GC_PR_BGD;
                ++bg;
            }
        }
    }
    return mask;
}

// GrabCut seeds its colour models with k-means on OpenCV's (thread-local) random generator: a
// fixed seed per segment makes the result reproducible; the thread's generator state is
// restored. False when GrabCut refuses (e.g. a degenerate colour model).
bool seededGrabCut(const cv::Mat& bgr, const cv::Rect& roi, cv::Mat& mask, int iterations, int s) {
    cv::Mat bgdModel, fgdModel;
    const uint64_t savedRng = cv::theRNG().state;
    cv::theRNG().state = 0x9e3779b97f4a7c15ULL ^ static_cast<uint64_t>(s + 1);
    bool ok = true;
    try {
        cv::grabCut(bgr(roi), mask, cv::Rect(), bgdModel, fgdModel, iterations,
                    cv::GC_INIT_WITH_MASK);
    } catch (const cv::Exception&) {
        ok = false;
    }
    cv::theRNG().state = savedRng;
    return ok;
}

// GrabCut on segment s's band, over its bounding box widened by the margin. It reads the
// labels and the image only, so segments can run in parallel.
SegmentCut cutSegment(const cv::Mat& bgr, const std::vector<int>& labels, const Segment& seg, int s,
                      const GrabCutParams& params) {
    SegmentCut cut;
    const int W = bgr.cols, H = bgr.rows;
    if (seg.pixels < std::max(params.minPixels, 16L) ||
        seg.pixels == static_cast<long>(labels.size()))
        return cut;
    const int margin = params.margin;
    const int rx0 = std::max(0, seg.x0 - margin), ry0 = std::max(0, seg.y0 - margin);
    const int rx1 = std::min(W - 1, seg.x1 + margin), ry1 = std::min(H - 1, seg.y1 + margin);
    const cv::Rect roi(rx0, ry0, rx1 - rx0 + 1, ry1 - ry0 + 1);
    long fg = 0, bg = 0;
    cv::Mat mask = segmentTrimap(labels, W, s, roi, params.band, fg, bg);
    if (fg < 16 || bg < 16) return cut;  // GrabCut's colour models need samples
    cv::Mat before = mask.clone();
    if (!seededGrabCut(bgr, roi, mask, params.iterations, s)) return cut;
    cut.roi = roi;
    cut.before = std::move(before);
    cut.mask = std::move(mask);
    return cut;
}

// What the segments' GrabCuts say about the pixels of their bands: a pixel leaves its segment
// when its owner's GrabCut calls it background, for the segment of the nearest mean colour
// whose GrabCut claims it (-1 when none does).
struct BandVotes {
    std::vector<uint8_t> ownerSaysBg;
    std::vector<int> claim;
    std::vector<float> claimDist;

    explicit BandVotes(size_t n)
        : ownerSaysBg(n, 0), claim(n, -1), claimDist(n, std::numeric_limits<float>::infinity()) {}

    void add(const cv::Mat& bgr, int s, const Segment& seg, const SegmentCut& cut,
             SegmentStats& st) {
        if (cut.mask.empty()) return;
        const int W = bgr.cols;
        const cv::Rect& roi = cut.roi;
        ++st.grabCutSegments;
        st.grabCutPixels += static_cast<long>(roi.area());
        for (int y = 0; y < roi.height; ++y) {
            const auto* b = cut.before.ptr<uint8_t>(y);
            const auto* m = cut.mask.ptr<uint8_t>(y);
            const auto* colour = bgr.ptr<cv::Vec3b>(y + roi.y) + roi.x;
            for (int x = 0; x < roi.width; ++x) {
                if (b[x] != cv::GC_PR_FGD && b[x] != cv::GC_PR_BGD) continue;
                const size_t p = static_cast<size_t>(y + roi.y) * W + (x + roi.x);
                const bool isFg = (m[x] & 1) != 0;
                if (b[x] == cv::GC_PR_FGD) {
                    if (!isFg) ownerSaysBg[p] = 1;
                } else if (isFg) {
                    const float d = colourDist2(colour[x], seg.mean);
                    if (d < claimDist[p]) {
                        claimDist[p] = d;
                        claim[p] = s;
                    }
                }
            }
        }
    }

    long apply(std::vector<int>& labels) const {
        long changed = 0;
        for (size_t p = 0; p < labels.size(); ++p)
            if (ownerSaysBg[p] && claim[p] != labels[p]) {
                labels[p] = claim[p];
                ++changed;
            }
        return changed;
    }
};

// Returns the pixels whose label changed; pixels no segment claims become -1.
long refineWithGrabCut(const cv::Mat& bgr, std::vector<int>& labels, int count, int band,
                       int iterations, long minPixels, int threads, SegmentStats& st) {
    const auto segs = describeSegments(bgr, labels, count);
    GrabCutParams params;
    params.band = band;
    params.iterations = iterations;
    params.minPixels = minPixels;
    params.margin = band + std::max(8, 2 * band);
    BandVotes votes(labels.size());
    // Segments run in parallel, a batch at a time, and are merged in segment order, so that
    // the result does not depend on the thread count.
    const int workers = std::max(1, std::min(threadsToUse(threads), count));
    const int batch = 4 * workers;
    for (int first = 0; first < count; first += batch) {
        const int n = std::min(batch, count - first);
        std::vector<SegmentCut> cuts(static_cast<size_t>(n));
        parallelFor(n, workers, [&](int k, int) {
            cuts[static_cast<size_t>(k)] =
                cutSegment(bgr, labels, segs[first + k], first + k, params);
        });
        for (int k = 0; k < n; ++k)
            votes.add(bgr, first + k, segs[first + k], cuts[static_cast<size_t>(k)], st);
    }
    return votes.apply(labels);
}

// ---------------------------------------------------------------------------------------
// (3) Seeded region growing into the unlabelled pixels (-1), nearest colour first.

long growIntoGaps(const cv::Mat& bgr, std::vector<int>& labels, int count) {
    const int W = bgr.cols, H = bgr.rows;
    const size_t N = labels.size();
    long unassigned = std::count(labels.begin(), labels.end(), -1);
    if (unassigned == 0) return 0;
    if (unassigned == static_cast<long>(N)) {
        std::fill(labels.begin(), labels.end(), 0);
        return unassigned;
    }
    const cv::Vec3b* colour = bgr.ptr<cv::Vec3b>(0);  // continuous: made by toBgr8
    std::vector<double> sum(static_cast<size_t>(count) * 3, 0.0), mean(sum.size(), 0.0);
    std::vector<long> n(count, 0);
    for (size_t p = 0; p < N; ++p)
        if (labels[p] >= 0) {
            const int l = labels[p];
            ++n[l];
            for (int c = 0; c < 3; ++c) sum[l * 3 + c] += colour[p][c];
        }
    auto updateMean = [&](int l) {
        for (int c = 0; c < 3; ++c) mean[l * 3 + c] = sum[l * 3 + c] / std::max(1L, n[l]);
    };
    for (int l = 0; l < count; ++l) updateMean(l);

    struct Entry {
        float d;
        int p, label;
        bool operator>(const Entry& o) const {
            return d != o.d ? d > o.d : (p != o.p ? p > o.p : label > o.label);
        }
    };
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    auto pushNeighbours = [&](int p, int l) {
        const int x = p % W, y = p / W;
        const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (const auto& q : nb) {
            if (q[0] < 0 || q[0] >= W || q[1] < 0 || q[1] >= H) continue;
            const int qi = q[1] * W + q[0];
            if (labels[qi] == -1) queue.push({colourDist2(colour[qi], &mean[l * 3]), qi, l});
        }
    };
    for (size_t p = 0; p < N; ++p)
        if (labels[p] >= 0) pushNeighbours(static_cast<int>(p), labels[p]);
    long grown = 0;
    while (!queue.empty()) {
        const Entry e = queue.top();
        queue.pop();
        if (labels[e.p] != -1) continue;
        labels[e.p] = e.label;
        ++grown;
        ++n[e.label];
        for (int c = 0; c < 3; ++c) sum[e.label * 3 + c] += colour[e.p][c];
        updateMean(e.label);
        pushNeighbours(e.p, e.label);
    }
    return grown;
}

// ---------------------------------------------------------------------------------------
// (4) 4-connected components; the small and the thin ones merged into their most similar
// neighbour; dense relabelling by size. Also cleans FH's result at the working resolution.

struct Components {
    std::vector<int> of;  // pixel → component
    int count = 0;
};

Components components4(const std::vector<int>& labels, int W, int H) {
    Components cc;
    const size_t N = labels.size();
    cc.of.assign(N, -1);
    std::vector<int> stack;
    for (size_t start = 0; start < N; ++start) {
        if (cc.of[start] >= 0) continue;
        const int id = cc.count++;
        const int l = labels[start];
        cc.of[start] = id;
        stack.push_back(static_cast<int>(start));
        while (!stack.empty()) {
            const int p = stack.back();
            stack.pop_back();
            const int x = p % W, y = p / W;
            auto visit = [&](int q) {
                if (cc.of[q] < 0 && labels[q] == l) {
                    cc.of[q] = id;
                    stack.push_back(q);
                }
            };
            if (x > 0) visit(p - 1);
            if (x + 1 < W) visit(p + 1);
            if (y > 0) visit(p - W);
            if (y + 1 < H) visit(p + W);
        }
    }
    return cc;
}

// The 4-connected components of a label map as a graph: each component's size and colour sum,
// its shared borders with its neighbours, and a union-find over merges.
class RegionGraph {
public:
    RegionGraph(const cv::Mat& bgr, const std::vector<int>& labels)
        : W_(bgr.cols), H_(bgr.rows), cc_(components4(labels, W_, H_)), C_(cc_.count),
          colour_(bgr.ptr<cv::Vec3b>(0)), size_(C_, 0), sum_(static_cast<size_t>(C_) * 3, 0.0),
          adj_(C_), thin_(C_, 0), parent_(C_) {
        for (size_t p = 0; p < labels.size(); ++p) {
            const int c = cc_.of[p];
            ++size_[c];
            for (int k = 0; k < 3; ++k) sum_[c * 3 + k] += colour_[p][k];
        }
        for (int c = 0; c < C_; ++c) parent_[c] = c;
        linkBorders();
    }

    int components() const { return C_; }

    // Marks the components mostly of `ink` pixels, and which are never merged
    // (MergeParams::ink).
    void markInk(const std::vector<int>& labels, const std::vector<uint8_t>& ink,
                 long minInkPiece, long minKeptPiece) {
        std::vector<long> inkPixels(static_cast<size_t>(C_), 0);
        std::vector<int> labelOf(static_cast<size_t>(C_), 0);
        for (size_t p = 0; p < ink.size(); ++p) {
            inkPixels[static_cast<size_t>(cc_.of[p])] += ink[p];
            labelOf[static_cast<size_t>(cc_.of[p])] = labels[p];
        }
        std::unordered_map<int, int> largest;  // label -> its largest component
        for (int c = 0; c < C_; ++c) {
            ink_.push_back(2 * inkPixels[static_cast<size_t>(c)] > size_[c]);
            auto [it, added] = largest.insert({labelOf[static_cast<size_t>(c)], c});
            if (!added && size_[c] > size_[it->second]) it->second = c;
        }
        fixed_.assign(static_cast<size_t>(C_), 0);
        for (int c = 0; c < C_; ++c) {
            // An ink line, or a piece wholly enclosed by ink (a lens where two outlines cross).
            const bool enclosed = std::all_of(adj_[c].begin(), adj_[c].end(), [&](const auto& nb) {
                return ink_[static_cast<size_t>(nb.first)] != 0;
            });
            fixed_[static_cast<size_t>(c)] =
                (ink_[static_cast<size_t>(c)] || enclosed) && size_[c] >= minInkPiece;
        }
        for (const auto& [label, c] : largest)
            if (!ink_[static_cast<size_t>(c)] && size_[c] >= minKeptPiece)
                fixed_[static_cast<size_t>(c)] = 1;
    }

    // Per component: whether its label is at least `first` or it has at least minSize pixels.
    std::vector<uint8_t> keepableComponents(const std::vector<int>& labels, int first,
                                            long minSize) const {
        std::vector<uint8_t> out(static_cast<size_t>(C_), 0);
        for (size_t p = 0; p < labels.size(); ++p)
            if (labels[p] >= first) out[static_cast<size_t>(cc_.of[p])] = 1;
        for (int c = 0; c < C_; ++c)
            if (size_[c] >= minSize) out[static_cast<size_t>(c)] = 1;
        return out;
    }

    // Marks components no wider than sliverWidth (each pixel within (sliverWidth-1)/2 steps of
    // another region).
    void markThin(int sliverWidth) {
        if (sliverWidth <= 0 || C_ <= 1) return;
        cv::Mat dist;  // steps (4-neighbour) to the nearest pixel on a region boundary
        cv::distanceTransform(interior_, dist, cv::DIST_L1, 3);
        std::vector<float> maxDist(C_, 0);
        for (int y = 0; y < H_; ++y) {
            const float* d = dist.ptr<float>(y);
            for (int x = 0; x < W_; ++x) {
                const int c = cc_.of[static_cast<size_t>(y) * W_ + x];
                maxDist[c] = std::max(maxDist[c], d[x]);
            }
        }
        const float limit = static_cast<float>((sliverWidth - 1) / 2) + 0.25f;
        for (int c = 0; c < C_; ++c) thin_[c] = maxDist[c] <= limit;
    }

    // Merges every component under minRegion pixels, or thin, into the adjacent one of the most
    // similar mean colour (ties: the longest shared border), smallest first. Returns the merges.
    // A thin component whose mean colour lies further than thinContrast from every
    // neighbour's and not between two of them (a line or a ring drawn on its surroundings, not
    // a sliver along a blurred edge) is not merged for being thin.
    long mergeSmallAndThin(long minRegion, const std::vector<uint8_t>& mayKeep,
                           double keepContrast, double thinContrast) {
        auto distinct = [&](int c) {
            return keepContrast > 0 && mayKeep[static_cast<size_t>(c)] &&
                   colourDistance(c, mostSimilarNeighbour(c)) > keepContrast;
        };
        auto keptThin = [&](int c) {
            return thinContrast > 0 && !adj_[c].empty() &&
                   colourDistance(c, mostSimilarNeighbour(c)) > thinContrast &&
                   !betweenNeighbours(c);
        };
        auto needsMerge = [&](int c) {
            if (!fixed_.empty() && fixed_[static_cast<size_t>(c)]) return false;
            return (thin_[c] && !keptThin(c)) || (size_[c] < minRegion && !distinct(c));
        };
        using Item = std::pair<long, int>;  // size, component: the smallest first
        std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
        for (int c = 0; c < C_; ++c)
            if (needsMerge(c)) queue.push({size_[c], c});
        long merged = 0;
        while (!queue.empty()) {
            const auto [sz, c] = queue.top();
            queue.pop();
            if (parent_[c] != c || size_[c] != sz || !needsMerge(c) || adj_[c].empty()) continue;
            const int r = unite(c, mostSimilarNeighbour(c));
            ++merged;
            if (needsMerge(r)) queue.push({size_[r], r});
        }
        return merged;
    }

    // Merges adjacent regions whose shared border is weak (mean colour step across it under
    // weakEdge), weakest first. Returns the merges.
    long mergeWeakBorders(double weakEdge) {
        if (weakEdge <= 0) return 0;
        struct Pair {
            double step;
            int a, b;
            long length;
            bool operator>(const Pair& o) const {
                return step != o.step ? step > o.step : (a != o.a ? a > o.a : b > o.b);
            }
        };
        std::priority_queue<Pair, std::vector<Pair>, std::greater<Pair>> pairs;
        auto pushPairs = [&](int a, bool all) {
            for (const auto& [n, border] : adj_[a])
                if (all || a < n)
                    pairs.push({border.step / border.length, std::min(a, n), std::max(a, n),
                                border.length});
        };
        for (int c = 0; c < C_; ++c)
            if (parent_[c] == c) pushPairs(c, false);
        long merged = 0;
        while (!pairs.empty() && pairs.top().step < weakEdge) {
            const Pair e = pairs.top();
            pairs.pop();
            if (parent_[e.a] != e.a || parent_[e.b] != e.b) continue;
            const auto it = adj_[e.a].find(e.b);
            if (it == adj_[e.a].end() || it->second.length != e.length) continue;  // stale
            pushPairs(unite(e.a, e.b), true);
            ++merged;
        }
        return merged;
    }

    // Writes dense labels, largest region first (ties: the one met first in scan order);
    // returns their count.
    int relabel(std::vector<int>& labels) {
        std::vector<int> roots, firstComp(C_, std::numeric_limits<int>::max());
        for (int c = 0; c < C_; ++c) {
            const int r = find(c);
            if (r == c) roots.push_back(c);
            firstComp[r] = std::min(firstComp[r], c);
        }
        std::sort(roots.begin(), roots.end(), [&](int a, int b) {
            return size_[a] != size_[b] ? size_[a] > size_[b] : firstComp[a] < firstComp[b];
        });
        std::vector<int> dense(C_, -1);
        for (size_t i = 0; i < roots.size(); ++i) dense[roots[i]] = static_cast<int>(i);
        for (size_t p = 0; p < labels.size(); ++p) labels[p] = dense[find(cc_.of[p])];
        return static_cast<int>(roots.size());
    }

private:
    // A shared border: pixel pairs, and the sum of the colour steps across them.
    struct Border {
        long length = 0;
        double step = 0;
    };

    // The colour step between pixels p and q (RGB distance).
    double colorStep(size_t p, size_t q) const {
        double d = 0;
        for (int k = 0; k < 3; ++k) {
            const double e = static_cast<double>(colour_[p][k]) - colour_[q][k];
            d += e * e;
        }
        return std::sqrt(d);
    }

    void link(int a, int b, double step) {
        Border& ab = adj_[a][b];
        ++ab.length;
        ab.step += step;
        Border& ba = adj_[b][a];
        ++ba.length;
        ba.step += step;
    }

    // The shared borders, each step measured between the pixels one further out on either
    // side (blurred edges are 2–3 pixels wide), and interior_ (0 on pixels with a foreign
    // 4-neighbour).
    void linkBorders() {
        interior_ = cv::Mat(H_, W_, CV_8U, cv::Scalar(255));
        for (int y = 0; y < H_; ++y) {
            auto* in = interior_.ptr<uint8_t>(y);
            for (int x = 0; x < W_; ++x) {
                const size_t p = static_cast<size_t>(y) * W_ + x;
                if (x + 1 < W_ && cc_.of[p] != cc_.of[p + 1]) {
                    link(cc_.of[p], cc_.of[p + 1],
                         colorStep(p - (x > 0 ? 1 : 0), p + 1 + (x + 2 < W_ ? 1 : 0)));
                    in[x] = in[x + 1] = 0;
                }
                if (y + 1 < H_ && cc_.of[p] != cc_.of[p + W_]) {
                    link(cc_.of[p], cc_.of[p + W_],
                         colorStep(p - (y > 0 ? W_ : 0), p + W_ + (y + 2 < H_ ? W_ : 0)));
                    in[x] = 0;
                    interior_.ptr<uint8_t>(y + 1)[x] = 0;
                }
            }
        }
    }

    int find(int c) {
        while (parent_[c] != c) c = parent_[c] = parent_[parent_[c]];
        return c;
    }

    // The neighbour of c with the closest mean colour (ties: the longest shared border, then
    // the lowest index).
    // The RGB distance between the mean colours of components a and b.
    double colourDistance(int a, int b) const {
        double d = 0;
        for (int k = 0; k < 3; ++k) {
            const double e = sum_[b * 3 + k] / size_[b] - sum_[a * 3 + k] / size_[a];
            d += e * e;
        }
        return std::sqrt(d);
    }

    // Whether c's mean colour lies near the colour segment between two of its neighbours' (an
    // edge's blend of the two): off it by less than a third of the segment's length.
    bool betweenNeighbours(int c) const {
        std::vector<std::array<double, 3>> means;
        for (const auto& entry : adj_[c]) means.push_back(meanColour(entry.first));
        const std::array<double, 3> m = meanColour(c);
        for (size_t i = 0; i < means.size(); ++i)
            for (size_t j = i + 1; j < means.size(); ++j) {
                const std::array<double, 3>& a = means[i];
                double d[3], dd = 0, t = 0;
                for (int k = 0; k < 3; ++k) {
                    d[k] = means[j][k] - a[k];
                    dd += d[k] * d[k];
                    t += (m[k] - a[k]) * d[k];
                }
                if (dd <= 0 || t < 0 || t > dd) continue;
                t /= dd;
                double off = 0;
                for (int k = 0; k < 3; ++k) {
                    const double e = m[k] - a[k] - t * d[k];
                    off += e * e;
                }
                if (9 * off < dd) return true;
            }
        return false;
    }

    std::array<double, 3> meanColour(int c) const {
        return {sum_[c * 3] / size_[c], sum_[c * 3 + 1] / size_[c], sum_[c * 3 + 2] / size_[c]};
    }

    int mostSimilarNeighbour(int c) const {
        double m[3];
        for (int k = 0; k < 3; ++k) m[k] = sum_[c * 3 + k] / size_[c];
        int best = -1;
        double bestD = 0;
        long bestLen = 0;
        const bool onlyInk = std::all_of(adj_[c].begin(), adj_[c].end(),
                                         [&](const auto& nb) { return isInk(nb.first); });
        for (const auto& [n, border] : adj_[c]) {
            if (isInk(n) && !onlyInk) continue;
            double d = 0;
            for (int k = 0; k < 3; ++k) {
                const double e = sum_[n * 3 + k] / size_[n] - m[k];
                d += e * e;
            }
            if (best < 0 || d < bestD ||
                (d == bestD && (border.length > bestLen ||
                                (border.length == bestLen && n < best)))) {
                best = n;
                bestD = d;
                bestLen = border.length;
            }
        }
        return best;
    }

    bool isInk(int c) const { return !ink_.empty() && ink_[static_cast<size_t>(c)]; }

    // Merges a and b (both roots, adjacent); the one with the larger adjacency map survives.
    int unite(int a, int b) {
        if (adj_[a].size() > adj_[b].size()) std::swap(a, b);  // a goes into b
        for (const auto& [n, border] : adj_[a]) {
            if (n == b) continue;
            auto& an = adj_[n];
            an.erase(a);
            Border& nb = an[b];
            nb.length += border.length;
            nb.step += border.step;
            Border& bn = adj_[b][n];
            bn.length += border.length;
            bn.step += border.step;
        }
        adj_[b].erase(a);
        std::unordered_map<int, Border>().swap(adj_[a]);
        parent_[a] = b;
        size_[b] += size_[a];
        for (int k = 0; k < 3; ++k) sum_[b * 3 + k] += sum_[a * 3 + k];
        thin_[b] = thin_[a] && thin_[b];
        if (!fixed_.empty()) {
            fixed_[static_cast<size_t>(b)] |= fixed_[static_cast<size_t>(a)];
            ink_[static_cast<size_t>(b)] |= ink_[static_cast<size_t>(a)];
        }
        return b;
    }

    const int W_, H_;
    const Components cc_;
    const int C_;
    const cv::Vec3b* colour_;  // the image, continuous
    std::vector<long> size_;
    std::vector<double> sum_;  // per component: the sum of its colours
    std::vector<std::unordered_map<int, Border>> adj_;
    cv::Mat interior_;
    std::vector<uint8_t> thin_;
    std::vector<int> parent_;
    std::vector<uint8_t> ink_, fixed_;  // per component (markInk); empty when not marked
};

// Splits labels into 4-connected components and merges every component under minRegion pixels
// or no wider than sliverWidth pixels into its most similar neighbour; then merges adjacent
// regions across weak borders, weakest first. The union of two 4-adjacent 4-connected sets is
// 4-connected, so every label ends as one 4-connected component. Relabels 0..count-1 by size,
// largest first.
MergeResult mergeRegions(const cv::Mat& bgr, std::vector<int>& labels, const MergeParams& mp) {
    RegionGraph graph(bgr, labels);
    MergeResult res;
    res.components = graph.components();
    graph.markThin(mp.sliverWidth);
    if (mp.ink) graph.markInk(labels, *mp.ink, mp.minInkPiece, mp.minKeptPiece);
    res.merged = graph.mergeSmallAndThin(mp.minRegion,
                                         graph.keepableComponents(labels, mp.firstKept, mp.keptMinSize),
                                         mp.keepContrast, mp.thinContrast);
    res.weakMerged = graph.mergeWeakBorders(mp.weakEdge);
    res.count = graph.relabel(labels);
    return res;
}

// The labels of `small` (a downscaled copy of `bgr`, or `bgr` itself) for every pixel of bgr.
std::vector<int> upscaleToImage(const cv::Mat& small, const std::vector<int>& labels,
                                const cv::Mat& bgr, const SegmentOptions& options,
                                SegmentStats& st) {
    if (small.cols == bgr.cols && small.rows == bgr.rows) return labels;
    if (!options.refineBorders)
        return upscaleLabels(labels, small.cols, small.rows, bgr.cols, bgr.rows);
    return upscaleLabelsRefined(small, labels, bgr, options.threads, &st.borderRefined);
}

// Per label: whether most of its pixels are ink (liftInk).
std::vector<uint8_t> inkLabels(const std::vector<int>& labels, int count,
                               const std::vector<uint8_t>& ink) {
    std::vector<long> inkPixels(static_cast<size_t>(count), 0), pixels(inkPixels);
    for (size_t p = 0; p < labels.size(); ++p) {
        ++pixels[static_cast<size_t>(labels[p])];
        inkPixels[static_cast<size_t>(labels[p])] += ink[p];
    }
    std::vector<uint8_t> isInk(static_cast<size_t>(count), 0);
    for (size_t l = 0; l < isInk.size(); ++l) isInk[l] = 2 * inkPixels[l] > pixels[l];
    return isInk;
}

int labelCount(const std::vector<int>& labels) {
    return labels.empty() ? 0 : *std::max_element(labels.begin(), labels.end()) + 1;
}

// (5) Ink lines found at full size take their pixels from the merged labels
// (segment_ink.h); the pieces of labels they cut off are merged like small regions. Returns the
// ink pixels.
std::vector<uint8_t> liftInk(const cv::Mat& bgr, std::vector<int>& labels, int count,
                             long minPixels, const MergeParams& merge,
                             const SegmentOptions& options) {
    std::vector<uint8_t> ink(labels.size(), 0);
    InkLineOptions inkOptions;
    inkOptions.minPixels = minPixels;
    if (options.minRegion > 0) inkOptions.minPiece = options.minRegion;
    inkOptions.contrast = options.distinctContrast;
    inkOptions.threads = options.threads;
    if (!options.inkLines || liftInkLines(bgr, labels, count, ink, inkOptions) == count)
        return ink;
    MergeParams pieces = merge;
    pieces.weakEdge = 0;
    pieces.firstKept = std::numeric_limits<int>::max();
    pieces.ink = &ink;
    pieces.minInkPiece = inkOptions.minPiece;
    pieces.minKeptPiece = minPixels;
    mergeRegions(bgr, labels, pieces);
    return ink;
}

// Renumbers the labels 0..count-1 by size, largest first (ties: the one met first in scan
// order), the labels marked `last` after all others; returns the count.
int relabelBySize(std::vector<int>& labels, int count, const std::vector<uint8_t>& last) {
    std::vector<long> size(static_cast<size_t>(count), 0);
    std::vector<size_t> first(static_cast<size_t>(count), labels.size());
    for (size_t p = 0; p < labels.size(); ++p) {
        const size_t l = static_cast<size_t>(labels[p]);
        ++size[l];
        first[l] = std::min(first[l], p);
    }
    std::vector<int> order(static_cast<size_t>(count));
    for (int l = 0; l < count; ++l) order[static_cast<size_t>(l)] = l;
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        if (!last.empty() && last[a] != last[b]) return last[a] < last[b];
        return size[a] != size[b] ? size[a] > size[b] : first[a] < first[b];
    });
    std::vector<int> dense(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) dense[static_cast<size_t>(order[i])] = i;
    for (int& l : labels) l = dense[static_cast<size_t>(l)];
    return count;
}

// `bgr` scaled down (area averaging) to at most maxPixels pixels; itself when it is no larger
// or maxPixels is 0.
cv::Mat downscaled(const cv::Mat& bgr, long maxPixels) {
    const int W = bgr.cols, H = bgr.rows;
    const long N = static_cast<long>(W) * H;
    if (maxPixels <= 0 || N <= maxPixels) return bgr;
    const double f = std::sqrt(static_cast<double>(maxPixels) / N);
    const int ws = std::max(1, static_cast<int>(std::floor(W * f)));
    const int hs = std::max(1, static_cast<int>(std::floor(H * f)));
    cv::Mat small;
    cv::resize(bgr, small, cv::Size(ws, hs), 0, 0, cv::INTER_AREA);
    return small;
}

// (1) FH on the working image (`work`), its minimum size from minRegion scaled to it, and the
// distinct pieces under that size lifted out (noiseSize: minRegion scaled).
FhRun graphStage(const cv::Mat& work, long N, long minRegion, const SegmentOptions& options,
                 SegmentStats& st) {
    st.workWidth = work.cols;
    st.workHeight = work.rows;
    const double workShare = static_cast<double>(work.total()) / N;
    const int wanted = options.segments > 0 ? options.segments : 12;
    const int fhMinSize =
        options.fhMinSize > 0
            ? options.fhMinSize
            : static_cast<int>(std::max<double>({1.0, std::round(minRegion * workShare),
                                                 std::floor(work.total() / (8.0 * wanted))}));
    const int noiseSize =
        static_cast<int>(std::max<double>(1.0, std::round(minRegion * workShare)));
    const FhRun fh = graphSegment(work, options, fhMinSize, std::min(noiseSize, fhMinSize), st);
    st.fhRegions = fh.rawCount;
    st.fhCleanRegions = fh.count;
    return fh;
}

// (2) GrabCut on each segment's boundary band, at full resolution up to grabCutPixels; the
// labels at full size.
std::vector<int> grabCutStage(const cv::Mat& bgr, const cv::Mat& work, const FhRun& fh,
                              long minRegion, const SegmentOptions& options, SegmentStats& st) {
    const int W = bgr.cols, H = bgr.rows;
    const long N = static_cast<long>(W) * H;
    if (!(options.grabCut && fh.count > 1 && W >= 8 && H >= 8))
        return upscaleToImage(work, fh.labels, bgr, options, st);
    const cv::Mat gc = downscaled(bgr, options.grabCutPixels);
    st.grabCutWidth = gc.cols;
    st.grabCutHeight = gc.rows;
    std::vector<int> labels = upscaleLabels(fh.labels, work.cols, work.rows, gc.cols, gc.rows);
    const double scale = static_cast<double>(gc.cols) / work.cols;
    const int band =
        options.band > 0 ? options.band : std::max(3, static_cast<int>(std::ceil(scale)) + 2);
    const double gcShare = static_cast<double>(gc.total()) / N;
    const long minPixels = std::lround(
        (options.grabCutMinPixels > 0 ? options.grabCutMinPixels : minRegion) * gcShare);
    st.grabCutChanged =
        refineWithGrabCut(gc, labels, fh.count, band, std::max(1, options.grabCutIterations),
                          minPixels, options.threads, st);
    return upscaleToImage(gc, labels, bgr, options, st);
}

}  // namespace

// Under the default minimum region size, thin structures of at least this many pixels are kept
// (when distinct), however large the image: a line's pixels grow with its length, not with the
// image's area. A minRegion given is honoured.
constexpr long kMinThinStructure = 64;

namespace {

// segmentImage's stages, OpenCV's allocation failures left as they are.
Segmentation segmentStages(const RgbaImage& image, const SegmentOptions& options) {
    const auto t0 = Clock::now();
    const int W = image.width, H = image.height;
    if (W <= 0 || H <= 0 || image.pixels.size() < static_cast<size_t>(W) * H * 4)
        throw Error("cannot segment an empty image");
    Segmentation seg;
    seg.width = W;
    seg.height = H;
    SegmentStats& st = seg.stats;
    const long N = static_cast<long>(W) * H;
    const long minRegion =
        options.minRegion > 0 ? options.minRegion : std::max(64L, N / 1000);
    const long smallestThin =
        options.minRegion > 0 ? minRegion : std::min(minRegion, kMinThinStructure);
    const cv::Mat bgr = toBgr8(image);

    auto t = Clock::now();
    const cv::Mat work = downscaled(bgr, options.workPixels);
    const FhRun fh = graphStage(work, N, minRegion, options, st);
    st.fhSeconds = secondsSince(t);

    t = Clock::now();
    seg.labels = grabCutStage(bgr, work, fh, minRegion, options, st);
    st.grabCutSeconds = secondsSince(t);

    // (3) Region growing into what GrabCut left unclaimed.
    t = Clock::now();
    st.grown = growIntoGaps(bgr, seg.labels, fh.count);
    st.growSeconds = secondsSince(t);

    // Thin structures found on the full-size image take the place of what the graph stage made
    // of them.
    ThinStructureOptions thin;
    thin.minPixels = smallestThin;
    thin.contrast = options.distinctContrast;
    thin.threads = options.threads;
    const int withThin = liftThinStructures(bgr, seg.labels, fh.count, thin);
    st.thinStructures = withThin - fh.count;
    st.thinGrown = growThinStructures(bgr, seg.labels, fh.count, withThin, thin.contrast);

    // (4) One 4-connected component per label, none under minRegion.
    t = Clock::now();
    MergeParams merge{minRegion, options.sliverWidth, options.weakEdge};
    merge.thinContrast = options.distinctContrast;
    if (smallestThin < minRegion) {
        merge.firstKept = fh.count;  // the thin structures, kept under minRegion when distinct
        merge.keepContrast = options.distinctContrast;
    }
    const MergeResult merged = mergeRegions(bgr, seg.labels, merge);
    st.components = merged.components;
    st.merged = merged.merged;
    st.weakMerged = merged.weakMerged;
    st.mergeSeconds = secondsSince(t);

    // (5) Ink lines, drawn over the regions they divide.
    t = Clock::now();
    const std::vector<uint8_t> ink =
        liftInk(bgr, seg.labels, merged.count, smallestThin, merge, options);
    st.inkSeconds = secondsSince(t);

    // Rings no wider than about 7 px are cut into two arcs (segment_thin.h).
    const int count = cutThinLoops(seg.labels, W, H, labelCount(seg.labels), 3, smallestThin);
    const std::vector<uint8_t> inkLabel = inkLabels(seg.labels, count, ink);
    seg.count = st.regions = relabelBySize(seg.labels, count, inkLabel);
    st.inkLines = seg.inkLabels =
        static_cast<int>(std::count(inkLabel.begin(), inkLabel.end(), 1));
    st.seconds = secondsSince(t0);
    return seg;
}

}  // namespace

Segmentation segmentImage(const RgbaImage& image, const SegmentOptions& options) {
    return withOpenCvOutOfMemoryAsBadAlloc([&] { return segmentStages(image, options); });
}

}  // namespace gm
