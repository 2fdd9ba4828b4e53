// The raster re-renderer: exact Ferguson evaluation, adaptive tessellation (error below 1/255
// in colour and 1/8 px in position), anti-aliased outline, patches painted in order, holes left
// uncovered, float RGBA output at any scale.
//
// Output pixel (x, y) covers [x, x+1) x [y, y+1) in output pixels; its centre is (x+0.5, y+0.5),
// i.e. canvas point ((x+0.5)/scale, (y+0.5)/scale). Colours are the patches' bicubic colours,
// not clamped to 0–1 (overshoot is kept so that fits through `samples` stay linear; writers
// clamp). Alpha is the exact area coverage of the mesh outline (outer boundary and hole
// outlines, nonzero winding), 1 inside.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

struct RenderOptions {
    double scale = 1.0;                // output pixels per canvas pixel
    double positionTolerance = 0.125;  // output pixels
    double colorTolerance = 1.0 / 255.0;
    bool antialias = true;     // anti-aliased outline (coverage in alpha)
    bool wantSamples = false;  // fill RenderResult::samples
    int threads = 0;           // worker threads; 0: all hardware threads, 1: this one
};

// Where a pixel's colour comes from: mesh index, patch index j*C+i, and local (s,t). The pixel's
// colour is evaluatePatch(mesh, i, j, s, t).col up to float rounding (where meshes blend at a
// partly covered pixel, it is the topmost mesh's contribution).
//  - centre == true: that patch covers the pixel centre, (s,t) is the centre's parameter (up to
//    the tessellation tolerance); the topmost mesh and, within a mesh, the last patch wins.
//  - centre == false, mesh >= 0: an outline pixel (0 < alpha) whose centre lies just outside the
//    mesh; its colour is taken from the nearest covered sample, named here.
//  - mesh == -1: nothing painted (alpha 0), or a flat shape (Document::shapes) covers the pixel
//    opaquely; shapes name no sample.
struct PixelSample {
    int32_t mesh = -1;
    int32_t patch = -1;
    float s = 0, t = 0;
    bool centre = false;
};

struct RenderResult {
    RgbaImage image;                   // width = round(doc.width*scale), likewise height
    std::vector<PixelSample> samples;  // one per pixel, row-major, when wantSamples, else empty
    size_t triangles = 0;              // micro-triangles rasterised (statistics)
};

// The document's meshes and flat shapes in their paint order (FlatShape::layer); a shape is
// anti-aliased like a mesh outline.
// Throws gm::Error when the scale is not a positive finite number or the output would be larger
// than 2^21 pixels along a side, or a mesh's arrays do not match its grid.
RenderResult renderDocument(const Document& doc, const RenderOptions& options = {});

// One mesh onto a canvas of the given size (canvas pixels, before scale).
RenderResult renderMesh(const GradientMesh& mesh, int canvasWidth, int canvasHeight,
                        const RenderOptions& options = {});

}  // namespace gm
