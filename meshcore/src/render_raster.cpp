// Micro-triangle rasterisation at pixel centres with an exact integer fill rule.
#include <algorithm>
#include <cmath>
#include <utility>

#include "render_internal.h"

namespace gm {
namespace render_detail {

namespace {

int64_t floorDiv(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// A pixel centre exactly on an edge belongs to the triangle on one side only: the edge A→B is
// inclusive when it points down, or left when horizontal. Reversing the edge flips that, and
// two triangles sharing an edge traverse it in opposite directions, so exactly one takes it.
int64_t edgeBias(int64_t dx, int64_t dy) { return (dy > 0 || (dy == 0 && dx < 0)) ? 0 : -1; }

}  // namespace

void rasterizeTriangle(const TessVertex& a, const TessVertex& b0, const TessVertex& c0, int patch,
                       const LayerRows& band, LayerSample* samples, uint8_t* kinds) {
    const int64_t half = 1 << (kSubpixelBits - 1), one = 1 << kSubpixelBits;
    const int yLo = band.originY + band.y0, yHi = band.originY + band.y1;  // output rows
    const int xLo = band.originX, xHi = band.originX + band.width;

    {
        // The centroid's pixel gets a fallback sample if nothing covers its centre.
        const int64_t cx = floorDiv(a.X + b0.X + c0.X, 3 * one);
        const int64_t cy = floorDiv(a.Y + b0.Y + c0.Y, 3 * one);
        if (cx >= xLo && cx < xHi && cy >= yLo && cy < yHi) {
            const size_t idx = static_cast<size_t>(cy - band.originY) * band.width + (cx - xLo);
            if (kinds[idx] == kNoSample) {
                kinds[idx] = kNearSample;
                samples[idx] = {patch, static_cast<float>((a.s + b0.s + c0.s) / 3),
                                static_cast<float>((a.t + b0.t + c0.t) / 3)};
            }
        }
    }

    const TessVertex* pb = &b0;
    const TessVertex* pc = &c0;
    int64_t area = (pb->X - a.X) * (pc->Y - a.Y) - (pb->Y - a.Y) * (pc->X - a.X);
    if (area == 0) return;
    if (area < 0) {  // folded patches give both orientations; paint them all
        std::swap(pb, pc);
        area = -area;
    }
    const TessVertex& b = *pb;
    const TessVertex& c = *pc;

    // Pixels whose centres (x·one + half) lie in the bounding box, clipped to the band.
    const int64_t minX = std::min({a.X, b.X, c.X}), maxX = std::max({a.X, b.X, c.X});
    const int64_t minY = std::min({a.Y, b.Y, c.Y}), maxY = std::max({a.Y, b.Y, c.Y});
    const int64_t px0 = std::max<int64_t>(floorDiv(minX - half + one - 1, one), xLo);
    const int64_t px1 = std::min<int64_t>(floorDiv(maxX - half, one), xHi - 1);
    const int64_t py0 = std::max<int64_t>(floorDiv(minY - half + one - 1, one), yLo);
    const int64_t py1 = std::min<int64_t>(floorDiv(maxY - half, one), yHi - 1);
    if (px0 > px1 || py0 > py1) return;

    // Edge functions E(P) = (B−A) × (P−A), positive inside; the weight of the vertex opposite.
    struct Edge {
        int64_t dx, dy, bias;
        const TessVertex* from;
    };
    const Edge e[3] = {{c.X - b.X, c.Y - b.Y, 0, &b},   // weight of a
                       {a.X - c.X, a.Y - c.Y, 0, &c},   // weight of b
                       {b.X - a.X, b.Y - a.Y, 0, &a}};  // weight of c
    int64_t bias[3], stepX[3], rowStart[3];
    const int64_t X0 = px0 * one + half, Y0 = py0 * one + half;
    for (int k = 0; k < 3; ++k) {
        bias[k] = edgeBias(e[k].dx, e[k].dy);
        stepX[k] = -e[k].dy * one;
        rowStart[k] = e[k].dx * (Y0 - e[k].from->Y) - e[k].dy * (X0 - e[k].from->X);
    }
    // (s,t) is affine in the pixel position: per row from the exact weights, then stepped.
    const double inv = 1.0 / static_cast<double>(area);
    const double sStep = (stepX[0] * a.s + stepX[1] * b.s + stepX[2] * c.s) * inv;
    const double tStep = (stepX[0] * a.t + stepX[1] * b.t + stepX[2] * c.t) * inv;
    for (int64_t py = py0; py <= py1; ++py) {
        int64_t w0 = rowStart[0], w1 = rowStart[1], w2 = rowStart[2];
        const double sRow = (w0 * a.s + w1 * b.s + w2 * c.s) * inv;
        const double tRow = (w0 * a.t + w1 * b.t + w2 * c.t) * inv;
        size_t idx = static_cast<size_t>(py - band.originY) * band.width + (px0 - xLo);
        for (int64_t px = px0; px <= px1; ++px, ++idx) {
            if (w0 + bias[0] >= 0 && w1 + bias[1] >= 0 && w2 + bias[2] >= 0) {
                const double k = static_cast<double>(px - px0);
                const double s = std::min(1.0, std::max(0.0, sRow + k * sStep));
                const double t = std::min(1.0, std::max(0.0, tRow + k * tStep));
                samples[idx] = {patch, static_cast<float>(s), static_cast<float>(t)};
                kinds[idx] = kCentreSample;
            }
            w0 += stepX[0];
            w1 += stepX[1];
            w2 += stepX[2];
        }
        for (int k = 0; k < 3; ++k) rowStart[k] += e[k].dx * one;
    }
}

}  // namespace render_detail
}  // namespace gm
