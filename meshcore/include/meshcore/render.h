// The raster re-renderer: exact Ferguson evaluation, adaptive tessellation (error below 1/255
// in colour and 1/8 px in position), anti-aliased outline, patches painted in order, holes left
// uncovered, float RGBA output at any scale.
#pragma once

#include <cstdint>
#include <vector>

#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

struct RenderOptions {
    double scale = 1.0;             // output pixels per canvas pixel
    double positionTolerance = 0.125;  // output pixels
    double colorTolerance = 1.0 / 255.0;
    bool antialias = true;           // anti-aliased outline (coverage in alpha)
    bool wantSamples = false;        // fill RenderResult::samples
};

// Which patch covers a pixel centre and where: mesh index, patch index j*C+i, and local (s,t).
struct PixelSample {
    int32_t mesh = -1;  // -1: no patch covers the pixel centre
    int32_t patch = -1;
    float s = 0, t = 0;
};

struct RenderResult {
    RgbaImage image;                   // width = round(doc.width*scale), likewise height
    std::vector<PixelSample> samples;  // one per pixel when wantSamples, else empty
};

RenderResult renderDocument(const Document& doc, const RenderOptions& options = {});

// One mesh onto a canvas of the given size (canvas pixels, before scale).
RenderResult renderMesh(const GradientMesh& mesh, int canvasWidth, int canvasHeight,
                        const RenderOptions& options = {});

}  // namespace gm
