#include "converters/foreground.h"

#include <algorithm>

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

ObjectMask objectMask(const RgbaImage& image, const RgbaImage* maskImage,
                      const std::string& imagePath, const std::string& maskPath, int threads) {
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
    m.mask = grabCutForeground(image, 5, threads);
    if (std::find(m.mask.begin(), m.mask.end(), 1) == m.mask.end())
        throw Error("foreground extraction found no object (give one with --mask)", imagePath);
    return m;
}

}  // namespace gm
