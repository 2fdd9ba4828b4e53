// Inputs of a colour fit built by hand: a region over the whole canvas and a document's render
// samples (the topmost mesh per pixel centre, as the fits use them).
#pragma once

#include <vector>

#include "converters/region.h"
#include "meshcore/render.h"

namespace gm {

inline Region wholeCanvas(int width, int height) {
    Region all;
    all.width = width;
    all.height = height;
    all.mask.assign(static_cast<size_t>(width) * height, 1);
    all.pixelCount = width * height;
    return all;
}

inline std::vector<PixelSample> fitSamples(const Document& doc) {
    RenderOptions ro;
    ro.wantSamples = true;
    ro.antialias = false;
    return renderDocument(doc, ro).samples;
}

}  // namespace gm
