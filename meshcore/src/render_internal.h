// Private pieces of the raster re-renderer (render.cpp): per-patch preparation and
// tessellation (render_tessellation.cpp), outline extraction and area coverage
// (render_coverage.cpp), micro-triangle rasterisation (render_raster.cpp).
//
// All coordinates here are OUTPUT pixels (canvas pixels times the scale), y down.
#pragma once

#include <cstdint>
#include <vector>

#include "meshcore/gradient_mesh.h"
#include "meshcore/render.h"

namespace gm {
namespace render_detail {

// Sub-pixel precision of the rasteriser: vertices are snapped to 1/256 pixel so that the fill
// rule can be decided exactly in integers (no pixel centre is lost or painted twice along a
// shared edge).
constexpr int kSubpixelBits = 8;
constexpr double kSubpixel = 1 << kSubpixelBits;
// Snapped coordinates are clamped to ±2^29 (±2^21 pixels): edge functions, at most 8·(2^29)²,
// then fit in int64.
constexpr double kFixedLimit = 536870912.0;
// The largest output side renderDocument accepts: pixel centres stay inside the fixed range.
constexpr int kMaxOutputSide = 1 << 21;
// Per-patch subdivision cap along s and along t: degenerate or absurdly large patches must not
// hang or exhaust memory.
constexpr int kMaxSubdivisions = 256;

// A bicubic polynomial in power form: value = Σ k[m][n] s^m t^n.
struct Poly2 {
    double k[4][4];
    double eval(double s, double t) const {
        double q[4];
        for (int m = 0; m < 4; ++m) q[m] = ((k[m][3] * t + k[m][2]) * t + k[m][1]) * t + k[m][0];
        return ((q[3] * s + q[2]) * s + q[1]) * s + q[0];
    }
};

// The colour of a patch, all channels at once: Σ k[m][n][channel] s^m t^n. Channel-minor
// storage lets the compiler vectorise Horner's rule across channels (the fourth lane is
// padding); this is the renderer's per-pixel inner loop.
struct ColorPoly {
    double k[4][4][4];
    void eval(double s, double t, float out[3]) const {
        double q[4][4];
        for (int m = 0; m < 4; ++m)
            for (int c = 0; c < 4; ++c)
                q[m][c] = ((k[m][3][c] * t + k[m][2][c]) * t + k[m][1][c]) * t + k[m][0][c];
        for (int c = 0; c < 3; ++c)
            out[c] = static_cast<float>(((q[3][c] * s + q[2][c]) * s + q[1][c]) * s + q[0][c]);
    }
};

// One patch, ready to tessellate and shade.
struct PreparedPatch {
    bool visible = false;                           // finite and overlapping the image
    int ns = 1, nt = 1;                             // subdivisions along s and t
    double minX = 0, minY = 0, maxX = 0, maxY = 0;  // control-net hull, output pixels
    PatchHermite hermite;                           // positions in output pixels
    Poly2 x, y;                                     // position, output pixels
    ColorPoly colour;                              // sRGB 0–1
};

struct PreparedMesh {
    int columns = 0, rows = 0;
    std::vector<PreparedPatch> patches;  // index j*C+i
    // horizontalCut[j*C+i]: the edge of row j between columns i and i+1 is a slit segment, so
    // the patches above and below it do not share it.
    std::vector<char> horizontalCut;
    // Bounds of all finite patches (output pixels), empty when none.
    double minX = 0, minY = 0, maxX = -1, maxY = -1;
};

// Hermite data scaled to output pixels, Bézier bounds, subdivision counts and polynomial forms
// for every patch. Patches whose hull misses [0,imageW) x [0,imageH) are marked invisible.
PreparedMesh prepareMesh(const GradientMesh& mesh, const RenderOptions& options, int imageW,
                         int imageH);

// The subdivision counts for one patch (output-pixel Hermite data).
void chooseSubdivisions(const PatchHermite& scaled, const RenderOptions& options, int& ns, int& nt);

struct TessVertex {
    int64_t X = 0, Y = 0;  // snapped position, 1/kSubpixel output pixels
    double s = 0, t = 0;   // local patch parameters
};

// A patch's micro-triangles. Vertices on an edge shared with a neighbouring patch are the
// union of both patches' subdivisions there and are computed from the edge's own data in a
// fixed order, so both patches produce bit-identical vertices: the tessellation of a mesh is
// free of T-junctions and cracks.
struct Tessellation {
    std::vector<TessVertex> vertices;
    std::vector<int> triangles;  // 3 indices each
};
void tessellatePatch(const PreparedMesh& mesh, int patch, Tessellation& out);

// Appends the cubic Bézier q0..q3 (without q0, which the previous curve ended on) flattened so
// that no chord strays more than `tolerance` from the curve.
void flattenCubic(Vec2 q0, Vec2 q1, Vec2 q2, Vec2 q3, double tolerance, std::vector<Vec2>& out);

// Closed polylines of the mesh outline (outer loop, then one loop per slit), output pixels.
// Loops are oriented consistently: the hole loops wind opposite to the outer loop wherever the
// mesh does not fold, so that nonzero-winding coverage leaves holes empty.
std::vector<std::vector<Vec2>> outlineLoops(const GradientMesh& mesh, double scale,
                                            double tolerance);

// A buffer of rows of a mesh's layer: buffer pixel (x, y) is output pixel (originX + x,
// originY + y); rows [y0, y1) of the buffer are being worked on; each row is `width` wide.
struct LayerRows {
    int originX = 0, originY = 0, width = 0;
    int y0 = 0, y1 = 0;
};

// Signed area coverage of the loops (nonzero rule, clamped to [0,1]) for rows [y0, y1) into
// alpha (the row buffer). `accumulator` is scratch.
void accumulateCoverage(const std::vector<std::vector<Vec2>>& loops, const LayerRows& band,
                        std::vector<double>& accumulator, float* alpha);

// Per buffer pixel: which patch painted its centre and where.
enum SampleKind : uint8_t {
    kNoSample = 0,
    kNearSample = 1,      // a triangle's centroid falls in the pixel but covers no centre
    kCentreSample = 2,    // a triangle covers the centre
    kBorrowedSample = 3,  // copied from the nearest pixel that had one
};
struct LayerSample {
    int32_t patch;
    float s, t;
};

// Rasterises one triangle into the band with the fill rule at pixel centres; later calls
// overwrite earlier ones. Also leaves a kNearSample at the centroid's pixel if that pixel has
// none, so that slivers thinner than a pixel still have a colour to lend to their outline.
void rasterizeTriangle(const TessVertex& a, const TessVertex& b, const TessVertex& c, int patch,
                       const LayerRows& band, LayerSample* samples, uint8_t* kinds);

// Paints a flat shape (anti-aliased, nonzero rule) over the image. When `samples` is not null
// (one per image pixel), the pixels the shape covers opaquely lose their mesh sample: no mesh
// shows there.
void renderShape(const FlatShape& shape, const RenderOptions& options, RgbaImage& image,
                 std::vector<PixelSample>* samples);

}  // namespace render_detail
}  // namespace gm
