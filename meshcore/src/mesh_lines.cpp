#include "meshcore/mesh_lines.h"

#include <algorithm>
#include <cmath>

#include "meshcore/evaluate.h"

namespace gm {

namespace {

// Blends `color` with weight w (0–1, times the colour's alpha) into pixel (x, y).
void blend(RgbaImage& img, int x, int y, const std::array<float, 4>& color, double w) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
    const float a = static_cast<float>(std::clamp(w, 0.0, 1.0)) * color[3];
    if (a <= 0) return;
    float* d = &img.pixels[(static_cast<size_t>(y) * img.width + x) * 4];
    const float outA = a + d[3] * (1 - a);
    for (int c = 0; c < 3; ++c)
        d[c] = outA > 0 ? (color[c] * a + d[c] * d[3] * (1 - a)) / outA : 0.f;
    d[3] = outA;
}

// One point of a line: its weight spread bilinearly over the four pixels around it (output
// pixel centres at +0.5), so a densely sampled curve reads as a 1-pixel anti-aliased line.
void splat(RgbaImage& img, Vec2 p, const std::array<float, 4>& color, double w) {
    const double fx = p.x - 0.5, fy = p.y - 0.5;
    const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
    const double ax = fx - x0, ay = fy - y0;
    blend(img, x0, y0, color, w * (1 - ax) * (1 - ay));
    blend(img, x0 + 1, y0, color, w * ax * (1 - ay));
    blend(img, x0, y0 + 1, color, w * (1 - ax) * ay);
    blend(img, x0 + 1, y0 + 1, color, w * ax * ay);
}

// The edge of patch h at fixed t (alongS) or fixed s, in output pixels.
void drawEdge(RgbaImage& img, const PatchHermite& h, bool alongS, double fixed, double scale,
              const std::array<float, 4>& color) {
    auto at = [&](double a) {
        const Vec2 p = (alongS ? evaluatePatch(h, a, fixed) : evaluatePatch(h, fixed, a)).pos;
        return scale * p;
    };
    // Enough samples that neighbours are about half an output pixel apart.
    double length = 0;
    Vec2 prev = at(0);
    for (int k = 1; k <= 16; ++k) {
        const Vec2 q = at(k / 16.0);
        length += norm(q - prev);
        prev = q;
    }
    if (!std::isfinite(length)) return;
    const int n = std::clamp(static_cast<int>(std::ceil(2 * length)), 2, 1 << 16);
    // Each sample carries half the line's ink per pixel of length (samples are 1/2 px apart).
    const double w = std::min(1.0, length / n);
    for (int k = 0; k <= n; ++k) splat(img, at(double(k) / n), color, 2 * w);
}

}  // namespace

void drawMeshLines(RgbaImage& image, const Document& doc, double scale,
                   const std::array<float, 4>& color) {
    for (const GradientMesh& m : doc.meshes) {
        const int C = m.columns(), R = m.rows();
        for (int j = 0; j < R; ++j)
            for (int i = 0; i < C; ++i) {
                const PatchHermite h = patchHermite(m, i, j);
                // Top and left edges of every patch, plus the bottom and right ones of the last
                // row and column; slit rows have a bottom edge above and a top edge below.
                drawEdge(image, h, true, 0.0, scale, color);
                drawEdge(image, h, false, 0.0, scale, color);
                if (j == R - 1) drawEdge(image, h, true, 1.0, scale, color);
                if (i == C - 1) drawEdge(image, h, false, 1.0, scale, color);
                for (const Slit& s : m.slits)
                    if (j + 1 == s.row && i >= s.i0 && i < s.i1)
                        drawEdge(image, h, true, 1.0, scale, color);
            }
        for (int j = 0; j <= R; ++j)
            for (int i = 0; i <= C; ++i) {
                const Vec2 p = scale * m.node(i, j).pos;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        blend(image, static_cast<int>(std::floor(p.x)) + dx,
                              static_cast<int>(std::floor(p.y)) + dy, color, 1.0);
            }
    }
}

}  // namespace gm
