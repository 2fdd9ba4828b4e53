// Foreground extraction by GrabCut (foreground.h), bounded on large images: GrabCut's cost and
// memory grow with the pixels it sees (a graph node and a GMM assignment per pixel, hundreds of
// bytes and several µs each, times its iterations), so a large image is cut on an
// area-downscaled copy of at most kGrabCutWorkPixels; the outline is then brought back to full
// resolution by one graph cut with that cut's colour models, in windows along a band around
// the upscaled outline only (everything off the band is certain).
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "converters/foreground.h"
#include "meshcore/error.h"
#include "meshcore/parallel_for.h"
#include "opencv_memory.h"

namespace gm {

namespace {

// Side of the square tiles the band is refined in (each cut with a margin of context).
constexpr int kWindow = 96;

cv::Mat toBgr8(const RgbaImage& image) {
    cv::Mat bgr(image.height, image.width, CV_8UC3);
    for (int y = 0; y < image.height; ++y) {
        auto* row = bgr.ptr<cv::Vec3b>(y);
        for (int x = 0; x < image.width; ++x) {
            const float* p = image.at(x, y);
            for (int c = 0; c < 3; ++c)
                row[x][2 - c] = static_cast<uint8_t>(std::lround(std::clamp(p[c], 0.f, 1.f) * 255));
        }
    }
    return bgr;
}

bool isForeground(uint8_t label) { return label == cv::GC_FGD || label == cv::GC_PR_FGD; }

// GrabCut's labels of an image and its colour models (OpenCV's GMMs of the background and
// the foreground).
struct GrabCutResult {
    cv::Mat labels, bgModel, fgModel;
};

// GrabCut on the whole of `bgr`, initialised with a rectangle ~5% inside its border.
GrabCutResult grabCutInRect(const cv::Mat& bgr, int iterations) {
    const int W = bgr.cols, H = bgr.rows;
    const int mx = std::max(1, W / 20), my = std::max(1, H / 20);
    GrabCutResult r;
    cv::grabCut(bgr, r.labels, cv::Rect(mx, my, W - 2 * mx, H - 2 * my), r.bgModel, r.fgModel,
                iterations, cv::GC_INIT_WITH_RECT);
    return r;
}

// Full-size GrabCut labels from the downscaled result: certain foreground / background farther
// than `band` downscaled pixels from its outline, probable within (upscaled by nearest
// neighbour: the band holds the outline wherever between the coarse pixels it lies).
cv::Mat bandLabels(const cv::Mat& smallLabels, cv::Size full, int band) {
    cv::Mat fg(smallLabels.size(), CV_8U), inner, outer;
    for (int y = 0; y < smallLabels.rows; ++y)
        for (int x = 0; x < smallLabels.cols; ++x)
            fg.at<uint8_t>(y, x) = isForeground(smallLabels.at<uint8_t>(y, x)) ? 255 : 0;
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
    cv::erode(fg, inner, kernel, cv::Point(-1, -1), band);
    cv::dilate(fg, outer, kernel, cv::Point(-1, -1), band);
    cv::Mat small(fg.size(), CV_8U);
    for (int y = 0; y < fg.rows; ++y) {
        const uint8_t *f = fg.ptr<uint8_t>(y), *in = inner.ptr<uint8_t>(y), *out = outer.ptr<uint8_t>(y);
        uint8_t* l = small.ptr<uint8_t>(y);
        for (int x = 0; x < fg.cols; ++x)
            l[x] = in[x] ? cv::GC_FGD : !out[x] ? cv::GC_BGD : f[x] ? cv::GC_PR_FGD : cv::GC_PR_BGD;
    }
    cv::Mat labels;
    cv::resize(small, labels, full, 0, 0, cv::INTER_NEAREST);
    return labels;
}

bool probable(uint8_t label) { return label == cv::GC_PR_FGD || label == cv::GC_PR_BGD; }

// One graph cut of a window of the band with the downscaled image's colour models (frozen:
// no model is learnt per window): `labels` inside `tile` takes the result; the context around
// it gives the cut its neighbours.
void refineWindow(const cv::Mat& bgr, const cv::Mat& before, cv::Mat& labels, cv::Rect tile,
                  int margin, const GrabCutResult& models) {
    const cv::Rect window = (tile + cv::Size(2 * margin, 2 * margin) - cv::Point(margin, margin)) &
                            cv::Rect(0, 0, bgr.cols, bgr.rows);
    cv::Mat mask = before(window).clone();
    cv::Mat bgModel = models.bgModel.clone(), fgModel = models.fgModel.clone();
    try {
        cv::grabCut(bgr(window), mask, cv::Rect(), bgModel, fgModel, 1,
                    cv::GC_EVAL_FREEZE_MODEL);
    } catch (const cv::Exception&) {
        return;  // a degenerate colour model: the upscaled outline stays
    }
    mask(tile - window.tl()).copyTo(labels(tile));
}

// Refines the probable pixels of `labels` at full size, window by window.
void refineBand(const cv::Mat& bgr, cv::Mat& labels, int band, const GrabCutResult& models,
                int threads) {
    const cv::Mat before = labels.clone();
    std::vector<cv::Rect> tiles;
    for (int y = 0; y < bgr.rows; y += kWindow)
        for (int x = 0; x < bgr.cols; x += kWindow) {
            const cv::Rect tile = cv::Rect(x, y, kWindow, kWindow) & cv::Rect(0, 0, bgr.cols, bgr.rows);
            const cv::Mat t = before(tile);
            bool open = false;
            for (int r = 0; r < t.rows && !open; ++r)
                for (int c = 0; c < t.cols && !open; ++c) open = probable(t.at<uint8_t>(r, c));
            if (open) tiles.push_back(tile);
        }
    const int margin = std::max(8, band);
    parallelFor(static_cast<int>(tiles.size()), threadsToUse(threads), [&](int k, int) {
        refineWindow(bgr, before, labels, tiles[static_cast<size_t>(k)], margin, models);
    });
}

}  // namespace

namespace {

// grabCutForeground, OpenCV's allocation failures left as they are.
std::vector<uint8_t> foregroundStages(const RgbaImage& image, int iterations, int threads) {
    const int W = image.width, H = image.height;
    if (W < 8 || H < 8) throw Error("image too small for foreground extraction (needs 8x8 or more)");
    const cv::Mat bgr = toBgr8(image);
    const double pixels = static_cast<double>(W) * H;
    cv::Mat labels;
    if (pixels <= kGrabCutWorkPixels) {
        labels = grabCutInRect(bgr, iterations).labels;
    } else {
        const double f = std::sqrt(kGrabCutWorkPixels / pixels);
        const cv::Size small(std::max(8, static_cast<int>(W * f)), std::max(8, static_cast<int>(H * f)));
        cv::Mat smallBgr;
        cv::resize(bgr, smallBgr, small, 0, 0, cv::INTER_AREA);
        const double scale = static_cast<double>(W) / small.width;
        const int band = 2;  // downscaled pixels each side of the outline
        const GrabCutResult coarse = grabCutInRect(smallBgr, iterations);
        labels = bandLabels(coarse.labels, bgr.size(), band);
        refineBand(bgr, labels, static_cast<int>(std::ceil(band * scale)), coarse, threads);
    }
    std::vector<uint8_t> mask(static_cast<size_t>(W) * H);
    for (int y = 0; y < H; ++y) {
        const uint8_t* l = labels.ptr<uint8_t>(y);
        for (int x = 0; x < W; ++x) mask[static_cast<size_t>(y) * W + x] = isForeground(l[x]) ? 1 : 0;
    }
    return mask;
}

}  // namespace

std::vector<uint8_t> grabCutForeground(const RgbaImage& image, int iterations, int threads) {
    return withOpenCvOutOfMemoryAsBadAlloc(
        [&] { return foregroundStages(image, iterations, threads); });
}

}  // namespace gm
