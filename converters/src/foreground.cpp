#include "converters/foreground.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "meshcore/error.h"

namespace gm {

const char* maskSourceName(MaskSource s) {
    switch (s) {
        case MaskSource::MaskImage: return "mask";
        case MaskSource::Alpha: return "alpha";
        case MaskSource::GrabCut: return "grabcut";
    }
    return "?";
}

std::vector<uint8_t> grabCutForeground(const RgbaImage& image, int iterations) {
    const int W = image.width, H = image.height;
    if (W < 8 || H < 8) throw Error("image too small for foreground extraction (needs 8x8 or more)");
    cv::Mat bgr(H, W, CV_8UC3);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const float* p = image.at(x, y);
            auto& d = bgr.at<cv::Vec3b>(y, x);
            for (int c = 0; c < 3; ++c)
                d[2 - c] = static_cast<uint8_t>(std::lround(std::clamp(p[c], 0.f, 1.f) * 255));
        }
    const int mx = std::max(1, W / 20), my = std::max(1, H / 20);
    cv::Rect rect(mx, my, W - 2 * mx, H - 2 * my);
    cv::Mat labels, bgModel, fgModel;
    cv::grabCut(bgr, labels, rect, bgModel, fgModel, iterations, cv::GC_INIT_WITH_RECT);
    std::vector<uint8_t> mask(static_cast<size_t>(W) * H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const uint8_t l = labels.at<uint8_t>(y, x);
            mask[static_cast<size_t>(y) * W + x] = (l == cv::GC_FGD || l == cv::GC_PR_FGD) ? 1 : 0;
        }
    return mask;
}

ObjectMask objectMask(const RgbaImage& image, const RgbaImage* maskImage,
                      const std::string& imagePath, const std::string& maskPath) {
    ObjectMask m;
    m.width = image.width;
    m.height = image.height;
    const size_t n = static_cast<size_t>(image.width) * image.height;
    m.mask.assign(n, 0);
    if (maskImage) {
        if (maskImage->width != image.width || maskImage->height != image.height)
            throw Error("mask is " + std::to_string(maskImage->width) + "x" +
                            std::to_string(maskImage->height) + " but the image is " +
                            std::to_string(image.width) + "x" + std::to_string(image.height),
                        maskPath);
        m.source = MaskSource::MaskImage;
        for (size_t k = 0; k < n; ++k) {
            const float* p = &maskImage->pixels[k * 4];
            const float grey = (p[0] + p[1] + p[2]) / 3.f;
            m.mask[k] = (grey >= 0.5f && p[3] >= 0.5f) ? 1 : 0;
        }
        if (std::find(m.mask.begin(), m.mask.end(), 1) == m.mask.end())
            throw Error("mask is empty (no white pixels)", maskPath);
        return m;
    }
    // The alpha channel says where the object is when it makes some pixels transparent: a
    // thousandth of the image at least, so that an opaque picture with a few see-through corner
    // pixels (rounded corners, an editor's artefact) still goes to foreground extraction.
    size_t transparent = 0;
    for (size_t k = 0; k < n; ++k) transparent += image.pixels[k * 4 + 3] < 0.5f;
    if (transparent > 0 && transparent * 1000 >= n) {
        m.source = MaskSource::Alpha;
        for (size_t k = 0; k < n; ++k) m.mask[k] = image.pixels[k * 4 + 3] >= 0.5f ? 1 : 0;
        if (std::find(m.mask.begin(), m.mask.end(), 1) == m.mask.end())
            throw Error("image is fully transparent: no object to convert", imagePath);
        return m;
    }
    m.source = MaskSource::GrabCut;
    m.mask = grabCutForeground(image);
    if (std::find(m.mask.begin(), m.mask.end(), 1) == m.mask.end())
        throw Error("foreground extraction found no object (give one with --mask)", imagePath);
    return m;
}

}  // namespace gm
