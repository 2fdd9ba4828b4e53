// Where the object comes from (docs/design.md §3 step 1): a mask image, the alpha channel when it
// makes at least 0.1% of the pixels transparent (alpha < 0.5), else foreground extraction by GrabCut initialised from the image border.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meshcore/image.h"

namespace gm {

enum class MaskSource { MaskImage, Alpha, GrabCut };

struct ObjectMask {
    int width = 0, height = 0;
    std::vector<uint8_t> mask;  // 1 = object
    MaskSource source = MaskSource::Alpha;
};

const char* maskSourceName(MaskSource s);

// `maskImage` may be null. A mask image must match the image size (gm::Error naming maskPath
// otherwise); white (grey ≥ 0.5 with alpha ≥ 0.5) is object. Throws gm::Error naming imagePath
// when the resulting mask is empty. `threads` as grabCutForeground's.
ObjectMask objectMask(const RgbaImage& image, const RgbaImage* maskImage,
                      const std::string& imagePath, const std::string& maskPath,
                      int threads = 0);

// Images up to this many pixels are cut whole; larger ones on a copy downscaled to it, their
// outline then refined at full size in a band around it (grabcut_foreground.cpp).
constexpr double kGrabCutWorkPixels = 1 << 18;

// GrabCut (OpenCV) with the rectangle init: a border of ~5% of the image is background.
// `iterations` on the whole (or downscaled) image; the full-size band refinement runs on up to
// `threads` threads (0: every hardware thread).
std::vector<uint8_t> grabCutForeground(const RgbaImage& image, int iterations = 5, int threads = 0);

}  // namespace gm
